"""Type stubs of the public API (docs/PYTHON.md has every call with its units)."""

import os
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._tetrasim import BACKENDS as BACKENDS
from ._tetrasim import HAS_TETGEN as HAS_TETGEN
from ._tetrasim import DivergedError as DivergedError
from ._tetrasim import __version__ as __version__

PathLike = Union[str, os.PathLike[str]]

class Mesh:
    def __init__(
        self,
        nodes: npt.ArrayLike,
        tets: npt.ArrayLike,
        label: Optional[str] = None,
    ) -> None: ...
    @property
    def nodes(self) -> npt.NDArray[np.float64]: ...
    @property
    def tets(self) -> npt.NDArray[np.int64]: ...
    @property
    def faces(self) -> npt.NDArray[np.int64]: ...
    @property
    def label(self) -> str: ...
    def write(self, path: PathLike) -> None: ...
    @staticmethod
    def from_meshio(m: Any, label: str = "meshio") -> "Mesh": ...
    def to_meshio(self) -> Any: ...

def default_params() -> Dict[str, Any]: ...
def read_mesh(path: PathLike, target_tets: Optional[int] = None) -> Mesh: ...
def prep(
    surface: PathLike,
    target_tets: Optional[int] = None,
    mesher: str = "tetgen",
    quality: Optional[float] = 2.0,
) -> Mesh: ...
def mesh_from_meshio(m: Any, label: str = "meshio") -> Mesh: ...
def mesh_to_meshio(mesh: Mesh) -> Any: ...

class Simulation:
    mesh: Optional[Mesh]
    scene_frames: Optional[int]
    def __init__(
        self,
        mesh: Union[Mesh, PathLike],
        *,
        backend: str = "cpu",
        fit_size: Optional[float] = 1.0,
        drop_height: Optional[float] = 0.1,
        offset: Sequence[float] = (0.0, 0.0, 0.0),
        pins: Iterable[int] = (),
        pin_boxes: Sequence[Tuple[Sequence[float], Sequence[float]]] = (),
        self_contact: bool = False,
        **params: Any,
    ) -> None: ...
    @classmethod
    def from_scene(cls, path: PathLike, backend: str = "cpu") -> "Simulation": ...
    @classmethod
    def from_record(
        cls, record: Dict[str, Any], mesh: Union[Mesh, PathLike, None] = None, **kw: Any
    ) -> "Simulation": ...
    def step(self, frames: int = 1) -> None: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def velocities(self) -> npt.NDArray[np.float64]: ...
    def set_state(self, positions: npt.ArrayLike, velocities: Optional[npt.ArrayLike] = None) -> None: ...
    @property
    def volume_ratio(self) -> float: ...
    @property
    def frames(self) -> int: ...
    @property
    def time(self) -> float: ...
    @property
    def backend(self) -> str: ...
    def record(self) -> Dict[str, Any]: ...
    def write(self, path: PathLike) -> None: ...

def sweep(
    settings: Sequence[Dict[str, Any]],
    *,
    use_ray: Optional[bool] = None,
    processes: Optional[int] = None,
    dataframe: bool = True,
) -> Any: ...
