# SPDX-License-Identifier: MIT
from os import PathLike
from typing import Any, Callable, Optional, Sequence, Union

import numpy.typing as npt

Progress = Optional[Callable[[float, str], Optional[bool]]]

def solve_inp(path: Union[str, PathLike[str]], solver: str = "auto") -> dict[str, Any]:
    """Linear static solve of a .inp deck (mm, N, MPa): nodes, node_labels, displacements (n x 3 mm), rotations,
    element_labels, stresses (m x 6 MPa, Abaqus order xx yy zz xy yz zx), von_mises, solver, iterations, relative_residual."""
def solve_inp_text(text: str, solver: str = "auto") -> dict[str, Any]:
    """solve_inp() of a deck given as text."""
def homogenize(density: npt.ArrayLike, voxel_mm: Union[float, Sequence[float]] = 1.0, *, E: float = 1.0, nu: float = 0.3,
               tol: float = 1e-8, progress: Progress = None) -> dict[str, Any]:
    """Periodic homogenization of a density grid [x, y, z] in [0, 1]: C (6 x 6 MPa, Voigt), volume_fraction,
    removed_fraction, and the isotropic fit E, nu, relative_residual."""
