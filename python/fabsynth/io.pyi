# SPDX-License-Identifier: MIT
from os import PathLike
from typing import Any, Optional, Union

import numpy as np
import numpy.typing as npt

Path = Union[str, PathLike[str]]
has_3mf: bool

def read_mesh(path: Path) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """(V n x 3 float64, F m x 3 int64) of an .obj, .stl or .ply file."""
def write_mesh(path: Path, V: npt.ArrayLike, F: npt.ArrayLike) -> None:
    """Writes (V, F) as .obj, .stl or .ply by extension, atomically."""
def write_3mf(path: Path, V: npt.ArrayLike, F: npt.ArrayLike, name: str = ..., face_colours: Optional[npt.NDArray[np.uint8]] = None) -> None:
    """Writes (V, F) (mm) as 3MF (only when has_3mf); face_colours: m x 3 uint8 sRGB per face."""
def read_3mf(path: Path, colours: bool = False) -> Any:
    """(V, F) in mm of a 3MF file (only when has_3mf); colours=True: (V, F, C) with C m x 4 uint8 RGBA per face (alpha 0: none)."""
def read_png(path: Path) -> npt.NDArray[np.uint8]:
    """uint8 (h, w) or (h, w, c); row 0 is the top row."""
def read_png_info(path: Path) -> dict[str, Any]:
    """dict(width, height, channels, bit_depth, pixel_mm=(x, y) mm or None)."""
def write_png(path: Path, image: npt.NDArray[np.uint8], pixel_mm: float = 0.0) -> None:
    """uint8 (h, w) or (h, w, c) as PNG; pixel_mm > 0 stores the pixel size (pHYs)."""
def read_svg(path: Path, tolerance: float = 0.01) -> dict[str, Any]:
    """dict(width, height, width_unit, height_unit, view_box, shapes=[dict(subpaths=[n x 2], closed, fill, stroke, stroke_width, id, fill_rule)])."""
