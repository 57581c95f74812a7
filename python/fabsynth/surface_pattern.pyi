# SPDX-License-Identifier: MIT
from typing import Any, Callable, Optional, Sequence

import numpy as np
import numpy.typing as npt

Progress = Optional[Callable[[float, str], Optional[bool]]]

class Exemplar:
    width: int
    height: int
    channels: int
    tileable: bool
    solid_fraction: float

class PatternResult:
    mesh: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]  # watertight solid, mm
    vertex_colours: npt.NDArray[np.uint8] # (n, 3) sRGB per vertex of mesh
    preview: npt.NDArray[np.uint8]        # (h, w, 3): two views
    grid: dict[str, tuple[float, float, float]]  # dims, origin (mm), spacing (mm)
    shell_voxels: npt.NDArray[np.int32]   # n x 3 voxel indices
    state: npt.NDArray[np.uint8]          # n: 1 empty, 2 exemplar, 3 reinforcement, 4 thin feature
    solid_voxels: npt.NDArray[np.int32]   # m x 3 voxel indices of the printable solid
    report: dict[str, Any]                # surface_patterns' report.json keys

def make_exemplar(mask: npt.NDArray[np.uint8], colour: Optional[npt.NDArray[np.uint8]] = None, *, feature_px: float,
                  tileable: bool = True, feature_weight: float = 1.0, colour_weight: float = 1.0) -> Exemplar:
    """An exemplar from a mask (white = solid) and an optional colour picture; feature_px: r_pattern in pixels."""
def make_pattern(V: npt.ArrayLike, F: npt.ArrayLike, exemplar: Exemplar, *, size_mm: float, thickness_mm: float,
                 resolution: int = 256, levels: int = 0, min_feature_mm: float = -1.0, smoothing: int = 50,
                 mm_per_px: float = 0.0, candidates: int = 128, jitter: float = 0.1, up: Sequence[float] = (0, 0, 1),
                 passes: int = 2, seed: int = 1, structure: bool = True, max_iterations: int = 30, stages: bool = False,
                 validate: bool = False, preview: bool = True, preview_size: int = 768, max_memory_gb: float = 16.0,
                 material: str = "abs", gravity: Sequence[float] = (0, 0, -1), samples: int = 1000, safety_factor: float = 2.0,
                 load_factor: float = 20.0, design_load_n: float = 0.0, geodesic_factor: float = 1.5, bridge_radius_mm: float = 0.0,
                 bridge_band: float = 0.25, support_plane: Optional[Sequence[float]] = None, support_band_mm: float = -1.0,
                 loads: Sequence[Sequence[float]] = (), progress: Progress = None) -> PatternResult:
    """A structurally sound surface pattern on (V, F) (mm), the surface_patterns tool's result."""
