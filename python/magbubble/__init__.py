"""magbubble — radial and non-spherical oscillations of a lipid-coated magnetic microbubble.

The Python front of the Rust core (the same code as the ``magbubble`` command line; nothing is
re-implemented here). Scenes are TOML files (``docs/scenes.md``); every function takes a
:class:`Scene` or a path, and ``overrides={"drive.amplitude": 0.3, ...}`` with the validation and
messages of ``--set``. See ``docs/python.md``.

>>> import magbubble as mb
>>> run = mb.run("scenes/coil_static.toml", overrides={"run.duration": 5e-6})
>>> run.status, run.series.columns[:4].tolist()
('completed', ['t', 'R', 'a2', 'b2'])
"""

from __future__ import annotations

import os
import tempfile
import warnings
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import pandas as pd

from . import _magbubble as _ext
from ._util import family_arg, frame, freq_arg, override_list, progress_bar, toml_text

__all__ = ["Scene", "Run", "Accuracy", "run", "modes", "floquet", "stability", "sweep", "accuracy", "coefficients", "response", "KMAX", "population", "attenuation"]
__all__ += ["Fit", "fit"]  # issue 32
__version__ = "0.1.0"

#: The largest mode order of the generated coupling tables (build setting MAGBUBBLE_KMAX).
KMAX: int = _ext.KMAX

PathLike = Union[str, "os.PathLike[str]"]


class Scene:
    """A validated scene: the TOML tree (overrides applied) and every resolved parameter.

    Make one with :meth:`Scene.load` or :meth:`Scene.from_toml`; :meth:`with_overrides` returns a
    new scene. An invalid scene raises ``ValueError`` with every problem (key, value, reason),
    the message the CLI prints after ``error:``.
    """

    __slots__ = ("_inner",)

    def __init__(self, inner: "_ext.Scene") -> None:
        self._inner = inner

    @classmethod
    def load(cls, path: PathLike, overrides: Optional[Mapping[str, Any]] = None) -> "Scene":
        """Reads a scene file (TOML), with overrides validated together with the file as
        ``magbubble run PATH --set key=value`` does."""
        return cls(_ext.Scene.load(os.fspath(path), override_list(overrides)))

    @classmethod
    def from_toml(cls, text: str, origin: str = "<string>") -> "Scene":
        """A scene from TOML text; ``origin`` names it in error messages and summaries."""
        return cls(_ext.Scene.from_toml(text, origin))

    def with_overrides(self, overrides: Mapping[str, Any]) -> "Scene":
        """A new scene with keys set, e.g. ``{"drive.amplitude": 0.3, "modes.max_order": 8}``:
        each value is written as ``--set key=value`` text (numbers exactly, ``True`` as ``true``,
        strings as written) and validated as ``--set`` is."""
        return Scene(self._inner.with_set(override_list(overrides)))

    def to_toml(self) -> str:
        """The scene as TOML text (overrides applied); :meth:`from_toml` reads it back."""
        return self._inner.to_toml()

    def resolved(self) -> Dict[str, Any]:
        """Every resolved parameter (defaults applied, SI units): ``summary.json``'s ``scene``."""
        return self._inner.resolved()

    @property
    def origin(self) -> str:
        """The file the scene came from (or the ``origin`` of :meth:`from_toml`)."""
        return self._inner.origin

    @property
    def overrides(self) -> List[str]:
        """The overrides applied since the file, as ``key=value`` strings."""
        return self._inner.overrides

    def __repr__(self) -> str:
        return repr(self._inner)


SceneOrPath = Union[Scene, str, "os.PathLike[str]"]


def _scene(scene_or_path: SceneOrPath, overrides: Optional[Mapping[str, Any]]) -> Scene:
    if isinstance(scene_or_path, Scene):
        return scene_or_path.with_overrides(overrides) if overrides else scene_or_path
    if isinstance(scene_or_path, (str, os.PathLike)):
        return Scene.load(scene_or_path, overrides)
    raise TypeError(f"expected a Scene or a path to a scene file, got {type(scene_or_path).__name__}")


