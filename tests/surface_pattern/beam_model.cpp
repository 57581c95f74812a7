#include <catch2/catch.hpp>

#include "support/test_util.hpp"

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/fem/stress.hpp>
#include <fabsynth/surface_pattern/beam_model.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

using namespace fabsynth;
namespace sp = fabsynth::surface_pattern;

namespace {

/// Restores the thread setting on scope exit.

/// Vertical column of n vertices at z = 0, 10, ... on a wall with normal +x, edges (i, i+1).
std::pair<std::vector<sp::beam_vertex>, std::vector<sp::beam_edge>> column(int n, double spacing = 10.0) {
    std::vector<sp::beam_vertex> v;
    std::vector<sp::beam_edge> e;
    for (int i = 0; i < n; ++i) v.push_back({{0, 0, spacing * i}, {1, 0, 0}});
    for (int i = 0; i + 1 < n; ++i) e.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i + 1), true});
    return {v, e};
}

/// nx x nz grid in the wall y = 0 (normal -y), centred on x = 0, spacing 10 mm, 4-neighbour edges.
struct grid {
    int nx, nz;
    std::vector<sp::beam_vertex> v;
    std::vector<sp::beam_edge> e;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> index;
    std::uint32_t id(int i, int k) const { return static_cast<std::uint32_t>(i + nx * k); }
    grid(int nx_, int nz_) : nx(nx_), nz(nz_) {
        for (int k = 0; k < nz; ++k)
            for (int i = 0; i < nx; ++i) v.push_back({{10.0 * (i - 0.5 * (nx - 1)), 0, 10.0 * k}, {0, -1, 0}});
        auto add = [&](std::uint32_t a, std::uint32_t b) {
            index[{std::min(a, b), std::max(a, b)}] = e.size();
            e.push_back({a, b, true});
        };
        for (int k = 0; k < nz; ++k)
            for (int i = 0; i < nx; ++i) {
                if (i + 1 < nx) add(id(i, k), id(i + 1, k));
                if (k + 1 < nz) add(id(i, k), id(i, k + 1));
            }
    }
    std::size_t edge(std::uint32_t a, std::uint32_t b) const { return index.at({std::min(a, b), std::max(a, b)}); }
    /// The edge mirrored by x -> -x.
    std::size_t mirror(std::size_t k) const {
        auto m = [&](std::uint32_t a) { return id(nx - 1 - static_cast<int>(a % nx), static_cast<int>(a / nx)); };
        return edge(m(e[k].a), m(e[k].b));
    }
};

/// Fibonacci points on a sphere (radius R, centre (0, 0, R)), edges to the k nearest neighbours.
std::pair<std::vector<sp::beam_vertex>, std::vector<sp::beam_edge>> fibonacci_sphere(int n, double R, int k) {
    std::vector<sp::beam_vertex> v;
    const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1 - 2 * (i + 0.5) / n, rr = std::sqrt(1 - z * z), phi = golden * i;
        const vec3 nrm(rr * std::cos(phi), rr * std::sin(phi), z);
        v.push_back({vec3(0, 0, R) + R * nrm, nrm});
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, bool> pairs;
    for (int i = 0; i < n; ++i) {
        std::vector<std::pair<double, int>> d;
        for (int j = 0; j < n; ++j)
            if (j != i) d.emplace_back(glm::length(v[static_cast<std::size_t>(i)].position - v[static_cast<std::size_t>(j)].position), j);
        std::partial_sort(d.begin(), d.begin() + k, d.end());
        for (int c = 0; c < k; ++c)
            pairs[{static_cast<std::uint32_t>(std::min(i, d[static_cast<std::size_t>(c)].second)),
                   static_cast<std::uint32_t>(std::max(i, d[static_cast<std::size_t>(c)].second))}] = true;
    }
    std::vector<sp::beam_edge> e;
    for (const auto& [p, _] : pairs) e.push_back({p.first, p.second, (p.first + p.second) % 3 != 0});
    return {v, e};
}

/// Axial stress sigma_aa (carried, at the centroid) of the beam of edge k, a = beam direction.
double axial_stress(const sp::beam_model& m, const std::vector<sp::beam_vertex>& v, const std::vector<sp::beam_edge>& e, std::size_t k) {
    const fem::voigt6 s = fem::element_stress(m.mesh(), m.last_result(), m.edge_element(k), fem::hex8::centroid());
    const vec3 a = glm::normalize(v[e[k].b].position - v[e[k].a].position);
    const Eigen::Vector3d av(a.x, a.y, a.z);
    return av.dot(fem::to_tensor(s) * av);
}

