# SPDX-License-Identifier: MIT
"""Finite elements (fabsynth::fem): a linear static solve of an Abaqus/CalculiX deck, periodic homogenization."""
from ._fabsynth.fem import homogenize, solve_inp, solve_inp_text

__all__ = ["homogenize", "solve_inp", "solve_inp_text"]
