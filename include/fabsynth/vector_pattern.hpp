// SPDX-License-Identifier: MIT
#pragma once
/// @file vector_pattern.hpp  Umbrella header of the vector-pattern building blocks (Zhou et al. 2014):
/// exemplars (vector_pattern/exemplar.hpp), slicing into pieces with portals (vector_pattern/pieces.hpp) and
/// topology-driven slicing positions (vector_pattern/reeb_slicing.hpp), the transition cost between
/// pieces (vector_pattern/portal_cost.hpp), synthesis along a band (vector_pattern/synthesis.hpp, with
/// vector_pattern/offsets.hpp, vector_pattern/stitching.hpp, vector_pattern/contours.hpp), the map of
/// band coordinates onto a curve (vector_pattern/band_map.hpp), curves in space and on surfaces with
/// the decoration of a surface by a band (geometry/space_curve.hpp, geometry/disk_parameterization.hpp,
/// geometry/surface_curve.hpp, geometry/surface_decoration.hpp; §6.3) and the PNG preview of a result
/// (geometry/coverage_image.hpp).
#include "fabsynth/vector_pattern/exemplar.hpp"
#include "fabsynth/vector_pattern/pieces.hpp"
#include "fabsynth/vector_pattern/reeb_slicing.hpp"
#include "fabsynth/vector_pattern/offsets.hpp"
#include "fabsynth/vector_pattern/stitching.hpp"
#include "fabsynth/vector_pattern/contours.hpp"
#include "fabsynth/vector_pattern/portal_cost.hpp"
#include "fabsynth/vector_pattern/synthesis.hpp"
#include "fabsynth/vector_pattern/band_map.hpp"
#include "fabsynth/geometry/coverage_image.hpp"
#include "fabsynth/geometry/disk_parameterization.hpp"
#include "fabsynth/geometry/space_curve.hpp"
#include "fabsynth/geometry/surface_curve.hpp"
#include "fabsynth/geometry/surface_decoration.hpp"
