// Filigree on a base surface, reconstruction and structure (filigree-synthesis.md §5, §6): the baked
// mesh M_b of a pattern on a flat mesh has the area of the 2D strips of the same skeletons; on a
// cylinder M_b is one edge-connected piece whose thickened solid is watertight; the shell model of
// M_b agrees with CalculiX (an independent solver, S3 elements) on the exported deck; after the
// structural optimization no node is weak.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fabsynth/fem/inp_writer.hpp"
#include "fabsynth/fem/solve_context.hpp"
#include "fabsynth/filigree/reconstruct.hpp"
#include "fabsynth/filigree/surface_structure.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/surface_offset.hpp"
#include "fabsynth/io/svg.hpp"
#include "support/sphere_mesh.hpp"
#include "support/surface_setup.hpp"

namespace surface_struct_test {

using namespace fabsynth;
using namespace fabsynth::filigree;
namespace fs = std::filesystem;

inline element scroll(double size) {
    element_options o;
    o.size_mm = size;
    o.width_mm = 0.8;
    o.name = "c_scroll";
    return element_from_svg(io::read_svg(fs::path(FABSYNTH_DATA_DIR) / "filigree" / "c_scroll.svg", 0.01), o);
}



// Edge-connected pieces, counted here with a map of edges and a flood fill (no library helper).
inline std::size_t edge_pieces(const triangle_mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> by_edge;
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const auto a = m.faces[f][static_cast<std::size_t>(k)], b = m.faces[f][static_cast<std::size_t>((k + 1) % 3)];
            by_edge[{std::min(a, b), std::max(a, b)}].push_back(f);
        }
    std::vector<int> seen(m.faces.size(), 0);
    std::size_t pieces = 0;
    for (std::size_t s = 0; s < m.faces.size(); ++s) {
        if (seen[s]) continue;
        ++pieces;
        std::vector<std::size_t> stack{s};
        seen[s] = 1;
        while (!stack.empty()) {
            const std::size_t f = stack.back();
            stack.pop_back();
            for (int k = 0; k < 3; ++k) {
                const auto a = m.faces[f][static_cast<std::size_t>(k)], b = m.faces[f][static_cast<std::size_t>((k + 1) % 3)];
                for (const std::size_t g : by_edge[{std::min(a, b), std::max(a, b)}])
                    if (!seen[g]) seen[g] = 1, stack.push_back(g);
            }
        }
    }
    return pieces;
}

TEST_CASE("surface baking on a flat mesh: M_b has the area and pieces of the 2D strips of the same skeletons", "[filigree][surface][bake]") {
    const std::vector<element> cls{scroll(14)};
    const std::vector<double> w{1.0};
    const fabsynth::test::surface_setup flat(fabsynth::test::plane_grid(25, 2.0, 1, 0.0), {0, 1, 0});
    synthesis_options so;
    so.max_rounds = 1;
    const auto r = synthesize_on_surface(cls, w, flat.region, flat.field(), so);
    const surface_space s(cls, r.instances, flat.field(), flat.region);
    const triangle_mesh mb = bake_pattern(s, r.skeletons);
    // the same skeletons in the plane: picture + reference point (a translation on a flat mesh)
    std::vector<graph::skeleton_graph<vec2>> sk;
    for (std::size_t i = 0; i < r.instances.size(); ++i) {
        graph::skeleton_graph<vec2> g;
        const vec3 a = flat.patcher.position(r.instances[i].anchor);
        for (std::size_t v = 0; v < r.skeletons[i].picture.size(); ++v) g.add_vertex(r.skeletons[i].picture[v] + vec2(a.x, a.y), r.skeletons[i].widths[v]);
        for (const auto& e : r.skeletons[i].edges) g.add_edge(e[0], e[1]);
        sk.push_back(std::move(g));
    }
    const auto strips = strip_outline(std::span<const graph::skeleton_graph<vec2>>(sk),
                                      std::vector<polygon_with_holes>{{ring2{{0, 0}, {50, 0}, {50, 50}, {0, 50}}, {}}});
    CHECK(surface_area(mb) == Approx(area(strips)).epsilon(1e-4));  // arcs flattened in each picture vs once
    CHECK(edge_pieces(mb) == strips.size());
}