class Run:
    """One simulated scene (``magbubble run``).

    - ``series``: DataFrame with the columns of ``series.csv`` (``t, R, a2, b2, …``, SI units;
      a last column ``p_b`` [Pa], the bubble pressure, with ``gas.thermal = "reduced"``), the
      values bit for bit those the CLI writes;
    - ``summary``: the dict of ``summary.json``;
    - ``status``: ``"completed"``, ``"blow_up"`` or ``"failed"`` (details in ``summary["status"]``);
    - ``integrator``: which method ran and why (``summary["integrator"]``);
    - ``echo`` (scenes with ``[echo]``, else None): DataFrame with the columns of ``echo.csv``
      (``t``, then the scattered pressure ``p_<distance>m_<angle>deg`` [Pa] per point);
    - ``spectrum`` (with ``[echo]``, else None): DataFrame with the columns of ``spectrum.csv``
      (``frequency_hz``, then ``<point>_db`` [dB re 1 Pa]); the levels are ``summary["echo"]``.
    """

    __slots__ = ("series", "summary", "scene", "echo", "spectrum")

    def __init__(
        self,
        series: pd.DataFrame,
        summary: Dict[str, Any],
        scene: Scene,
        echo: Optional[pd.DataFrame] = None,
        spectrum: Optional[pd.DataFrame] = None,
    ) -> None:
        self.series = series
        self.summary = summary
        self.scene = scene
        self.echo = echo
        self.spectrum = spectrum

    @property
    def status(self) -> str:
        s = self.summary["status"]
        return s if isinstance(s, str) else next(iter(s))

    @property
    def blow_up(self) -> Optional[Dict[str, Any]]:
        """``{"t": seconds, "mode": "a16"}`` for a blow-up, else None."""
        s = self.summary["status"]
        return s.get("blow_up") if isinstance(s, dict) else None

    @property
    def integrator(self) -> Optional[Dict[str, Any]]:
        """Which integrator ran and why (``summary["integrator"]``, issue 34): ``method``
        (e.g. ``"dop853"``), ``chosen`` (``"auto"`` or ``"scene"``), ``reason`` and
        ``spectral_radius_per_s`` (the stiffness estimate, 1/s)."""
        return self.summary.get("integrator")

    def __repr__(self) -> str:
        return f"Run({self.scene.origin!r}, status={self.status!r}, rows={len(self.series)})"


Progress = Union[bool, Callable[[float, float], None]]


def run(scene_or_path: SceneOrPath, overrides: Optional[Mapping[str, Any]] = None, *, progress: Progress = True) -> Run:
    """Simulates a scene (``magbubble run``). Releases the GIL; a tqdm bar (if tqdm is installed
    and ``progress``) shows the simulated time (or ``progress(t, duration)`` is called, every
    ~50 ms, when it is a function); KeyboardInterrupt stops the run. A blow-up or a
    failed integration is a status, not an exception; a model that cannot be built raises
    ValueError."""
    scene = _scene(scene_or_path, overrides)
    update, close = progress_bar(progress, "run", "µs", 1e6)
    try:
        header, data, summary, echo = _ext.run(scene._inner, update)
    finally:
        close()
    series = pd.DataFrame(data, columns=header, copy=False)
    if echo is None:
        return Run(series, summary, scene)
    return Run(series, summary, scene, frame(echo[0]), frame(echo[1]))


def response(
    scene_or_path: SceneOrPath,
    freq: Union[str, Sequence[float]],
    overrides: Optional[Mapping[str, Any]] = None,
) -> pd.DataFrame:
    """The linear radial response (``magbubble response``): one row per frequency with the
    columns of ``response.csv`` (``frequency_hz, amplitude_m_per_pa, phase_rad, delta_total,
    delta_liquid_viscosity, delta_radiation, delta_shell_viscosity, delta_other, sigma_s_m2,
    sigma_e_m2``; ``sigma_e_m2`` NaN without ``liquid.sound_speed``). ``freq``: ``"A:B:N"`` or
    ``"A:B:N:log"`` (as ``--freq``) or a sequence of frequencies [Hz]. ``attrs`` holds
    ``natural_frequency_hz``, ``resonance_frequency_hz`` (the largest amplitude on the grid)
    and ``damping_rates_per_s`` (by source, as in ``response.json``)."""
    scene = _scene(scene_or_path, overrides)
    if not isinstance(freq, str):
        freq = [float(f) for f in freq]
    columns, natural, resonance, rates = _ext.response(scene._inner, freq)
    df = frame(columns)
    df.attrs.update(natural_frequency_hz=natural, resonance_frequency_hz=resonance, damping_rates_per_s=rates)
    return df


