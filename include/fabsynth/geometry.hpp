// SPDX-License-Identifier: MIT
#pragma once
/// @file geometry.hpp  Geometry building blocks, every header of geometry/: meshes and their
/// topology, polygons and Clipper booleans, segments and distances, the distance transform,
/// rasterization, marching tetrahedra, constrained Delaunay and ear-clipping triangulation,
/// planar curves and curves in space with their band maps, extrusion, the medial axis, convex
/// hulls and polyline simplification, rigid motions, smoothing, shaded previews of meshes
/// (render.hpp) and coverage images and drawings of polygons. What works on a mesh surface
/// (parameterizations, curves on surfaces, baking, offsets) is the surface block (surface.hpp).
#include "fabsynth/geometry/box_pairs.hpp"
#include "fabsynth/geometry/cdt.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/coverage_image.hpp"
#include "fabsynth/geometry/curve.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/distance_transform.hpp"
#include "fabsynth/geometry/drawing.hpp"
#include "fabsynth/geometry/extrude.hpp"
#include "fabsynth/geometry/hull_simplify.hpp"
#include "fabsynth/geometry/marching_cubes.hpp"
#include "fabsynth/geometry/medial_axis.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/raster.hpp"
#include "fabsynth/geometry/render.hpp"
#include "fabsynth/geometry/rigid_motion.hpp"
#include "fabsynth/geometry/segment.hpp"
#include "fabsynth/geometry/smooth.hpp"
#include "fabsynth/geometry/space_curve.hpp"
#include "fabsynth/geometry/triangulate.hpp"
