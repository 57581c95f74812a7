// A base mesh with the whole of it as the filigree region, an up-vector direction field and scale 1
// (the set-up of the surface filigree tests).
#pragma once

#include <utility>

#include "fabsynth/filigree/surface/field.hpp"
#include "fabsynth/filigree/surface/space.hpp"
#include "fabsynth/surface/exponential_map.hpp"

namespace fabsynth::test {

struct surface_setup {
    triangle_mesh mesh;
    surface_patcher patcher;
    filigree::surface_region region;
    filigree::surface_direction_field direction;
    filigree::surface_scale_field scale;
    surface_setup(triangle_mesh m, vec3 up)
        : mesh(std::move(m)), patcher(mesh), region(filigree::surface_region::whole(patcher)),
          direction(filigree::surface_direction_field::from_up_vector(patcher, up)), scale(filigree::surface_scale_field::constant(mesh, 1.0)) {}
    surface_setup(const surface_setup&) = delete;  // the patcher and fields point into this object
    [[nodiscard]] filigree::surface_control field() const { return {&direction, &scale}; }
};

}  // namespace fabsynth::test
