// SPDX-License-Identifier: MIT
#pragma once
/// @file voxel.hpp  Voxel grids (dense / sparse), neighbourhoods, connected components, mesh
/// voxelization (surface shell and solid), multi-resolution pyramids and preview pictures.
#include "fabsynth/voxel/components.hpp"
#include "fabsynth/voxel/grid.hpp"
#include "fabsynth/voxel/neighbourhood.hpp"
#include "fabsynth/voxel/preview.hpp"
#include "fabsynth/voxel/pyramid.hpp"
#include "fabsynth/voxel/voxelize.hpp"
