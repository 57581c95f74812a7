#!/usr/bin/env bash
# Voxelize two closed meshes: shell.vtk (shell / solid / normals per voxel), solid.stl (watertight
# marching-cubes mesh of the solid voxels) and slices.png (preview) per mesh.
set -euo pipefail
: "${BIN:?BIN must point at the built examples}" "${DATA:?DATA must point at data/}" "${OUT_DIR:?OUT_DIR must be set}"
for mesh in bunny_lowres kitten_lowres; do
  "$BIN/voxelize/voxelize" "$DATA/meshes/$mesh.obj" --resolution 64 -o "$OUT_DIR/voxelize_$mesh"
done
