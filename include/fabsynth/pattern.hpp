#pragma once
/// @file pattern.hpp  Umbrella header of the vector-pattern building blocks (Zhou et al. 2014):
/// exemplars (pattern/exemplar.hpp), slicing into pieces with portals (pattern/pieces.hpp) and
/// topology-driven slicing positions (pattern/reeb_slicing.hpp).
#include "fabsynth/pattern/exemplar.hpp"
#include "fabsynth/pattern/pieces.hpp"
#include "fabsynth/pattern/reeb_slicing.hpp"
