"""Type stubs of the extension module magbubble._magbubble (python/src/*.rs). Use the package
``magbubble`` (python/magbubble/__init__.py), which wraps these into dicts and DataFrames."""

from typing import Callable, List, Optional, Tuple

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
    def resolved_json(self) -> str: ...
    @property
    def origin(self) -> str: ...
    @property
    def overrides(self) -> List[str]: ...

def run(scene: Scene, progress: _Progress = None) -> Tuple[List[str], npt.NDArray[np.float64], str]: ...
def modes(scene: Scene, kmax: Optional[int] = None, damped: bool = False) -> str: ...
def floquet(scene: Scene, steps: int = 400, variant: str = "orbit") -> str: ...
def coefficients(field: str, kmax: int) -> str: ...

_Curve = Tuple[str, str, str, List[str], List[Tuple[int, List[str]]], int, int]

def stability(
    scene: str,
    freq: str,
    out: str,
    overrides: List[str] = ...,
    family: Optional[str] = None,
    method: str = "floquet",
    vary: str = "drive.amplitude",
    freq_key: Optional[str] = None,
    range: str = "0:1",
    tol: float = 1e-3,
    abs_tol: Optional[float] = None,
    scan: int = 8,
    shard: Optional[str] = None,
    progress: _Progress = None,
) -> Tuple[List[_Curve], List[str]]: ...

_GridRow = Tuple[List[str], Optional[Tuple[List[str], npt.NDArray[np.float64]]]]

def sweep(
    scene: Scene,
    axes: List[Tuple[str, List[str], bool]],
    out: Optional[str] = None,
    shard: Optional[str] = None,
    keep_series: bool = False,
    return_series: bool = False,
    progress: _Progress = None,
) -> Tuple[List[str], List[_GridRow], int, int, str]: ...
