// SPDX-License-Identifier: MIT
#pragma once
/// @file vector_pattern.hpp  Umbrella header of the vector-pattern building blocks (Zhou et al. 2014):
/// exemplars (vector_pattern/exemplar.hpp), slicing into pieces with portals (vector_pattern/pieces.hpp) and
/// topology-driven slicing positions (vector_pattern/reeb_slicing.hpp), the transition cost between
/// pieces (vector_pattern/portal_cost.hpp), synthesis along a band (vector_pattern/synthesis.hpp, with
/// vector_pattern/offsets.hpp, vector_pattern/stitching.hpp, vector_pattern/contours.hpp), the map of
/// band coordinates onto a curve (vector_pattern/band_map.hpp), and the whole pipeline in one call,
/// make_pattern (vector_pattern/pipeline.hpp): along planar curves, in rectangles, along curves in
/// space and on surfaces, embossed or carved (§6.3). The curves, the surface decoration and the
/// previews it uses are geometry's and surface's (geometry.hpp, surface.hpp), not re-exported here.
#include "fabsynth/vector_pattern/exemplar.hpp"
#include "fabsynth/vector_pattern/pieces.hpp"
#include "fabsynth/vector_pattern/reeb_slicing.hpp"
#include "fabsynth/vector_pattern/offsets.hpp"
#include "fabsynth/vector_pattern/stitching.hpp"
#include "fabsynth/vector_pattern/contours.hpp"
#include "fabsynth/vector_pattern/portal_cost.hpp"
#include "fabsynth/vector_pattern/synthesis.hpp"
#include "fabsynth/vector_pattern/band_map.hpp"
#include "fabsynth/vector_pattern/pipeline.hpp"
