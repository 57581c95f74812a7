#pragma once
// A bundled vector exemplar (data/vector/FILE) in band coordinates: u from 0, v centred on 0.
// Shared by the band-map and extrusion tests.
#include <string>
#include <vector>

#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/io/svg.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"

namespace fabsynth::test {

inline std::vector<polygon_with_holes> vector_band(const std::string& file, double* width = nullptr) {
    const auto ex = vector_pattern::exemplar_from_svg(io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/" + file));
    std::vector<polygon_with_holes> band = ex.polygons;
    const vec2 shift{-ex.bounds.lo.x, -ex.bounds.center().y};
    for (auto& p : band) {
        for (vec2& q : p.outer) q += shift;
        for (auto& h : p.holes)
            for (vec2& q : h) q += shift;
    }
    if (width) *width = ex.width();
    return band;
}

}  // namespace fabsynth::test
