// check_pattern_output OUT.svg OUT.stl PIXEL: re-counts the topology of a curve_patterns result
// independently of the library's synthesis code and prints one line
//   components C holes H watertight W shapes S filled_only F
// - components/holes: every subpath of the SVG (read back with io::read_svg) is rasterized by the
//   even-odd scanline oracle of tests/support/raster_topology.hpp at PIXEL mm (no Clipper, no
//   polygon grouping), solid 8-connected components and enclosed empty 4-connected regions;
// - watertight: the STL (io::read_stl welds coincident vertices) has every edge in exactly two
//   faces with opposite orientations (geometry/mesh_topology.hpp) and positive volume;
// - filled_only: every shape is filled and none is stroked.
// Exit status 2 on unreadable input.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/io/mesh_stl.hpp"
#include "fabsynth/io/svg.hpp"
#include "support/raster_topology.hpp"

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: check_pattern_output OUT.svg OUT.stl PIXEL\n");
        return 2;
    }
    try {
        const double pixel = std::stod(argv[3]);
        const fabsynth::io::svg_document doc = fabsynth::io::read_svg(argv[1]);
        std::vector<fabsynth::polygon_with_holes> rings;  // one "polygon" per ring: the oracle fills even-odd over all
        bool filled_only = !doc.shapes.empty();
        for (const auto& s : doc.shapes) {
            filled_only = filled_only && s.filled() && !s.stroked();
            for (const auto& sp : s.subpaths) rings.push_back({sp, {}});
        }
        const fabsynth::box2 b = doc.bounds();
        if (b.empty()) throw std::runtime_error("no shape in the SVG");
        const auto t = fabsynth::test::raster_topology(rings, b.lo, b.hi, pixel);
        const fabsynth::triangle_mesh m = fabsynth::io::read_stl(argv[2]);
        const bool watertight = fabsynth::analyze_topology(m).is_watertight() && fabsynth::signed_volume(m) > 0.0;
        std::printf("components %zu holes %zu watertight %d shapes %zu filled_only %d\n", t.components, t.holes,
                    watertight ? 1 : 0, doc.shapes.size(), filled_only ? 1 : 0);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "check_pattern_output: %s\n", e.what());
        return 2;
    }
    return 0;
}