double max_of(const std::vector<double>& x) { return *std::max_element(x.begin(), x.end()); }

}  // namespace

TEST_CASE("beam_model: a column under gravity carries the weight above each beam (statics)", "[surface_pattern][beam]") {
    const int n = 6;
    auto [v, e] = column(n);
    const sp::beam_options opt{.thickness_mm = 1.0, .beam_width_mm = 2.0};
    sp::beam_model model(v, e, opt);
    const double A = 2.0 * 1.0, F = opt.load_per_vertex_n;
    const auto score = model.solve();
    REQUIRE(score.size() == e.size());
    // Only the bottom hub is held (lowest 10% of the extent).
    const auto [b0, b1] = model.vertex_nodes(0);
    CHECK(model.statistics().fixed_nodes == b1 - b0);
    for (std::size_t k = 0; k < e.size(); ++k) {
        const double above = n - 1 - static_cast<double>(k);  // vertices k+1 .. n-1 hang on beam (k, k+1)
        const double expected = above * F / A;               // compression [MPa]
        INFO("beam " << k);
        CHECK(axial_stress(model, v, e, k) == Approx(-expected).epsilon(0.02));
        // The beam next to the held hub also feels its clamped Poisson contraction (one element
        // per beam); away from the support the score is the axial stress alone.
        if (k > 0) CHECK(score[k] == Approx(expected).epsilon(0.03));
        else CHECK(score[k] > expected);
    }
    // Total reaction along z = the total load.
    double rz = 0;
    for (const auto& f : model.supports().fixed)
        if (f.dof == 2) rz += model.last_result().reactions(static_cast<Eigen::Index>(model.last_result().dofs.index(f.node, 2)));
    CHECK(rz == Approx(n * F).epsilon(1e-9));
}

TEST_CASE("beam_model: a force profile hangs the column from its top vertex", "[surface_pattern][beam]") {
    auto [v, e] = column(5);
    sp::force_profile fp;
    fp.fixed_vertices = {4};
    fp.loads = {{0, vec3(0, 0, -3.0)}};  // 3 N pulling the bottom vertex down
    sp::beam_model model(v, e, {.beam_width_mm = 1.5, .sample = sp::beam_stress_sample::centre}, fp);
    const auto score = model.solve();
    const double A = 1.5 * 1.0;
    for (std::size_t k = 0; k < e.size(); ++k) {
        INFO("beam " << k);
        CHECK(axial_stress(model, v, e, k) == Approx(3.0 / A).epsilon(0.02));  // tension everywhere
        if (k + 1 < e.size()) CHECK(score[k] == Approx(3.0 / A).epsilon(0.03));  // the last one is clamped
    }
}

TEST_CASE("beam_model: a mirror-symmetric wall gives mirror-symmetric scores", "[surface_pattern][beam]") {
    grid g(5, 4);
    // Break the regularity symmetrically: two mirrored vertical edges and the central rung empty.
    const std::size_t a = g.edge(g.id(1, 1), g.id(1, 2));
    g.e[a].solid = false;
    g.e[g.mirror(a)].solid = false;
    g.e[g.edge(g.id(1, 2), g.id(2, 2))].solid = false;
    g.e[g.edge(g.id(3, 2), g.id(2, 2))].solid = false;
    sp::beam_model model(g.v, g.e, {.thickness_mm = 1.2});
    const auto score = model.solve();
    const double top = max_of(score);
    REQUIRE(top > 0);
    for (std::size_t k = 0; k < g.e.size(); ++k) {
        INFO("edge " << k << " mirror " << g.mirror(k));
        CHECK(std::abs(score[k] - score[g.mirror(k)]) <= 1e-6 * top);
        CHECK(std::isfinite(score[k]));
    }
}

