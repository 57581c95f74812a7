// SPDX-License-Identifier: MIT
#pragma once
/// @file io.hpp  File input/output: meshes (OBJ, STL, PLY; 3MF with fabsynth::lib3mf), images
/// (PNG 8/16-bit with pixel size, PGM), legacy VTK, SVG, number lists as text.
///
/// io/ is the only part of fabsynth that touches files. Every reader parses from memory
/// (parse_obj, parse_stl, ... take bytes and a name for messages) and rejects malformed input
/// with fabsynth::io_error naming the file and line or byte offset; every writer writes
/// atomically (temporary file + rename).
#include "fabsynth/io/atomic_file.hpp"
#include "fabsynth/io/encoding.hpp"
#include "fabsynth/io/image.hpp"
#include "fabsynth/io/mesh.hpp"
#if defined(FABSYNTH_HAS_LIB3MF)
#include "fabsynth/io/mesh_3mf.hpp"
#endif
#include "fabsynth/io/mesh_obj.hpp"
#include "fabsynth/io/mesh_ply.hpp"
#include "fabsynth/io/mesh_stl.hpp"
#include "fabsynth/io/numbers.hpp"
#include "fabsynth/io/vtk.hpp"
#include "fabsynth/io/svg.hpp"