def modes(
    scene_or_path: SceneOrPath,
    kmax: Optional[int] = None,
    *,
    damped: bool = False,
    overrides: Optional[Mapping[str, Any]] = None,
) -> Dict[str, Any]:
    """Natural frequencies (``magbubble modes --json``; ``damped``: ``--damped --json``)."""
    scene = _scene(scene_or_path, overrides)
    return _ext.modes(scene._inner, kmax, damped)


def floquet(
    scene_or_path: SceneOrPath,
    *,
    steps: int = 400,
    variant: str = "orbit",
    overrides: Optional[Mapping[str, Any]] = None,
) -> Dict[str, Any]:
    """Floquet multipliers of the periodic orbit (``magbubble floquet --json``): the report with
    ``"status": "ok"``, or the CLI's status object ``{"status": "error", "kind", "message"}``
    when the analysis fails (no periodic orbit, …). Its warnings (not converged in ``steps``)
    are also issued as Python warnings. A bad scene, ``steps`` or ``variant`` raises ValueError."""
    scene = _scene(scene_or_path, overrides)
    result = _ext.floquet(scene._inner, steps, variant)
    for w in result.get("warnings", []):
        warnings.warn(w, RuntimeWarning, stacklevel=2)
    return result


class Accuracy:
    """What accuracy costs in time (``magbubble accuracy``), as DataFrames.

    Time-series study (the default):

    - ``ladders``: one row per rung, the columns of ``accuracy.csv`` (``method, setting, e_r,
      e_a, error, wall_seconds, rhs_evals, steps, rejected``) and ``status``;
    - ``orders``: per method the observed order against the step (``order_dt``) and against
      the work (``order_work``; None where the work barely changes), and ``work_ratio``;
    - ``sizes``: the mode and grid ladders, the columns of ``sizes.csv`` and ``status``.

    Critical-ε_p study (``critical=`` a frequency): ``rungs``, one row per search (the
    references first, error 0), the columns of ``critical.csv`` plus ``closure`` and ``outcome``.

    ``report`` is the whole dict (``accuracy.json`` / ``critical.json``).
    """

    __slots__ = ("report", "ladders", "orders", "sizes", "rungs")

    def __init__(self, report: Dict[str, Any]) -> None:
        self.report = report
        self.ladders = self.orders = self.sizes = self.rungs = None
        if "ladders" in report:
            rows, orders = [], []
            for lad in report["ladders"]:
                for r in lad["rungs"]:
                    st = r["stats"]
                    rows.append((lad["method"], r["setting"], r["e_r"], r["e_a"], r["error"], r["wall_seconds"],
                                 st["rhs_evals"], st["steps"], st["rejected"], r["status"]))
                orders.append((lad["method"], lad["setting_name"], lad["order_dt"], lad["order_work"], lad["work_ratio"]))
            self.ladders = pd.DataFrame(rows, columns=["method", "setting", "e_r", "e_a", "error", "wall_seconds",
                                                       "rhs_evals", "steps", "rejected", "status"])
            self.orders = pd.DataFrame(orders, columns=["method", "setting_name", "order_dt", "order_work", "work_ratio"])
            sizes = [(label, r["size"], r["wall_seconds"], r["stats"]["rhs_evals"], r["stats"]["steps"],
                      r["delta_r"], r["delta_a2"], r["status"])
                     for label in ("modes", "grid") for r in report[label]]
            self.sizes = pd.DataFrame(sizes, columns=["ladder", "size", "wall_seconds", "rhs_evals", "steps",
                                                      "delta_r", "delta_a2", "status"])
        else:
            rows = [(r["ladder"], r["closure"], r["setting"], r["critical"], r["error"], r["wall_seconds"],
                     r["evaluations"], r["outcome"]) for r in report["references"] + report["rungs"]]
            self.rungs = pd.DataFrame(rows, columns=["ladder", "closure", "setting", "critical", "error",
                                                     "wall_seconds", "evaluations", "outcome"])

    def __repr__(self) -> str:
        if self.ladders is not None:
            return f"Accuracy(methods={list(self.orders['method'])}, rungs={len(self.ladders)})"
        return f"Accuracy(critical, searches={len(self.rungs)})"


