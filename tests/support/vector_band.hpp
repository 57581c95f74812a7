#pragma once
// A bundled vector exemplar (data/vector/FILE) in band coordinates: u from 0, v centred on 0.
// Shared by the band-map, extrusion, piece and synthesis tests.
#include <string>
#include <vector>

#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/io/svg.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"

namespace fabsynth::test {

/// The bundled band exemplars (data/vector/).
inline constexpr const char* bundled_vector_files[] = {"lace_scallop.svg", "greek_key.svg", "pearls.svg", "vine.svg",
                                                       "quatrefoil.svg",   "hearts.svg",    "zigzag.svg",
                                                       "disks.svg",        "leaves.svg"};

/// A bundled band exemplar as read by exemplar_from_svg.
inline vector_pattern::exemplar load_vector_exemplar(const std::string& file) {
    return vector_pattern::exemplar_from_svg(io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/" + file));
}

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
