// The .inp reader: bundled decks against independently built models and analytic values, and
// every unsupported or malformed input reported by name and line.
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/fem/inp.hpp"
#include "fabsynth/fem/solve_context.hpp"
#include "fabsynth/fem/stress.hpp"

using namespace fabsynth;
using namespace fabsynth::fem;

namespace {
std::string slurp(const std::string& name) {
    std::ifstream in(std::string(FABSYNTH_DATA_DIR) + "/fem/" + name, std::ios::binary);
    REQUIRE(in);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}
const char* tiny_deck =
    "*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n5,0,0,1\n6,1,0,1\n7,1,1,1\n8,0,1,1\n"
    "*ELEMENT, TYPE=C3D8, ELSET=E\n1,1,2,3,4,5,6,7,8\n*MATERIAL,NAME=M\n*ELASTIC\n100.,0.25\n"
    "*SOLID SECTION,ELSET=E,MATERIAL=M\n";
}  // namespace

TEST_CASE("inp: plate deck equals the programmatic plate and the plate table", "[fem][inp]") {
    const inp_deck d = parse_inp(slurp("plate_s3_simply_supported.inp"), "plate.inp");
    CHECK(d.model.nodes.size() == 81);
    CHECK(d.model.elements.size() == 128);
    CHECK(d.model.elements[0].kind == element_kind::shell3);
    CHECK(d.node_sets.at("YEDGES").size() == 18);
    CHECK(d.node_sets.at("EDGES").size() == 36);
    CHECK(d.loads.pressures.size() == 128);
    const auto r = solve_linear_static(d.model, d.loads);
    // Centre node: id 41 is (4, 4) in the 9 x 9 grid.
    std::size_t c = 0;
    while (d.model.node_ids[c] != 41) ++c;
    const double D = 1000.0 / (12 * (1 - 0.09));
    const double table = 0.00406 * 1e-3 * 1e8 / D;
    // CalculiX's sign: +P pushes along the normal (+z for these counter-clockwise triangles)
    CHECK(r.displacement(c).z == Approx(table).epsilon(0.015));
    // Reactions carry the whole pressure resultant q a^2.
    double rz = 0;
    for (std::size_t i = 0; i < d.model.nodes.size(); ++i) rz += r.reactions(static_cast<Eigen::Index>(r.dofs.offset[i] + 2));
    CHECK(rz == Approx(-1e-3 * 100 * 100));
}

TEST_CASE("inp: cantilever deck equals the same beam built with make_box_mesh", "[fem][inp]") {
    const inp_deck d = parse_inp(slurp("cantilever_c3d8.inp"), "cantilever.inp");
    REQUIRE(d.model.elements.size() == 80);
    CHECK(d.ignored_keywords.size() == 2);  // *NODE PRINT, *EL PRINT
    CHECK(d.model.sections[0].material == isotropic_material{3500, 0.36, 1.24e-9});
    const auto r = solve_linear_static(d.model, d.loads);
    mesh m = make_box_mesh(vec3(0.0), vec3(100, 10, 10), ivec3(20, 2, 2), {isotropic_material::pla()});
    load_case lc;
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
        const vec3 p = m.nodes[i];
        if (p.x == 0)
            for (int k = 0; k < 3; ++k) lc.fixed.push_back({static_cast<std::uint32_t>(i), k});
        if (p.x == 100) {
            const double w = ((p.y == 0 || p.y == 10) ? 0.5 : 1.0) * ((p.z == 0 || p.z == 10) ? 0.5 : 1.0) / 4;
            lc.forces.push_back({static_cast<std::uint32_t>(i), 2, -10 * w});
        }
    }
    const auto r2 = solve_linear_static(m, lc);
    CHECK((r.u - r2.u).norm() < 1e-12 * r2.u.norm());  // node ids 1.. map to the same 0-based order
}

TEST_CASE("inp: mixed solid/shell deck, DOF counts and equilibrium", "[fem][inp]") {
    const inp_deck d = parse_inp(slurp("mixed_c3d8_c3d6_s3.inp"), "mixed.inp");
    const mesh& m = d.model;
    REQUIRE(m.elements.size() == 6);
    CHECK(m.elements[2].kind == element_kind::wedge6);
    CHECK(m.elements[5].kind == element_kind::shell3);
    CHECK(m.sections.size() == 2);
    const dof_map dofs(m);
    CHECK(dofs.total == 12 * 3 + 4 * 6);
    CHECK(d.loads.gravity.size() == 6);
    const auto r = solve_linear_static(m, d.loads);
    // Vertical reactions balance the 5 N point load plus the weight rho g (V_solid + A t).
    const double weight = 1.04e-9 * 9810 * (2 * 1000 + 2 * 500 + 100 * 0.8);
    double rz = 0;
    for (std::size_t i = 0; i < m.nodes.size(); ++i) rz += r.reactions(static_cast<Eigen::Index>(r.dofs.offset[i] + 2));
    CHECK(rz == Approx(5 + weight).epsilon(1e-9));
    for (const auto& s : centroid_stresses(m, r)) CHECK(s.allFinite());
}