TEST_CASE("beam_model: an empty edge sends its load through the other path", "[surface_pattern][beam]") {
    // A ladder: columns at x = -5 and x = +5, rows z = 0..30, rungs on every row; bottom row held.
    std::vector<sp::beam_vertex> v;
    std::vector<sp::beam_edge> e;
    for (int k = 0; k < 4; ++k)
        for (int s = 0; s < 2; ++s) v.push_back({{s ? 5.0 : -5.0, 0, 10.0 * k}, {0, -1, 0}});
    auto id = [](int s, int k) { return static_cast<std::uint32_t>(s + 2 * k); };
    for (int k = 0; k < 4; ++k) {
        e.push_back({id(0, k), id(1, k), true});
        if (k < 3) e.push_back({id(0, k), id(0, k + 1), true}), e.push_back({id(1, k), id(1, k + 1), true});
    }
    auto find = [&](std::uint32_t a, std::uint32_t b) {
        for (std::size_t k = 0; k < e.size(); ++k)
            if ((e[k].a == a && e[k].b == b) || (e[k].a == b && e[k].b == a)) return k;
        return e.size();
    };
    const std::size_t left = find(id(0, 1), id(0, 2)), right = find(id(1, 1), id(1, 2));
    const double rho_min = GENERATE(1e-4, 1e-3);
    sp::beam_model model(v, e, {.beam_width_mm = 2.0, .rho_min = rho_min});
    const double A = 2.0, above = 4 * 1.0;  // rows 2 and 3 hang on the panel between rows 1 and 2
    const auto before = model.solve();
    const double nl0 = axial_stress(model, v, e, left) * A, nr0 = axial_stress(model, v, e, right) * A;
    CHECK(nl0 == Approx(-above / 2).epsilon(0.03));
    CHECK(nr0 == Approx(-above / 2).epsilon(0.03));
    model.set_edge_solid(right, false);
    CHECK_FALSE(model.edge_solid(right));
    const auto after = model.solve();
    const double nl1 = axial_stress(model, v, e, left) * A, nr1 = axial_stress(model, v, e, right) * A;
    INFO("rho_min " << rho_min << ": axial forces " << nl0 << ", " << nr0 << " -> " << nl1 << ", " << nr1);
    CHECK(nl1 + nr1 == Approx(-above).epsilon(0.01));  // statics across the panel, before and after
    CHECK(nl0 + nr0 == Approx(-above).epsilon(0.01));
    if (rho_min == 1e-4) {                             // the default
        CHECK(nl1 / nl0 == Approx(2.0).epsilon(0.03));  // the axial force doubles
        CHECK(std::abs(nr1) < 0.01 * std::abs(nl1));   // the empty beam carries almost nothing
    } else {
        // At 1e-3 the soft beam still takes ~7%: with the 10 mm lever of the panel it forms a couple
        // whose stiffness (rho A d^2 = 0.2) rivals the solid beam's bending stiffness (t w^3 / 12 = 0.67).
        CHECK(nl1 / nl0 > 1.8);
        CHECK(std::abs(nr1) < 0.1 * std::abs(nl1));
    }
    CHECK(after[left] > 1.9 * before[left]);        // and the score rises (axial + the panel's moment)
    // The empty edge's score is C eps (paper): it still measures the strain the edge bridges.
    CHECK(after[right] > 0);
}

TEST_CASE("beam_model: changing edge states reuses the analysis and matches a fresh model", "[surface_pattern][beam]") {
    grid g(6, 5);
    sp::beam_options opt{.rho_min = 1e-3};
    // Both ways of handling changed values: refactorize (default) or CG on the previous factor first.
    opt.solver.reuse_preconditioner = GENERATE(false, true);
    sp::beam_model model(g.v, g.e, opt);
    (void)model.solve();
    std::vector<std::size_t> flip;
    for (std::size_t k = 0; k < g.e.size(); k += 4) flip.push_back(k);
    for (int round = 0; round < 3; ++round) {
        for (std::size_t k : flip) {
            const bool solid = (k / 4 + static_cast<std::size_t>(round)) % 2 == 1;
            model.set_edge_solid(k, solid);
            g.e[k].solid = solid;
        }
        const auto score = model.solve();
        sp::beam_model fresh(g.v, g.e, opt);
        const auto expect = fresh.solve();
        const double top = max_of(expect);
        for (std::size_t k = 0; k < score.size(); ++k) {
            INFO("round " << round << " edge " << k);
            CHECK(std::abs(score[k] - expect[k]) <= 1e-6 * std::max(std::abs(expect[k]), 1e-3 * top));
        }
    }
    const auto st = model.statistics();
    CHECK(st.analyses == 1);
    CHECK(st.solves == 4);
    CHECK(st.factorizations + st.reused_solves == st.solves);
    CHECK(st.factorizations >= 1);
    if (!opt.solver.reuse_preconditioner) CHECK(st.factorizations == st.solves);
    CHECK(st.hexes == g.e.size());
    CHECK(st.dofs == 3 * st.nodes);
}

