// SPDX-License-Identifier: MIT
#pragma once
/// @file version.hpp  The single place the library version lives (CMake reads it from here).
#define FABSYNTH_VERSION_MAJOR 0
#define FABSYNTH_VERSION_MINOR 1
#define FABSYNTH_VERSION_PATCH 0
#define FABSYNTH_VERSION_STRING "0.1.0"
