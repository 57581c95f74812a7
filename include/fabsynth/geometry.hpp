// SPDX-License-Identifier: MIT
#pragma once
/// @file geometry.hpp  Geometry building blocks: meshes, polygons, Clipper booleans, distances,
/// marching cubes, mesh topology, planar curves with a band map, triangulation, extrusion and the
/// medial axis of polygons with holes, convex hulls and polyline simplification, shaded previews
/// of meshes (render.hpp) and coverage images of polygons (coverage_image.hpp).
#include "fabsynth/geometry/box_pairs.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/coverage_image.hpp"
#include "fabsynth/geometry/curve.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/distance_transform.hpp"
#include "fabsynth/geometry/extrude.hpp"
#include "fabsynth/geometry/hull_simplify.hpp"
#include "fabsynth/geometry/marching_cubes.hpp"
#include "fabsynth/geometry/medial_axis.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/render.hpp"
#include "fabsynth/geometry/triangulate.hpp"
