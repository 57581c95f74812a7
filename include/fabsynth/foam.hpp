// SPDX-License-Identifier: MIT
#pragma once
/// @file foam.hpp  Procedural Voronoi foams (Martinez, Dumas & Lefebvre, SIGGRAPH 2016): graded
/// jittered seeds (Algorithm 3), an exact per-point evaluator and a fast tiled slicer, fields from
/// images, meshes and elasticity targets, a surface frame following a mesh (slices, implicit and
/// mesh), beam-network export and the elasticity -> (rho, tau) inverse mapping.
///
/// The elasticity fit itself (homogenized samples, the grid run, its text outputs) is in
/// foam/elasticity_samples.hpp, foam/elasticity_study.hpp, foam/elasticity_text.hpp and its figure
/// foam/fit_plot.hpp, included on their own because they pull in the FEM (fem/homogenization.hpp).
#include "fabsynth/foam/beams.hpp"
#include "fabsynth/foam/elasticity.hpp"
#include "fabsynth/foam/evaluator.hpp"
#include "fabsynth/foam/field_adaptors.hpp"
#include "fabsynth/foam/fields.hpp"
#include "fabsynth/foam/fit.hpp"
#include "fabsynth/foam/frame.hpp"
#include "fabsynth/foam/frame_mesh.hpp"
#include "fabsynth/foam/seeds.hpp"
#include "fabsynth/foam/slice_stack.hpp"