def accuracy(
    scene_or_path: SceneOrPath,
    overrides: Optional[Mapping[str, Any]] = None,
    *,
    quick: bool = False,
    repeats: Optional[int] = None,
    duration: Optional[float] = None,
    critical: Optional[float] = None,
    progress: Progress = True,
) -> Accuracy:
    """What accuracy costs in time (``magbubble accuracy``): every integrator's error against
    its work on the scene, and the mode (and grid) ladders; with ``critical`` (a drive
    frequency [Hz]) the error of the critical ε_p against its cost instead (``--critical``).
    ``quick``: the short study (5 µs, three rungs per ladder). Releases the GIL; a tqdm bar
    counts the simulations; KeyboardInterrupt stops the study before its next simulation.
    Bad ``repeats``, ``duration`` or ``critical`` raise ValueError before any work."""
    scene = _scene(scene_or_path, overrides)
    if critical is not None:
        if repeats is not None or duration is not None:
            raise ValueError("repeats and duration have no meaning with critical= (a Floquet study)")
        return Accuracy(_ext.accuracy_critical(scene._inner, float(critical), quick))
    update, close = progress_bar(progress, "accuracy study", "runs")
    try:
        report = _ext.accuracy_study(scene._inner, quick, repeats, duration, update)
    finally:
        close()
    return Accuracy(report)


def coefficients(field: str, kmax: int) -> Dict[str, Any]:
    """The generated Legendre-coupling tables of ``field`` (``"coil"`` or ``"dipole"``) up to
    mode ``kmax`` (``magbubble coefficients --json``)."""
    return _ext.coefficients(field, kmax)


def stability(
    scene_or_path: SceneOrPath,
    freq: Union[str, Sequence[float]],
    family: Union[None, str, Mapping[str, Sequence[Any]]] = None,
    overrides: Optional[Mapping[str, Any]] = None,
    *,
    method: str = "floquet",
    vary: str = "drive.amplitude",
    freq_key: Optional[str] = None,
    range: Tuple[float, float] = (0.0, 1.0),
    tol: float = 1e-3,
    abs_tol: Optional[float] = None,
    scan: int = 8,
    out: Optional[PathLike] = None,
    shard: Optional[str] = None,
    progress: Progress = True,
    executor: Any = None,
    shards: Optional[int] = None,
    modes: str = "scene",
    cutoff_limit: Optional[int] = None,
) -> pd.DataFrame:
    """A stability diagram (``magbubble stability``): one row per frequency and family member,
    the columns of the CSV (``index``, the frequency key, ``critical``, ``outcome``, …), with the
    family key in front when ``family`` is given.

    ``freq`` is a list of frequencies [Hz] or the CLI's text (``"0.2e6:2e6:10:log"``);
    ``family`` is ``{"field.coil.current": [0, 1e5]}`` or ``"KEY=V1,V2"``. With ``out`` the CSVs
    (+ ``.meta.json``) are written there and the call is resumable: run it again after an
    interruption and only the missing points are computed; ``shard="i/n"`` computes one shard
    (join them with ``magbubble merge``). Without ``out`` a temporary directory is used.
    ``df.attrs`` holds ``csv`` (paths, with ``out``), ``computed``, ``resumed`` and ``failed``.
    KeyboardInterrupt stops it: no point starts, the points in flight are abandoned, and the CSV
    keeps only the whole rows finished so far (a rerun with the same ``out`` resumes). ``progress``: a tqdm bar of points, or a function ``(done, total)``.
    ``modes="auto"`` (``--modes auto``) raises the cutoff ``modes.max_order`` from the scene's
    value, doubling up to ``cutoff_limit`` (default 64), until the critical value converges; the
    frame gains ``max_order_used``, ``cutoff_converged``, ``critical_error`` and ``min_tension``.
    """
    scene = _scene(scene_or_path, overrides)
    if executor is not None:  # issue 33: shards on any concurrent.futures.Executor (_shards.py)
        from ._shards import run_sharded

        kwargs = dict(family=family, method=method, vary=vary, freq_key=freq_key, range=range, tol=tol, abs_tol=abs_tol, scan=scan,
                      modes=modes, cutoff_limit=cutoff_limit)
        return run_sharded(executor, "stability", scene, (freq,), kwargs, out, shards, progress)
    lo, hi = range
    freq = freq_arg(freq)
    family = family_arg(family)
    update, close = progress_bar(progress, "stability", "point")
    with tempfile.TemporaryDirectory(prefix="magbubble-") as tmp:
        out_dir = os.fspath(out) if out is not None else os.path.join(tmp, "out")
        try:
            curves, failed = _ext.stability(
                scene._inner, freq, out_dir, family, method, vary, freq_key, (float(lo), float(hi)), float(tol),
                None if abs_tol is None else float(abs_tol), int(scan), shard, update,
                modes, None if cutoff_limit is None else int(cutoff_limit),
            )
        finally:
            close()
    parts = []
    for fkey, fval, _path, columns, _c, _r in curves:
        df = frame(columns)
        if fkey:
            df.insert(0, fkey, _family_value(fval))
        parts.append(df)
    result = pd.concat(parts, ignore_index=True) if len(parts) > 1 else parts[0]
    result.attrs.update(
        csv=[c[2] for c in curves] if out is not None else [],
        computed=sum(c[4] for c in curves),
        resumed=sum(c[5] for c in curves),
        failed=list(failed),
    )
    for line in failed:
        warnings.warn(line, RuntimeWarning, stacklevel=2)
    return result


