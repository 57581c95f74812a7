// SPDX-License-Identifier: MIT
#pragma once
/// @file core.hpp  Core vocabulary: vectors, boxes, errors, hash RNG, progress, parallel loops, images and a canvas for figures.
#include "fabsynth/core/box.hpp"
#include "fabsynth/core/canvas.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/version.hpp"
