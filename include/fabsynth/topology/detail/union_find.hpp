#pragma once
/// @file union_find.hpp  Forwarding header only: the union-find with potentials now lives in
/// core/union_find.hpp. Kept because vector_pattern/contours.hpp (being edited on another branch)
/// still names topology::detail::potential_union_find; delete this file once it includes
/// core/union_find.hpp and uses fabsynth::potential_union_find.
#include "fabsynth/core/union_find.hpp"

namespace fabsynth::topology::detail {
using fabsynth::potential_union_find;
}  // namespace fabsynth::topology::detail