def sweep(
    scene_or_path: SceneOrPath,
    grid: Mapping[str, Union[str, Sequence[Any]]],
    overrides: Optional[Mapping[str, Any]] = None,
    *,
    out: Optional[PathLike] = None,
    shard: Optional[str] = None,
    series: bool = False,
    progress: Progress = True,
    executor: Any = None,
    shards: Optional[int] = None,
) -> pd.DataFrame:
    """A grid of runs in parallel (``magbubble sweep SCENE --grid KEY=V1,V2 …``): every
    combination of the values in ``grid`` (the first key slowest), one row per run with its
    parameters, ``status``, ``t_blow_up``, ``R_min``/``R_max``, ``max_shape``, ``max_a2`` … (the
    columns of ``sweep.csv``, docs/user-guide.md).

    ``grid`` maps a scene key to a list of values (``{"bubble.radius": [5e-6, 1e-5]}``, written
    as ``--set`` text) or to the CLI's text (``"0.5e6:2e6:8:log"``, ``"1e6,2e6"``). ``overrides``
    apply to every run (grid values win). With ``out`` the CSV (+ ``.meta.json``) is written
    there, resumable and shardable (``shard="i/n"``, joined by ``magbubble merge``).
    ``series=True`` adds a column ``series`` with each run's DataFrame (as :func:`run`'s; with
    ``out`` also written to ``out/series/<index>.csv``). Invalid keys or values raise ValueError
    (the messages of ``--set``) before any run; KeyboardInterrupt keeps the finished rows.
    ``df.attrs``: ``csv``, ``computed``, ``resumed``.
    """
    scene = _scene(scene_or_path, overrides)
    if not isinstance(grid, Mapping) or not grid:
        raise TypeError("grid must be a non-empty dict {key: [values]} or {key: 'START:STOP:N'}")
    if executor is not None:  # issue 33: shards on any concurrent.futures.Executor (_shards.py)
        if series:
            raise ValueError("series=True with an executor: the series stay in the workers; run without executor")
        from ._shards import run_sharded

        return run_sharded(executor, "sweep", scene, (dict(grid),), {}, out, shards, progress)
    axes = []
    for key, values in grid.items():
        if isinstance(values, str):
            axes.append((key, [values], True))
        else:
            axes.append((key, [toml_text(v) for v in values], False))
    update, close = progress_bar(progress, "sweep", "run")
    try:
        columns, runs, computed, resumed, path = _ext.sweep(
            scene._inner, axes, None if out is None else os.fspath(out), shard, bool(series and out is not None),
            bool(series), update,
        )
    finally:
        close()
    df = frame(columns)
    if series:
        df["series"] = [None if s is None else pd.DataFrame(s[1], columns=s[0], copy=False) for s in runs]
    df.attrs.update(csv=[path] if path else [], computed=computed, resumed=resumed)
    return df


def _family_value(text: str) -> Any:
    try:
        return int(text)
    except ValueError:
        try:
            return float(text)
        except ValueError:
            return text


