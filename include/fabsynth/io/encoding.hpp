// SPDX-License-Identifier: MIT
#pragma once
/// @file encoding.hpp  Text or binary output for formats that have both (STL, PLY, PGM, VTK).

namespace fabsynth::io {

/// ascii: human-readable text; binary: compact (byte order as each format prescribes).
enum class encoding { ascii, binary };

}  // namespace fabsynth::io
