# SPDX-License-Identifier: MIT
from os import PathLike
from typing import Any, Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

Progress = Optional[Callable[[float, str], Optional[bool]]]
Polygons = list[tuple[npt.NDArray[np.float64], list[npt.NDArray[np.float64]]]]  # [(outer n x 2, [holes])], mm

class Element:
    name: str

class PlanarFiligree:
    outline: Polygons                      # the printable piece, mm, y down
    mesh: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]
    view: tuple[float, float, float, float]
    preview: npt.NDArray[np.uint8]
    steps: npt.NDArray[np.uint8]
    stress_map: npt.NDArray[np.uint8]
    histogram: npt.NDArray[np.uint8]
    report: dict[str, Any]

class SurfaceFiligree:
    solid: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]
    baked: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]
    preview: npt.NDArray[np.uint8]
    stress_map: npt.NDArray[np.uint8]
    histogram: npt.NDArray[np.uint8]
    report: dict[str, Any]

def element_from_svg(path: Union[str, PathLike[str]], *, size_mm: float = 20.0, width_mm: float = 0.0, tolerance_mm: float = 0.05,
                     name: str = "") -> Element: ...
def make_filigree(elements: Sequence[Element], weights: Optional[Sequence[float]] = None, *, rect: Optional[Sequence[float]] = None,
                  domain_svg: Optional[Union[str, PathLike[str]]] = None, rotation_deg: float = 0.0, seed: int = 1, sigma_d: float = 0.15,
                  sigma_f: float = 0.05, max_rounds: int = 6, crossing_penalty: float = 5.0, max_elements: int = 5000,
                  structure: bool = True, material: str = "abs", thickness_mm: float = 1.0, max_thickness_mm: float = 0.0,
                  pressure_pa: float = 1000.0, max_bridge_mm: float = 0.0, previews: bool = True, progress: Progress = None) -> PlanarFiligree: ...
def make_surface_filigree(elements: Sequence[Element], weights: Optional[Sequence[float]], V: npt.ArrayLike, F: npt.ArrayLike, *,
                          up: Sequence[float] = (0, 0, 1), region_faces: Optional[Sequence[int]] = None,
                          vertex_scale: Optional[Sequence[float]] = None, seed: int = 1, sigma_d: float = 0.15, sigma_f: float = 0.05,
                          max_rounds: int = 6, crossing_penalty: float = 5.0, max_elements: int = 5000, structure: bool = True,
                          material: str = "abs", thickness_mm: float = 1.0, max_thickness_mm: float = 0.0, pressure_pa: float = 1000.0,
                          max_bridge_mm: float = 0.0, previews: bool = True, progress: Progress = None) -> SurfaceFiligree: ...