# populations (issue 33)
from ._population import attenuation, population  # noqa: E402
# --- fit (issue 32) ---------------------------------------------------------------------------


class Fit:
    """A fit of a scene to measurements (``magbubble fit``).

    - ``parameters``: DataFrame, one row per fitted key: ``key, value, std_error, low, high``
      (and ``start, log, derivative``: how ∂f/∂p was formed, "exact" or "finite_difference");
    - ``correlation``: DataFrame of the parameters' correlations (index and columns: keys);
    - ``curves``: DataFrame of fit.csv: ``t`` and per fitted column ``<c>_data, <c>_model,
      <c>_residual``;
    - ``status``: ``"converged"``, ``"max_iterations"`` or ``"failed"`` (``reason`` says why);
    - ``warnings``, ``report`` (the dict of fit.json).
    """

    __slots__ = ("parameters", "correlation", "curves", "report")

    def __init__(self, report: Dict[str, Any], names: List[str], columns: List[List[float]]) -> None:
        self.report = report
        self.parameters = pd.DataFrame(report["parameters"])
        keys = [p["key"] for p in report["parameters"]]
        self.correlation = pd.DataFrame(report["correlation"], index=keys, columns=keys, dtype=float)
        self.curves = pd.DataFrame(dict(zip(names, columns)), columns=names)

    @property
    def status(self) -> str:
        return self.report["status"]

    @property
    def reason(self) -> Optional[str]:
        return self.report.get("reason")

    @property
    def warnings(self) -> List[str]:
        return list(self.report["warnings"])

    def __repr__(self) -> str:
        vals = ", ".join(f"{k}={v:.6g}" for k, v in zip(self.parameters["key"], self.parameters["value"]))
        return f"Fit(status={self.status!r}, {vals})"


def fit(
    scene_or_path: SceneOrPath,
    data: Optional[Union[PathLike, pd.DataFrame]] = None,
    params: Sequence[str] = (),
    *,
    attenuation: Optional[Union[PathLike, pd.DataFrame]] = None,
    concentration: Optional[float] = None,
    starts: int = 1,
    overrides: Optional[Mapping[str, Any]] = None,
) -> Fit:
    """Fits scene keys to measured R(t) (and a_k(t)) (``magbubble fit``). ``data``: a CSV path or a
    DataFrame with columns ``t, R[, a2, …][, sigma_R, …]``; ``params``: ``"KEY"`` or
    ``"KEY=LOW:HIGH"`` (a numeric scene key or ``"time_offset"``). Bad input raises ValueError
    naming the key, column or value; a fit that fails is ``status == "failed"``.

    ``attenuation=`` instead of ``data`` (``magbubble fit --attenuation``): a measured attenuation
    spectrum, path or DataFrame with columns ``f`` [Hz], ``attenuation_db_per_cm``[, ``sigma``],
    of the scene's ``[population]`` (with ``population.concentration``) or of a monodisperse
    suspension at bubble.radius with ``concentration`` [bubbles/mL]; ``curves`` then has columns
    ``f, data, model, residual``."""
    scene = _scene(scene_or_path, overrides)
    if isinstance(params, str):
        params = [params]
    if (data is None) == (attenuation is None):
        raise ValueError("fit: give either data (R(t)) or attenuation (a spectrum), not both or neither")
    call = _ext.fit if attenuation is None else _ext.fit_attenuation
    extra: Dict[str, Any] = {} if attenuation is None else {"concentration": concentration}
    if attenuation is None and concentration is not None:
        raise ValueError("fit: concentration is for an attenuation spectrum (attenuation=)")
    source = data if attenuation is None else attenuation
    if isinstance(source, pd.DataFrame):
        cols = [(str(c), [float(x) for x in source[c].to_numpy(dtype=float)]) for c in source.columns]
        report, names, columns = call(scene._inner, list(params), columns=cols, starts=starts, **extra)
    elif isinstance(source, (str, os.PathLike)):
        report, names, columns = call(scene._inner, list(params), path=os.fspath(source), starts=starts, **extra)
    else:
        raise TypeError(f"{'data' if attenuation is None else 'attenuation'}: expected a path or a DataFrame, got {type(source).__name__}")
    return Fit(report, names, columns)