TEST_CASE("surface filigree on a cylinder: M_b one piece, watertight solid, shell model agrees with CalculiX, no weak node after the structural optimization",
          "[filigree][surface][structure]") {
    const std::vector<element> cls{scroll(12)};
    const std::vector<double> w{1.0};
    const fabsynth::test::surface_setup band(fabsynth::test::cylinder(15, 24, 48, 1.5), {0, 0, 1});
    synthesis_options so;
    so.max_rounds = 1;
    so.seed = 4;
    const auto syn = synthesize_on_surface(cls, w, band.region, band.field(), so);
    surface_reinforcement_options ro;
    ro.up = {0, 0, 1};
    ro.base.thickness = 0.6;
    const auto rf = reinforce_on_surface(cls, w, band.region, band.field(), so, syn, ro);
    CHECK(edge_pieces(rf.baked) == 1);
    CHECK(rf.dropped_area_fraction < 0.05);
    REQUIRE(rf.analysed);
    CHECK(rf.weak_fraction_phase2.back() == 0.0);
    CHECK(rf.max_von_mises_after <= rf.yield_mpa);

    const triangle_mesh solid = thicken_surface(rf.baked, rf.thickness, {.cell = rf.thickness / 3});
    const auto topo = analyze_topology(solid);
    CHECK(topo.is_watertight());
    CHECK(topo.components == 1);

    // The shell model of the analysis, solved here and by CalculiX on the written deck.
    // ccx expands S3 into wedges of the shell's thickness along averaged nodal normals; the slivers
    // the booleans leave invert them unless the shell is thin against the elements, hence a coarser
    // vertex merge and a thin shell here
    triangle_mesh fem_mesh = fem_mesh_of(rf.baked, 0.2);
    for (vec3& v : fem_mesh.vertices)  // ccx reads fields of at most 20 characters: coordinates on a 1e-9 mm grid print short
        for (int k = 0; k < 3; ++k) v[k] = std::round(v[k] * 1e9) / 1e9;
    if (std::system("command -v ccx > /dev/null 2>&1") != 0) {
        WARN("ccx (Debian calculix-ccx) not found: CalculiX oracle skipped");
        return;
    }
    struct agreement {
        double umax = 0, diff = 0, correlation = 0, rms_ratio = 0;  // rms_ratio: |u_ccx|_2 / |u_ours|_2
    };
    auto compare = [&](const structure_options& sopt, const std::string& name) {
        const fem::mesh model = shell_model(fem_mesh, 0.1, sopt.material);
        const auto supports = support_nodes_along(fem_mesh, {0, 0, 1}, sopt.support_fraction);
        const fem::load_case lc = structural_load_case(model, supports, sopt, {0, 0, -1});
        const fem::static_result ours = fabsynth::filigree::detail::structure::solve_checked(model, lc, {});
        const fs::path dir = fs::path(FABSYNTH_TEST_TMP) / ("ccx_surface_" + name);
        fs::create_directories(dir);
        std::ofstream(dir / "deck.inp") << fem::write_inp(model, lc, {.heading = "fabsynth surface filigree", .print_displacements = true});
        REQUIRE(std::system(("cd '" + dir.string() + "' && ccx -i deck > ccx.log 2>&1").c_str()) == 0);
        std::ifstream dat(dir / "deck.dat");
        std::map<long, vec3> theirs;
        std::string line;
        bool block = false;
        while (std::getline(dat, line)) {
            if (line.find("displacements") != std::string::npos) {
                block = true;
                continue;
            }
            std::istringstream in(line);
            long n = 0;
            double x = 0, y = 0, z = 0;
            if (block && (in >> n >> x >> y >> z)) theirs[n] = {x, y, z};
        }
        REQUIRE(theirs.size() >= model.nodes.size());
        agreement a;
        double dot = 0, n1 = 0, n2 = 0;
        for (std::size_t i = 0; i < model.nodes.size(); ++i) {
            const vec3 u = ours.displacement(i), v = theirs.at(static_cast<long>(i) + 1);
            a.umax = std::max(a.umax, glm::length(u));
            a.diff = std::max(a.diff, glm::length(u - v));
            dot += glm::dot(u, v), n1 += glm::dot(u, u), n2 += glm::dot(v, v);
        }
        a.correlation = dot / std::sqrt(n1 * n2);
        a.rms_ratio = std::sqrt(n2 / n1);
        return a;
    };
    // ccx expands each S3 into one layer of linear wedges (C3D6), which lock in bending, so it is
    // stiffer than the CST + DKT shell; the displacement fields must still point the same way (a
    // wrong load direction or sign gives a correlation near 0 or -1: this comparison found the
    // opposite pressure sign of the deck writer) and ccx may not be softer.
    structure_options weight;  // self weight alone
    weight.pressure_pa = 0;
    const agreement sw = compare(weight, "weight");
    INFO("self weight: max |u| " << sw.umax << " mm, max difference " << sw.diff << " mm, correlation " << sw.correlation << ", rms ratio "
                                 << sw.rms_ratio);
    CHECK(sw.correlation > 0.8);
    CHECK(sw.rms_ratio > 0.2);
    CHECK(sw.rms_ratio < 1.05);
    const agreement p = compare(structure_options{}, "pressure");  // the pipeline's load case
    INFO("pressure: max |u| " << p.umax << " mm, max difference " << p.diff << " mm, correlation " << p.correlation << ", rms ratio " << p.rms_ratio);
    CHECK(p.correlation > 0.95);
    CHECK(p.rms_ratio > 0.2);
    CHECK(p.rms_ratio < 1.05);
}

}  // namespace surface_struct_test
