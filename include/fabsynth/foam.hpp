#pragma once
/// @file foam.hpp  Procedural Voronoi foams (Martinez, Dumas & Lefebvre, SIGGRAPH 2016): graded
/// jittered seeds (Algorithm 3), an exact per-point evaluator and a fast tiled slicer, a surface
/// frame following a mesh, beam-network export and the elasticity -> (rho, tau) inverse mapping.
#include "fabsynth/foam/beams.hpp"
#include "fabsynth/foam/elasticity.hpp"
#include "fabsynth/foam/evaluator.hpp"
#include "fabsynth/foam/fields.hpp"
#include "fabsynth/foam/fit.hpp"
#include "fabsynth/foam/frame.hpp"
#include "fabsynth/foam/seeds.hpp"