TEST_CASE("beam_model: curved graphs build, balance their loads and are thread-count independent", "[surface_pattern][beam]") {
    test::thread_count_guard guard;
    auto [v, e] = fibonacci_sphere(120, 20.0, 6);
    std::vector<double> result[2];
    for (unsigned t : {1u, 2u}) {
        set_num_threads(t);
        sp::beam_model model(v, e, {.thickness_mm = 1.0});
        result[t - 1] = model.solve();
        if (t == 1) {
            // Statics: the support reactions balance the 120 N of gravity.
            vec3 R(0.0);
            for (const auto& f : model.supports().fixed)
                R[f.dof] += model.last_result().reactions(static_cast<Eigen::Index>(model.last_result().dofs.index(f.node, f.dof)));
            CHECK(R.z == Approx(120.0).epsilon(1e-8));
            CHECK(std::abs(R.x) < 1e-8);
            CHECK(std::abs(R.y) < 1e-8);
            for (double s : result[0]) CHECK((std::isfinite(s) && s >= 0));
            CHECK(model.statistics().wedges > 2 * v.size());
        }
    }
    CHECK(result[0] == result[1]);
}

TEST_CASE("beam_model: degenerate neighbourhoods fall back to a valid hub", "[surface_pattern][beam]") {
    // Vertex 0 sees 1 and 2 at almost the same angle (5.7 deg apart) and 3 above; 3 is a leaf and
    // 4 a lone vertex standing on the ground. All hubs build (positive Jacobians are checked inside).
    const std::vector<sp::beam_vertex> v = {
        {{0, 0, 0}, {0, -1, 0}}, {{10, 0, 0}, {0, -1, 0}}, {{10, 0, 1}, {0, -1, 0}}, {{0, 0, 10}, {0, -1, 0}}, {{-10, 0, -4}, {0, -1, 0}},
    };
    const std::vector<sp::beam_edge> e = {{0, 1, true}, {0, 2, true}, {0, 3, false}};
    sp::beam_model model(v, e, {.beam_width_mm = 1.0}, sp::force_profile{{0, 4}, {}});  // hub 0 held whole
    const auto score = model.solve();
    for (double s : score) CHECK((std::isfinite(s) && s > 0));
    CHECK(model.hub_radius(0) <= 0.35 * 10.0 + 1e-12);
    CHECK(model.hub_radius(3) == Approx(0.5));  // a leaf: one side, r = w / 2
    const auto [l0, l1] = model.vertex_nodes(4);
    CHECK(l1 - l0 == 2 + 2 * 6);  // the lone vertex: a hexagon
    // An edge along a vertex normal has no tangent direction: it is built or rejected, never UB.
    const std::vector<sp::beam_vertex> w = {{{0, 0, 0}, {0, -1, 0}}, {{10, 0, 0}, {0, -1, 0}}, {{0, 4, 0}, {0, -1, 0}}};
    const std::vector<sp::beam_edge> f = {{0, 1, true}, {0, 2, true}};
    try {
        sp::beam_model m2(w, f, {.beam_width_mm = 1.0, .gravity = {0, 0, -1}});
        (void)m2;
        SUCCEED("built");
    } catch (const invalid_input&) {
        SUCCEED("rejected");
    } catch (const fabsynth::error&) {
        SUCCEED("other library error");
    }
}

