// SPDX-License-Identifier: MIT
#pragma once
/// @file surface.hpp  Umbrella header of the surface block (depends on core and geometry): what
/// works on a triangle-mesh surface. The cotangent Laplacian and harmonic interpolation
/// (surface/laplacian.hpp), the bijective disk parameterization of a disk-topology mesh
/// (surface/disk_parameterization.hpp), local parameterizations by the discrete exponential map
/// (surface/exponential_map.hpp), curves drawn on a surface (surface/curve.hpp), the region a
/// closed curve on a mesh encloses (surface/curve_region.hpp), baking planar strips into the faces
/// (surface/bake.hpp), a band embossed onto or carved out of a shell (surface/decoration.hpp) and
/// the printable offset solid of a thin surface (surface/offset.hpp).
#include "fabsynth/surface/laplacian.hpp"
#include "fabsynth/surface/disk_parameterization.hpp"
#include "fabsynth/surface/exponential_map.hpp"
#include "fabsynth/surface/curve.hpp"
#include "fabsynth/surface/curve_region.hpp"
#include "fabsynth/surface/bake.hpp"
#include "fabsynth/surface/decoration.hpp"
#include "fabsynth/surface/offset.hpp"
