#pragma once
/// @file dp.hpp  Dynamic-programming building blocks: the generic sequence solver with its policy
/// concepts, precomputed transition tables and the portal matching costs of §3.6.1.
#include "fabsynth/dp/sequence_solver.hpp"
