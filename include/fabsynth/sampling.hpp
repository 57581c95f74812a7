// SPDX-License-Identifier: MIT
#pragma once
/// @file sampling.hpp  Umbrella header of the sampling block: Poisson-disk down-sampling of point
/// sets with a radius search for a target count, and dart throwing with an acceptance predicate.
#include "fabsynth/sampling/dart_throwing.hpp"
#include "fabsynth/sampling/poisson_disk.hpp"
