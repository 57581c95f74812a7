# SPDX-License-Identifier: MIT
from os import PathLike
from typing import Any, Optional, Sequence, Union

def write_layers(obj: Any, plan: dict[str, Any], layers: Sequence[int], out_dir: Union[str, PathLike[str]],
                 supersample: int = 1) -> list[tuple[int, float, str, int, int]]: ...
def write_stack(obj: Any, plan: dict[str, Any], out_dir: Union[str, PathLike[str]], client: Optional[Any] = None,
                layers_per_task: int = 16, supersample: int = 1) -> dict[str, Any]: ...
