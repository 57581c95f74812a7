// SPDX-License-Identifier: MIT
#pragma once
/// @file fem.hpp  Linear elastic finite elements: hex8 / wedge6 / shell3 elements, material,
/// parallel deterministic assembly, supports and loads, sparse solver policies, the reusing solve context with its automatic method (SA-AMG, CHOLMOD, LDL^T), stress recovery,
/// and the Abaqus/CalculiX .inp subset reader. Units: mm, N, MPa, t/mm^3.
///
/// Usage:
///   fabsynth::fem::inp_model d = fabsynth::fem::parse_inp(text, "deck.inp");
///   auto r = fabsynth::fem::solve_linear_static(d.model, d.loads);
///   auto s = fabsynth::fem::centroid_stresses(d.model, r);
#include "fabsynth/fem/assembly.hpp"
#include "fabsynth/fem/boundary.hpp"
#include "fabsynth/fem/element.hpp"
#include "fabsynth/fem/hex8.hpp"
#include "fabsynth/fem/inp.hpp"
#include "fabsynth/fem/material.hpp"
#include "fabsynth/fem/mesh.hpp"
#include "fabsynth/fem/shell3.hpp"
#include "fabsynth/fem/solvers.hpp"
#include "fabsynth/fem/solve_context.hpp"
#include "fabsynth/fem/inp_writer.hpp"
#include "fabsynth/fem/amg.hpp"
#include "fabsynth/fem/stress.hpp"
#include "fabsynth/fem/wedge6.hpp"
#include "fabsynth/fem/voxel.hpp"
#include "fabsynth/fem/homogenization.hpp"
