"""Helpers of the magbubble package: override values as ``--set`` text, typed columns as a
DataFrame, progress bars. Nothing here computes physics."""

from __future__ import annotations

import numbers
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence

import numpy as np
import pandas as pd


def toml_text(value: Any) -> str:
    """``value`` as the text of ``--set key=<text>``: booleans as ``true``/``false``, numbers in
    a form that reads back exactly (``repr`` of a float), strings as written (a bare word such
    as ``radau5`` or a quoted TOML string), lists as TOML arrays, dicts as inline tables."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        return repr(float(value))
    if isinstance(value, str):
        return value
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{k} = {toml_text(v)}" for k, v in value.items()) + " }"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_text(v) for v in value) + "]"
    raise TypeError(f"cannot write {type(value).__name__} {value!r} as a scene value")


def override_list(overrides: Optional[Mapping[str, Any]]) -> list:
    """``{"drive.amplitude": 0.3}`` → ``["drive.amplitude=0.3"]`` (the ``--set`` strings)."""
    if overrides is None:
        return []
    if isinstance(overrides, (str, bytes)) or not isinstance(overrides, Mapping):
        raise TypeError("overrides must be a dict {key: value}, e.g. {'drive.amplitude': 0.3}")
    out = []
    for key, value in overrides.items():
        if not isinstance(key, str):
            raise TypeError(f"override key {key!r} is not a string")
        out.append(f"{key}={toml_text(value)}")
    return out


def freq_arg(freq: Any) -> Any:
    """The frequency axis: the CLI's text (``"0.5e6:2e6:16:log"``, ``"1e6,2e6"``) or a list of
    numbers [Hz]."""
    if isinstance(freq, str):
        return freq
    return [float(f) for f in _iterable(freq, "freq")]


def family_arg(family: Any) -> Any:
    """The family: ``"KEY=V1,V2"``, or ``{KEY: [V1, V2]}`` (one key) as (key, [``--set`` texts])."""
    if family is None or isinstance(family, str):
        return family
    if not isinstance(family, Mapping) or len(family) != 1:
        raise TypeError("family must be 'KEY=V1,V2,…' or a dict with one key {KEY: [V1, V2, …]}")
    ((key, values),) = family.items()
    return (str(key), [toml_text(v) for v in _iterable(values, "family values")])


def _iterable(x: Any, what: str) -> Iterable:
    try:
        return list(x)
    except TypeError:
        raise TypeError(f"{what}: expected a list of numbers, got {type(x).__name__}") from None


def frame(columns: Sequence[tuple]) -> pd.DataFrame:
    """A DataFrame of the extension's typed columns ``(name, kind, data)``: ``int`` and ``float``
    columns are numpy arrays (used as they are), a ``text`` column is ``(codes, values)`` and
    becomes an object column holding the distinct values once each."""
    data = {}
    for name, kind, values in columns:
        if kind == "text":
            codes, distinct = values
            table = np.empty(len(distinct), dtype=object)
            table[:] = distinct
            data[name] = pd.Series(table[codes], dtype=object, copy=False)
        else:
            data[name] = pd.Series(values, copy=False)
    return pd.DataFrame(data, copy=False)


def progress_bar(enabled: Any, desc: str, unit: str, scale: float = 1.0) -> tuple:
    """(callback(done, total), close()) of a tqdm bar when ``enabled`` is true and tqdm is
    installed, else (None, a no-op). ``scale`` multiplies done and total (seconds → µs).
    A callable ``enabled`` is itself the callback (called every ~50 ms with (done, total));
    an exception it raises stops the call like a KeyboardInterrupt."""
    if callable(enabled):
        return enabled, lambda: None
    if not enabled:
        return None, lambda: None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None, lambda: None
    bar = tqdm(desc=desc, unit=unit, total=None, leave=False)

    def shown(x: float):
        return int(x) if scale == 1.0 else round(x * scale, 3)

    def update(done: float, total: float) -> None:
        if total == total and bar.total != shown(total):  # total is NaN until known
            bar.total = shown(total)
        bar.n = shown(done)
        bar.refresh()

    return update, bar.close


Callback = Optional[Callable[[float, float], None]]
