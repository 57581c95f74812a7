# SPDX-License-Identifier: MIT
"""Files: meshes as (V, F), PNG pictures as uint8 arrays with their pixel size, SVG drawings (fabsynth::io)."""
from ._fabsynth.io import has_3mf, read_mesh, read_png, read_png_info, read_svg, write_mesh, write_png

__all__ = ["has_3mf", "read_mesh", "read_png", "read_png_info", "read_svg", "write_mesh", "write_png"]
if has_3mf:
    from ._fabsynth.io import read_3mf, write_3mf  # noqa: F401
    __all__ += ["read_3mf", "write_3mf"]
