// SPDX-License-Identifier: MIT
#pragma once
/// @file filigree.hpp  Umbrella header of the filigree pipeline (Chen, Zhang, Xin, Xia, Lefebvre &
/// Wang 2016, filigree-synthesis.md): elements from SVG drawings (filigree/element.hpp), the planar
/// domain (filigree/domain.hpp) and control fields (filigree/field.hpp), placed instances
/// (filigree/pattern.hpp), the pattern matching energy (filigree/matching.hpp), initialization by
/// dart throwing (filigree/initialization.hpp), placement optimization (filigree/placement.hpp)
/// with smooth connections by free-form deformation (filigree/ffd.hpp, filigree/contact.hpp,
/// filigree/connection.hpp), boosting (filigree/boosting.hpp), the topology cut
/// (filigree/topology_cut.hpp), the driver of these steps (filigree/synthesis.hpp), strips and
/// meshes (filigree/reconstruct.hpp), the shell-FEM analysis (filigree/structure.hpp) and the
/// structural optimization (filigree/reinforcement.hpp); the whole pipeline in one call,
/// make_filigree (filigree/pipeline.hpp). On a base surface (part 2, filigree/surface/): control
/// fields (field.hpp), synthesis through local maps (space.hpp, synthesis.hpp), the topology cut
/// (topology_cut.hpp), baking (reconstruct.hpp), the structure on M_b (structure.hpp) and the
/// pipeline in one call (pipeline.hpp: make_filigree on a mesh).
#include "fabsynth/filigree/element.hpp"
#include "fabsynth/filigree/domain.hpp"
#include "fabsynth/filigree/field.hpp"
#include "fabsynth/filigree/pattern.hpp"
#include "fabsynth/filigree/matching.hpp"
#include "fabsynth/filigree/initialization.hpp"
#include "fabsynth/filigree/placement.hpp"
#include "fabsynth/filigree/ffd.hpp"
#include "fabsynth/filigree/contact.hpp"
#include "fabsynth/filigree/connection.hpp"
#include "fabsynth/filigree/boosting.hpp"
#include "fabsynth/filigree/topology_cut.hpp"
#include "fabsynth/filigree/synthesis.hpp"
#include "fabsynth/filigree/reconstruct.hpp"
#include "fabsynth/filigree/structure.hpp"
#include "fabsynth/filigree/reinforcement.hpp"
#include "fabsynth/filigree/appearance.hpp"
#include "fabsynth/filigree/figures.hpp"
#include "fabsynth/filigree/pipeline.hpp"
#include "fabsynth/filigree/surface/pipeline.hpp"
