// SPDX-License-Identifier: MIT
#pragma once
/// @file surface_pattern.hpp  Umbrella header of the surface-pattern pipeline (Lu, Lefebvre, Dumas,
/// Wu & Dick 2015, structurally-sound-patterns.md): the voxel shell and its pyramid
/// (surface_pattern/shell.hpp), exemplars with their Gaussian stack and feature-distance channel
/// (surface_pattern/exemplar.hpp), labels and the plane mapping (surface_pattern/labels.hpp), the
/// synthesis energy (surface_pattern/energy.hpp), the optimizer and constrained resynthesis
/// (surface_pattern/synthesis.hpp), the surface and abstract graphs (surface_pattern/abstract_graph.hpp),
/// the beam-wedge FEM model that scores abstract edges (surface_pattern/beam_model.hpp), fabrication:
/// specks, inward thickening, meshing (surface_pattern/fabricate.hpp) and thin features
/// (surface_pattern/thin_features.hpp), the full-resolution validation
/// (surface_pattern/validation.hpp), and the structural optimizer with the loop of Algorithm 1
/// (surface_pattern/structural.hpp), and the whole pipeline in one call, make_pattern
/// (surface_pattern/pipeline.hpp).
#include "fabsynth/surface_pattern/shell.hpp"
#include "fabsynth/surface_pattern/exemplar.hpp"
#include "fabsynth/surface_pattern/labels.hpp"
#include "fabsynth/surface_pattern/energy.hpp"
#include "fabsynth/surface_pattern/synthesis.hpp"
#include "fabsynth/surface_pattern/abstract_graph.hpp"
#include "fabsynth/surface_pattern/fabricate.hpp"
#include "fabsynth/surface_pattern/beam_model.hpp"
#include "fabsynth/surface_pattern/thin_features.hpp"
#include "fabsynth/surface_pattern/validation.hpp"
#include "fabsynth/surface_pattern/structural.hpp"
#include "fabsynth/surface_pattern/pipeline.hpp"
