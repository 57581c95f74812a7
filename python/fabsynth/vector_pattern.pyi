# SPDX-License-Identifier: MIT
from os import PathLike
from typing import Any, Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

Progress = Optional[Callable[[float, str], Optional[bool]]]

class Exemplar:
    height: float

class PatternResult:
    drawn: list[tuple[npt.NDArray[np.float64], list[npt.NDArray[np.float64]]]]  # [(outer n x 2, [holes])], mm, y down
    view: tuple[float, float, float, float]
    mesh: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]
    preview: npt.NDArray[np.uint8]
    report: dict[str, Any]

def exemplar_from_svg(path: Union[str, PathLike[str]]) -> Exemplar: ...
def make_pattern(exemplar: Exemplar, *, height: float, line: Optional[float] = None, circle: Optional[float] = None,
                 curve: Optional[npt.ArrayLike] = None, rect: Optional[Sequence[float]] = None, curve3d: Optional[npt.ArrayLike] = None,
                 surface: Optional[tuple[npt.ArrayLike, npt.ArrayLike]] = None, points: Optional[npt.ArrayLike] = None,
                 closed: bool = False, closed_loop: bool = False, components: Optional[int] = None, holes: Optional[int] = None,
                 seed: int = 0, thickness: float = 1.0, tolerance: float = 0.0, slicing: str = "reeb", beta: float = 0.0,
                 twist_deg: float = 0.0, emboss: Optional[float] = None, carve: Optional[float] = None, shell: Optional[float] = None,
                 cell: Optional[float] = None, progress: Progress = None) -> PatternResult: ...
