// SPDX-License-Identifier: MIT
#pragma once
/// @file topology.hpp  Topology building blocks: descriptors of sliced patterns, their merge and
/// loop closing, and the policies that plug them into the DP sequence solver (fabsynth/dp.hpp).
#include "fabsynth/topology/descriptor.hpp"
