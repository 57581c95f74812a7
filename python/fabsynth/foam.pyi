# SPDX-License-Identifier: MIT
from typing import Any, Callable, Iterator, Optional, Sequence

import numpy as np
import numpy.typing as npt

Progress = Optional[Callable[[float, str], Optional[bool]]]
Region = Sequence[float]  # (x0, y0, x1, y1), mm
Box = Sequence[float]     # (x0, y0, z0, x1, y1, z1), mm
Plan = dict[str, Any]     # plan(): region, pixel, layer, z0, layers, selected
SLICES_PER_BATCH: int

class Foam:
    """Procedural Voronoi foam: density (seeds/mm^3) or density_x=(rho0, rho1, x0, x1), radius (mm), cell (mm),
    seed; elasticity=True reads the density values as E/Es (the shipped fit at `radius`)."""
    def __init__(self, *, density: float = 0.2, density_x: Optional[Sequence[float]] = None, radius: float = 0.25,
                 cell: float = 2.0, seed: int = 1, elasticity: bool = False) -> None: ...
    @property
    def params(self) -> dict[str, Any]: ...
    def contains(self, points: npt.ArrayLike) -> npt.NDArray[np.bool_]:
        """n x 3 points (mm) -> n bools (solid)."""
    def slice(self, z: float, region: Region, pixel: float, supersample: int = 1) -> npt.NDArray[np.uint8]:
        """uint8 (h, w), row 0 at y0, 255 = solid."""
    def slices(self, zs: Sequence[float], region: Region, pixel: float, supersample: int = 1,
               progress: Progress = None) -> Iterator[npt.NDArray[np.uint8]]: ...
    def layers(self, plan: Plan, layers: Optional[Sequence[int]] = None, supersample: int = 1,
               progress: Progress = None) -> Iterator[npt.NDArray[np.uint8]]: ...
    def seeds(self, box: Box) -> npt.NDArray[np.float64]:
        """n x 3 seeds (mm) in the box."""
    def beams(self, box: Box) -> dict[str, npt.NDArray[Any]]:
        """dict(nodes n x 3 mm, edges m x 2 int64, radii m mm)."""

class MeshFoam:
    """A foam inside a closed mesh (V n x 3 mm, F m x 3) with a frame of `frame` mm, cut open by (point, normal) planes."""
    def __init__(self, foam: Foam, V: npt.ArrayLike, F: npt.ArrayLike, *, frame: float = 0.5,
                 cuts: Sequence[tuple[Sequence[float], Sequence[float]]] = ()) -> None: ...
    @property
    def foam(self) -> Foam: ...
    @property
    def frame(self) -> float: ...
    @property
    def cuts(self) -> list[tuple[tuple[float, float, float], tuple[float, float, float]]]: ...
    @property
    def mesh(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]: ...
    def contains(self, points: npt.ArrayLike) -> npt.NDArray[np.bool_]: ...
    def plan(self, pixel: float, layer: float = 0.0, count: int = 0) -> Plan:
        """The stack through the mesh's bounding box, as foam_slicer plans it."""
    def slice(self, z: float, region: Region, pixel: float, supersample: int = 1) -> npt.NDArray[np.uint8]: ...
    def slices(self, zs: Sequence[float], region: Region, pixel: float, supersample: int = 1,
               progress: Progress = None) -> Iterator[npt.NDArray[np.uint8]]: ...
    def layers(self, plan: Plan, layers: Optional[Sequence[int]] = None, supersample: int = 1,
               progress: Progress = None) -> Iterator[npt.NDArray[np.uint8]]: ...

def plan(box: Box, pixel: float, layer: float = 0.0, count: int = 0) -> Plan:
    """A slice stack through a box: region (the box grown by a pixel), pixel, layer, z0, layers, selected."""
def elasticity(density: npt.ArrayLike, radius: float) -> npt.NDArray[np.float64]:
    """E/Es of the shipped fit at densities (seeds/mm^3) and radius (mm)."""
def density_for_elasticity(e: npt.ArrayLike, radius: float) -> npt.NDArray[np.float64]:
    """Densities (seeds/mm^3) whose fitted E/Es at `radius` is e (clamped to the reachable range)."""
def reachable_elasticity(radius: float) -> tuple[float, float]: ...
