// SPDX-License-Identifier: MIT
#pragma once
/// @file dp.hpp  Dynamic-programming building blocks: the generic sequence solver with its policy
/// concepts and precomputed transition tables (dp/sequence_solver.hpp). Transition costs of a
/// particular problem live with it (vector patterns: vector_pattern/portal_cost.hpp).
#include "fabsynth/dp/sequence_solver.hpp"
