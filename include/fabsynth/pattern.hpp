#pragma once
/// @file pattern.hpp  Umbrella header of the vector-pattern building blocks (Zhou et al. 2014):
/// exemplars (pattern/exemplar.hpp), slicing into pieces with portals (pattern/pieces.hpp) and
/// topology-driven slicing positions (pattern/reeb_slicing.hpp), and synthesis along a band
/// (pattern/synthesis.hpp, with pattern/offsets.hpp, pattern/stitching.hpp, pattern/contours.hpp),
/// and the map of band coordinates onto a curve (pattern/band_map.hpp).
#include "fabsynth/pattern/exemplar.hpp"
#include "fabsynth/pattern/pieces.hpp"
#include "fabsynth/pattern/reeb_slicing.hpp"
#include "fabsynth/pattern/offsets.hpp"
#include "fabsynth/pattern/stitching.hpp"
#include "fabsynth/pattern/contours.hpp"
#include "fabsynth/pattern/synthesis.hpp"
#include "fabsynth/pattern/band_map.hpp"