TEST_CASE("inp: unsupported and malformed input is reported by name and line", "[fem][inp][errors]") {
    const std::string base = tiny_deck;
    auto err = [&](const std::string& extra) -> std::string {
        try {
            (void)parse_inp(base + extra, "deck.inp");
        } catch (const io_error& e) {
            return e.what();
        }
        return "no error";
    };
    CHECK_THAT(err("*FOO, BAR=1\n1\n"), Catch::Contains("deck.inp:16") && Catch::Contains("unsupported keyword *FOO"));
    CHECK_THAT(err("*INCLUDE, INPUT=x.inp\n"), Catch::Contains("*INCLUDE"));
    CHECK_THAT(err("*ELEMENT, TYPE=C3D20\n"), Catch::Contains("C3D20"));
    CHECK_THAT(err("*ELEMENT, TYPE=C3D8\n2,1,2,3,4,5,6,7,99\n"), Catch::Contains("undefined node 99"));
    CHECK_THAT(err("*BOUNDARY\n1, 5\n"), Catch::Contains("has no dof 5"));
    CHECK_THAT(err("*BOUNDARY\nNOSUCH, 1\n"), Catch::Contains("node set NOSUCH is not defined"));
    CHECK_THAT(err("*BOUNDARY\n1, XYZSYMM\n"), Catch::Contains("XYZSYMM"));
    CHECK_THAT(err("*DLOAD\nE, P, 1.0\n"), Catch::Contains("pressure only on S3"));
    CHECK_THAT(err("*DLOAD\nE, GRAV, 9810, 0, 0, -1\n"), Catch::Contains("no *DENSITY"));
    CHECK_THAT(err("*DLOAD\nE, BX, 1.0\n"), Catch::Contains("BX"));
    CHECK_THAT(err("*CLOAD\n1, 3, abc\n"), Catch::Contains("deck.inp:17") && Catch::Contains("'abc'"));
    CHECK_THAT(err("*NSET, NSET=A, GENERATE\n1, 2000000000\n"), Catch::Contains("too large"));
    CHECK_THAT(err("*STEP, NLGEOM=YES\n"), Catch::Contains("NLGEOM"));
    CHECK_THAT(err("*STEP\n*STATIC\n"), Catch::Contains("without *END STEP"));
    CHECK_THAT(err("*NODE\n1, 5, 5, 5\n"), Catch::Contains("node 1 is defined twice"));
    CHECK_THAT(err("*ELASTIC\n1,0.3\n"), Catch::Contains("outside a *MATERIAL"));
    CHECK_THAT(err("*ELEMENT, TYPE=C3D8, ELSET=F\n2,1,2,3,4,5,6,7,8\n"), Catch::Contains("element 2 has no *SOLID SECTION"));
    CHECK_THAT(err("*MATERIAL, NAME=B\n*ELASTIC\n100, 0.7\n*SOLID SECTION, ELSET=E, MATERIAL=B\n"), Catch::Contains("Poisson"));
    // values that would overflow the element integrals are refused at their line
    CHECK_THAT(err("*NODE\n90, 1e308, 0, 0\n"), Catch::Contains("deck.inp:17") && Catch::Contains("x = 1e308 is out of range"));
    CHECK_THAT(err("*MATERIAL, NAME=B\n*ELASTIC\n1e308, 0.3\n"), Catch::Contains("deck.inp:18") && Catch::Contains("E = 1e308"));
    CHECK_THAT(err("*CLOAD\n1, 3, -1e31\n"), Catch::Contains("out of range"));
    CHECK_NOTHROW(parse_inp(base + "*BOUNDARY\n1, ENCASTRE\n", "ok.inp"));  // rotations skipped on solid nodes
}

TEST_CASE("inp: mutated decks only ever throw fabsynth::error", "[fem][inp][errors]") {
    const std::string deck = slurp("mixed_c3d8_c3d6_s3.inp");
    int parsed = 0;
    for (std::uint64_t it = 0; it < 400; ++it) {
        counter_rng rng(2024, it);
        std::string t = deck;
        const int edits = 1 + static_cast<int>(rng.uniform_int(4));
        for (int k = 0; k < edits; ++k) {
            const auto pos = static_cast<std::size_t>(rng.uniform_int(t.size()));
            const char pool[] = ",*\n0123456789.-eE ABCZ";
            t[pos] = pool[rng.uniform_int(sizeof pool - 1)];
        }
        try {
            const inp_deck d = parse_inp(t, "mutant.inp");
            ++parsed;
            (void)solve_linear_static(d.model, d.loads);
        } catch (const fabsynth::error&) {
        }
    }
    CHECK(parsed > 0);
}
