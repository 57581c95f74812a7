// SPDX-License-Identifier: MIT
#pragma once
/// @file filigree.hpp  Umbrella header of the filigree pipeline (Chen, Zhang, Xin, Xia, Lefebvre &
/// Wang 2016, filigree-synthesis.md): elements from SVG drawings (filigree/element.hpp), the planar
/// domain (filigree/domain.hpp) and control fields (filigree/field.hpp), placed instances
/// (filigree/pattern.hpp), the pattern matching energy (filigree/matching.hpp), initialization by
/// dart throwing (filigree/initialization.hpp), placement optimization (filigree/placement.hpp)
/// with smooth connections by free-form deformation (filigree/deformation.hpp,
/// filigree/connection.hpp), boosting (filigree/boosting.hpp), the topology cut
/// (filigree/topology_cut.hpp), the driver of these steps (filigree/synthesis.hpp), strips and
/// meshes (filigree/reconstruct.hpp), the shell-FEM analysis (filigree/structure.hpp) and the
/// structural optimization (filigree/reinforcement.hpp).
#include "fabsynth/filigree/element.hpp"
#include "fabsynth/filigree/domain.hpp"
#include "fabsynth/filigree/field.hpp"
#include "fabsynth/filigree/pattern.hpp"
#include "fabsynth/filigree/matching.hpp"
#include "fabsynth/filigree/initialization.hpp"
#include "fabsynth/filigree/placement.hpp"
#include "fabsynth/filigree/deformation.hpp"
#include "fabsynth/filigree/connection.hpp"
#include "fabsynth/filigree/boosting.hpp"
#include "fabsynth/filigree/topology_cut.hpp"
#include "fabsynth/filigree/synthesis.hpp"
#include "fabsynth/filigree/reconstruct.hpp"
#include "fabsynth/filigree/structure.hpp"
#include "fabsynth/filigree/reinforcement.hpp"
