// SPDX-License-Identifier: MIT
#pragma once
/// @file compiler.hpp  Compiler workarounds, each confined to the functions that need it.
///
/// FABSYNTH_NO_SLP_VECTORIZE: GCC 12's SLP vectorizer folds double(float(x)) back to x in all but
/// the last lane of per-component code over glm vectors at -O2 (GCC 12.2: `v[a] =
/// double(float(v[a]))` rounds only z). Functions that round doubles to float and keep the result
/// as doubles carry this attribute; tests/geometry/extrude.cpp ("weld_to_float rounds every
/// component") reproduces the miscompile when it is removed. Users' code is not affected by it.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#define FABSYNTH_NO_SLP_VECTORIZE __attribute__((optimize("no-tree-slp-vectorize")))
#else
#define FABSYNTH_NO_SLP_VECTORIZE
#endif
