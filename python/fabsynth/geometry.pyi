# SPDX-License-Identifier: MIT
from typing import Any

import numpy as np
import numpy.typing as npt

def simplify_mesh(V: npt.ArrayLike, F: npt.ArrayLike, tolerance: float = 0.05, attempts: int = 4
                  ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.int64], dict[str, Any]]:
    """(V2, F2, source, report): fewer triangles within `tolerance` mm both ways, the same topology, no self-intersection;
    source[i] is the input vertex of result vertex i; report: raw_triangles, triangles, simplified, tolerance_mm,
    hausdorff_mm, hausdorff_measured_mm, runs, warning."""
def hausdorff_distance(Va: npt.ArrayLike, Fa: npt.ArrayLike, Vb: npt.ArrayLike, Fb: npt.ArrayLike, precision: float = 0.01
                       ) -> tuple[float, float]:
    """(lower, upper) mm: a distance attained and a certified bound of the two-sided Hausdorff distance."""
