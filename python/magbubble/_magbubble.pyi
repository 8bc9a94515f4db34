"""Type stubs of the extension module magbubble._magbubble (python/src/*.rs). Use the package
``magbubble`` (python/magbubble/__init__.py), which wraps these into dicts and DataFrames."""

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

KMAX: int

_Progress = Optional[Callable[[float, float], None]]

class Scene:
    @staticmethod
    def load(path: str, overrides: List[str] = ...) -> "Scene": ...
    @staticmethod
    def from_toml(text: str, origin: str = "<string>") -> "Scene": ...
    def with_set(self, overrides: List[str]) -> "Scene": ...
    def to_toml(self) -> str: ...
    def resolved(self) -> Dict[str, Any]: ...
    @property
    def origin(self) -> str: ...
    @property
    def overrides(self) -> List[str]: ...

def run(
    scene: Scene, progress: _Progress = None
) -> Tuple[List[str], npt.NDArray[np.float64], Dict[str, Any], Optional[Tuple[List[_Column], List[_Column]]]]: ...
def modes(scene: Scene, kmax: Optional[int] = None, damped: bool = False) -> Dict[str, Any]: ...
def floquet(scene: Scene, steps: int = 400, variant: str = "orbit") -> Dict[str, Any]: ...
def coefficients(field: str, kmax: int) -> Dict[str, Any]: ...
def accuracy_study(
    scene: Scene,
    quick: bool = False,
    repeats: Optional[int] = None,
    duration: Optional[float] = None,
    progress: _Progress = None,
) -> Dict[str, Any]: ...
def accuracy_critical(scene: Scene, frequency_hz: float, quick: bool = False) -> Dict[str, Any]: ...

# (name, "int" | "float" | "text", int64 array | float64 array | (uint32 codes, distinct values))
_Column = Tuple[str, str, Any]
_Curve = Tuple[str, str, str, List[_Column], int, int]

def stability(
    scene: Scene,
    freq: Union[str, List[float]],
    out: str,
    family: Union[None, str, Tuple[str, List[str]]] = None,
    method: str = "floquet",
    vary: str = "drive.amplitude",
    freq_key: Optional[str] = None,
    range: Tuple[float, float] = (0.0, 1.0),
    tol: float = 1e-3,
    abs_tol: Optional[float] = None,
    scan: int = 8,
    shard: Optional[str] = None,
    progress: _Progress = None,
    modes: str = "scene",
    cutoff_limit: Optional[int] = None,
) -> Tuple[List[_Curve], List[str]]: ...

_Series = Optional[Tuple[List[str], npt.NDArray[np.float64]]]

def sweep(
    scene: Scene,
    axes: List[Tuple[str, List[str], bool]],
    out: Optional[str] = None,
    shard: Optional[str] = None,
    keep_series: bool = False,
    return_series: bool = False,
    progress: _Progress = None,
) -> Tuple[List[_Column], Optional[List[_Series]], int, int, str]: ...

# populations (issue 33)
_Triple = Tuple[List[float], List[float], List[float]]

def population(
    scene: Scene,
    freq: Union[str, List[float]],
    out: str,
    range: Tuple[float, float] = (0.0, 1.0),
    eps_points: int = 101,
    tol: float = 1e-3,
    abs_tol: Optional[float] = None,
    scan: int = 8,
    window_check: bool = True,
    shard: Optional[str] = None,
    progress: _Progress = None,
) -> Tuple[str, int, int, Optional[List[_Column]], Optional[_Triple], Optional[str], List[str]]: ...
def attenuation(
    scene: Scene, freq: Union[str, List[float]], out: str, shard: Optional[str] = None, progress: _Progress = None
) -> Tuple[str, int, int, Optional[_Triple], Optional[str]]: ...
def merge(inputs: List[str], out: str) -> int: ...
# issue 32
def fit(
    scene: Scene,
    params: List[str],
    path: Optional[str] = None,
    columns: Optional[List[Tuple[str, List[float]]]] = None,
    starts: int = 1,
) -> Tuple[Dict[str, Any], List[str], List[List[float]]]: ...
def fit_attenuation(
    scene: Scene,
    params: List[str],
    path: Optional[str] = None,
    columns: Optional[List[Tuple[str, List[float]]]] = None,
    concentration: Optional[float] = None,
    starts: int = 1,
) -> Tuple[Dict[str, Any], List[str], List[List[float]]]: ...
def response(scene: Scene, freq: Union[str, Sequence[float]]) -> Tuple[List[_Column], float, float, Dict[str, float]]: ...