TEST_CASE("beam_model: bad input throws invalid_input, unsupported parts no_solution", "[surface_pattern][beam]") {
    auto [v, e] = column(3);
    const sp::beam_options opt{};
    auto bad_edges = [&](std::vector<sp::beam_edge> ee) { CHECK_THROWS_AS(sp::beam_model(v, ee, opt), invalid_input); };
    bad_edges({{0, 3, true}});
    bad_edges({{1, 1, true}});
    bad_edges({{0, 1, true}, {1, 0, false}});
    auto bad_vertex = [&](auto change) {
        auto vv = v;
        change(vv[1]);
        CHECK_THROWS_AS(sp::beam_model(vv, e, opt), invalid_input);
    };
    bad_vertex([](sp::beam_vertex& x) { x.position.y = std::numeric_limits<double>::quiet_NaN(); });
    bad_vertex([](sp::beam_vertex& x) { x.position.z = std::numeric_limits<double>::infinity(); });
    bad_vertex([](sp::beam_vertex& x) { x.normal = vec3(0.0); });
    bad_vertex([](sp::beam_vertex& x) { x.normal.x = std::numeric_limits<double>::quiet_NaN(); });
    bad_vertex([&](sp::beam_vertex& x) { x.position = v[0].position; });  // coincident endpoints
    CHECK_THROWS_AS(sp::beam_model(v, e, {.thickness_mm = 0}), invalid_input);
    CHECK_THROWS_AS(sp::beam_model(v, e, {.thickness_mm = -1}), invalid_input);
    CHECK_THROWS_AS(sp::beam_model(v, e, {.beam_width_mm = -1}), invalid_input);
    CHECK_THROWS_AS(sp::beam_model(v, e, {.rho_min = 0}), invalid_input);
    CHECK_THROWS_AS(sp::beam_model(v, e, {.gravity = vec3(0.0)}), invalid_input);
    CHECK_THROWS_AS(sp::beam_model(v, e, {.support_fraction = 1.5}), invalid_input);
    CHECK_THROWS_AS(sp::beam_model(v, e, opt, sp::force_profile{{7}, {}}), invalid_input);
    CHECK_THROWS_AS(sp::beam_model(v, e, opt, sp::force_profile{{}, {{9, vec3(0, 0, -1)}}}), invalid_input);
    sp::beam_model ok(v, e, opt);
    CHECK_THROWS_AS(ok.set_edge_solid(e.size(), false), invalid_input);
    CHECK_THROWS_AS(ok.edge_element(e.size()), invalid_input);
    // A floating pair of vertices high above the column: no support.
    auto vv = v;
    vv.push_back({{20, 0, 100}, {1, 0, 0}});
    vv.push_back({{20, 0, 110}, {1, 0, 0}});
    auto ee = e;
    ee.push_back({3, 4, true});
    CHECK_THROWS_AS(sp::beam_model(vv, ee, opt), no_solution);
}

TEST_CASE("beam_model: an edge across a thin part is split at a knot and carries the load of what hangs from it",
          "[surface_pattern][beam]") {
    // A fin 1 mm thick: column A on its +x face (z = 0..30), column B on its -x face (z = 10..30),
    // joined only at the top by an edge along A's normal, which no single hex can follow.
    std::vector<sp::beam_vertex> v;
    std::vector<sp::beam_edge> e;
    for (int i = 0; i < 4; ++i) v.push_back({{0.5, 0, 10.0 * i}, {1, 0, 0}});
    for (int i = 1; i < 4; ++i) v.push_back({{-0.5, 0, 10.0 * i}, {-1, 0, 0}});
    for (std::uint32_t i = 0; i < 3; ++i) e.push_back({i, i + 1, true});
    e.push_back({4, 5, true});
    e.push_back({5, 6, true});
    e.push_back({3, 6, true, sp::beam_vertex{{0, 0, 30.5}, {0, 0, 1}}});  // across the fin, knot on its rim
    sp::beam_model model(v, e, {.thickness_mm = 0.5, .beam_width_mm = 0.3});
    CHECK(model.statistics().knots == 1);
    CHECK(model.statistics().hexes == e.size() + 1);
    for (std::size_t k = 0; k + 1 < e.size(); ++k) CHECK_FALSE(model.edge_split(k));
    REQUIRE(model.edge_split(5));
    const auto [h0, h1] = model.edge_elements(5);
    CHECK(h1 == h0 + 2);
    const std::vector<double> score = model.solve();
    // Statics: the reactions balance the 7 N on the seven vertices (knots carry no load).
    vec3 R(0.0);
    for (const auto& f : model.supports().fixed)
        R[f.dof] += model.last_result().reactions(static_cast<Eigen::Index>(model.last_result().dofs.index(f.node, f.dof)));
    CHECK(R.z == Approx(7.0).epsilon(1e-8));
    // Column B's 3 N reach the support only through the split edge: it is stressed, and softening
    // it (rho_min) moves B far more than A's top.
    CHECK(score[5] > 0.01);
    const double drop_solid = model.last_result().displacement(model.vertex_nodes(6).first).z;
    model.set_edge_solid(5, false);
    (void)model.solve();
    const double drop_empty = model.last_result().displacement(model.vertex_nodes(6).first).z;
    CHECK(drop_empty < 100 * drop_solid);  // both negative: B sags far more through the soft knot
}
