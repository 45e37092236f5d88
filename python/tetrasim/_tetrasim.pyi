"""Type stubs of the Rust extension (PyO3). The Python layer (`tetrasim/__init__.py`) is the
public API; these are the calls it makes."""

from typing import List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str
BACKENDS: List[str]
HAS_TETGEN: bool

class DivergedError(RuntimeError): ...

class Mesh:
    def __init__(
        self,
        nodes: npt.NDArray[np.float64],
        tets: npt.NDArray[np.int64],
        label: Optional[str] = None,
    ) -> None: ...
    @property
    def nodes(self) -> npt.NDArray[np.float64]:
        """Node positions, (n, 3) float64."""
    @property
    def tets(self) -> npt.NDArray[np.int64]:
        """Tetrahedra, (t, 4) int64 node indices."""
    @property
    def faces(self) -> npt.NDArray[np.int64]:
        """Boundary triangles, (f, 3) int64, outward."""
    @property
    def label(self) -> str: ...
    def write(self, path: str) -> None: ...

def read_mesh(path: str, target_tets: Optional[int] = None) -> Mesh: ...
def prep(
    surface: str,
    target_tets: Optional[int] = None,
    mesher: str = "tetgen",
    quality: Optional[float] = 2.0,
) -> Mesh: ...
def default_params() -> str: ...

class _Simulation:
    def __init__(
        self,
        mesh: Mesh,
        params_json: str,
        backend: str = "cpu",
        fit_size: Optional[float] = 1.0,
        drop_height: Optional[float] = 0.1,
        pins: Sequence[int] = (),
        pin_boxes: Sequence[Tuple[Tuple[float, float, float], Tuple[float, float, float]]] = (),
        offset: Tuple[float, float, float] = (0.0, 0.0, 0.0),
        self_contact: bool = False,
        rotation: Optional[Tuple[float, float, float, float]] = None,
        device: Optional[str] = None,
    ) -> None: ...
    @staticmethod
    def from_scene(
        path: str, backend: str = "cpu", device: Optional[str] = None
    ) -> Tuple["_Simulation", int]: ...
    def save(self, path: str) -> None: ...
    def load(self, path: str) -> None: ...
    def close(self) -> None: ...
    def step(self, frames: int = 1) -> None: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def velocities(self) -> npt.NDArray[np.float64]: ...
    def set_state(
        self,
        positions: npt.NDArray[np.float64],
        velocities: Optional[npt.NDArray[np.float64]] = None,
    ) -> None: ...
    @property
    def volume_ratio(self) -> float: ...
    @property
    def pin_force(self) -> npt.NDArray[np.float64]: ...
    @property
    def floor_force(self) -> npt.NDArray[np.float64]: ...
    @property
    def collider_forces(self) -> npt.NDArray[np.float64]: ...
    @property
    def frames(self) -> int: ...
    @property
    def time(self) -> float: ...
    @property
    def backend(self) -> str: ...
    def record_json(self) -> str: ...
    def write(self, path: str) -> None: ...

class _Series:
    def __init__(self, sim: _Simulation, path: str, format: Optional[str] = None) -> None: ...
    def add(self, sim: _Simulation) -> None: ...
    def close(self) -> None: ...
    @property
    def frames(self) -> List[int]: ...
