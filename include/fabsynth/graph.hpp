// SPDX-License-Identifier: MIT
#pragma once
/// @file graph.hpp  Umbrella header of the graph building block (namespace fabsynth::graph):
/// CSR graphs and their voxel / mesh / polyline adaptors, shortest-path forests, forest adjacency,
/// components and colouring. The union-find every module shares is core/union_find.hpp.
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/graph/colouring.hpp"
#include "fabsynth/graph/components.hpp"
#include "fabsynth/graph/csr_graph.hpp"
#include "fabsynth/graph/forest_adjacency.hpp"
#include "fabsynth/graph/from_mesh.hpp"
#include "fabsynth/graph/from_voxels.hpp"
#include "fabsynth/graph/shortest_paths.hpp"
#include "fabsynth/graph/skeleton_graph.hpp"
