"""Populations (issue 33, docs/population.md): ``population`` and ``attenuation``."""

from __future__ import annotations

import os
import tempfile
import warnings
from typing import Any, Mapping, Optional, Sequence, Tuple, Union

import pandas as pd

from . import _magbubble as _ext
from ._util import frame, freq_arg, progress_bar


def population(
    scene_or_path: Any,
    freq: Union[str, Sequence[float]],
    overrides: Optional[Mapping[str, Any]] = None,
    *,
    range: Tuple[float, float] = (0.0, 1.0),
    eps_points: int = 101,
    tol: float = 1e-3,
    abs_tol: Optional[float] = None,
    scan: int = 8,
    window_check: bool = True,
    out: Optional[Any] = None,
    shard: Optional[str] = None,
    executor: Any = None,
    shards: Optional[int] = None,
    progress: Any = True,
) -> pd.DataFrame:
    """A population's stability map (``magbubble population``): the rows of ``population.csv``
    (``frequency_hz``, ``eps_p``, ``fraction_unstable``); ``df.attrs["bins"]`` is
    ``population_bins.csv`` (``frequency_hz``, ``radius``, ``weight``, ``critical_eps_p``,
    ``mode``, ``outcome``, ``windows``, ``note``). The scene needs a ``[population]`` section.

    Arguments as the CLI's (``range`` is the ε_p search range and grid). With ``out`` the files
    are written there and a rerun resumes; ``shard="i/n"`` computes one shard (the DataFrames are
    then empty: merge the shards). ``executor``: any ``concurrent.futures.Executor`` (a process
    pool, ``dask.distributed``'s ``Client.get_executor()``, submitit's): the points are split into
    ``shards`` shards run there and merged; the result equals the local one bit for bit.
    ``df.attrs``: ``bins``, ``csv``, ``computed``, ``resumed``, ``failed``, ``multi_window``.
    """
    from . import _scene
    from ._shards import run_sharded

    scene = _scene(scene_or_path, overrides)
    kwargs = dict(range=range, eps_points=eps_points, tol=tol, abs_tol=abs_tol, scan=scan, window_check=window_check)
    if executor is not None:
        return run_sharded(executor, "population", scene, (freq,), kwargs, out, shards, progress)
    lo, hi = range
    update, close = progress_bar(progress, "population", "point")
    with tempfile.TemporaryDirectory(prefix="magbubble-") as tmp:
        out_dir = os.fspath(out) if out is not None else os.path.join(tmp, "out")
        try:
            path, computed, resumed, bins, fraction, failed, multi = _ext.population(
                scene._inner, freq_arg(freq), out_dir, (float(lo), float(hi)), int(eps_points), float(tol),
                None if abs_tol is None else float(abs_tol), int(scan), bool(window_check), shard, update,
            )
        finally:
            close()
    names = ["frequency_hz", "eps_p", "fraction_unstable"]
    df = pd.DataFrame(dict(zip(names, fraction))) if fraction is not None else pd.DataFrame(columns=names)
    bins_df = frame(bins) if bins is not None else pd.DataFrame()
    df.attrs.update(bins=bins_df, csv=[path] if out is not None else [], computed=computed, resumed=resumed,
                    failed=[failed] if failed else [], multi_window=list(multi))
    if failed:
        warnings.warn(failed, RuntimeWarning, stacklevel=2)
    return df


def attenuation(
    scene_or_path: Any,
    freq: Union[str, Sequence[float]],
    overrides: Optional[Mapping[str, Any]] = None,
    *,
    out: Optional[Any] = None,
    shard: Optional[str] = None,
    progress: Any = False,
) -> pd.DataFrame:
    """A population's linear attenuation and backscatter (``magbubble attenuation``): the rows
    of ``attenuation.csv`` (``frequency_hz``, ``attenuation_db_per_cm``,
    ``backscatter_per_m_sr``). The scene needs ``[population]`` with ``concentration`` and
    ``liquid.sound_speed``. ``out``/``shard`` as :func:`population`."""
    from . import _scene

    scene = _scene(scene_or_path, overrides)
    update, close = progress_bar(progress, "attenuation", "frequency")
    with tempfile.TemporaryDirectory(prefix="magbubble-") as tmp:
        out_dir = os.fspath(out) if out is not None else os.path.join(tmp, "out")
        try:
            path, computed, resumed, cols, failed = _ext.attenuation(scene._inner, freq_arg(freq), out_dir, shard, update)
        finally:
            close()
    names = ["frequency_hz", "attenuation_db_per_cm", "backscatter_per_m_sr"]
    df = pd.DataFrame(dict(zip(names, cols))) if cols is not None else pd.DataFrame(columns=names)
    df.attrs.update(csv=[path] if out is not None else [], computed=computed, resumed=resumed, failed=[failed] if failed else [])
    if failed:
        warnings.warn(failed, RuntimeWarning, stacklevel=2)
    return df
