// Filigree reconstruction (§6) and shell analysis (§5) against independent oracles: strip areas
// from the disc / hull formulas, watertightness and divergence-theorem volume of the extrusion,
// edge-use counts and angles of the FEM triangulation, the Euler-Bernoulli cantilever, the weight
// of the piece, and the 1/t^2 scaling of bending stress for phase 2.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <span>
#include <utility>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/filigree/reconstruct.hpp"
#include "fabsynth/filigree/structure.hpp"

namespace recon_test {

using namespace fabsynth;
using fabsynth::graph::skeleton_graph;

inline constexpr double pi = std::numbers::pi;

/// One skeleton edge from a to b with widths wa, wb.
inline skeleton_graph<vec2> segment(vec2 a, vec2 b, double wa, double wb) {
    skeleton_graph<vec2> g;
    const auto u = g.add_vertex(a, wa), v = g.add_vertex(b, wb);
    g.add_edge(u, v);
    return g;
}

inline double outline_perimeter(const std::vector<polygon_with_holes>& polys) {
    double l = 0;
    for (const auto& p : polys) {
        l += perimeter(p.outer);
        for (const auto& h : p.holes) l += perimeter(h);
    }
    return l;
}

/// Axis-aligned rectangle [x0, x1] x [y0, y1], counter-clockwise.
inline polygon_with_holes rectangle(double x0, double y0, double x1, double y1) {
    return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}};
}

/// Annulus of radii r_in < r_out as n-gons.
inline polygon_with_holes annulus(double r_out, double r_in, int n) {
    polygon_with_holes p;
    for (int k = 0; k < n; ++k) {
        const double a = 2 * pi * k / n;
        p.outer.push_back({r_out * std::cos(a), r_out * std::sin(a)});
        p.holes.resize(1);
        p.holes[0].push_back({r_in * std::cos(-a), r_in * std::sin(-a)});  // clockwise
    }
    return p;
}

/// Counts of directed edges of a face list.
template <class Faces>
std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed_edges(const Faces& faces) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> use;
    for (const auto& f : faces)
        for (int i = 0; i < 3; ++i) ++use[{f[i], f[(i + 1) % 3]}];
    return use;
}

/// Volume by the divergence theorem: sum over faces of det(a, b, c) / 6.
inline double divergence_volume(const triangle_mesh& m) {
    double v = 0;
    for (const auto& f : m.faces) {
        const vec3 a = m.vertices[f[0]], b = m.vertices[f[1]], c = m.vertices[f[2]];
        v += (a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x)) / 6.0;
    }
    return v;
}

/// Smallest angle of a planar triangle, degrees (law of cosines).
inline double smallest_angle_deg(vec2 a, vec2 b, vec2 c) {
    const double la = glm::distance(b, c), lb = glm::distance(c, a), lc = glm::distance(a, b);
    const double A = std::acos(std::clamp((lb * lb + lc * lc - la * la) / (2 * lb * lc), -1.0, 1.0));
    const double B = std::acos(std::clamp((la * la + lc * lc - lb * lb) / (2 * la * lc), -1.0, 1.0));
    return std::min({A, B, pi - A - B}) * 180 / pi;
}

/// What the FEM-triangulation test measures.
struct mesh_check {
    bool conforming = true;    // every undirected edge in 1 or 2 triangles, every directed edge once
    bool inside = true;        // every triangle's centroid inside the outline
    double area = 0, boundary_length = 0, min_angle = 180;
    std::size_t below_15 = 0;
};

inline mesh_check check_mesh(const planar_triangulation& t, const std::vector<polygon_with_holes>& outline) {
    mesh_check c;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> undirected;
    for (const auto& [e, n] : directed_edges(t.triangles)) {
        if (n != 1) c.conforming = false;
        ++undirected[{std::min(e.first, e.second), std::max(e.first, e.second)}];
    }
    for (const auto& [e, n] : undirected) {
        if (n > 2) c.conforming = false;
        if (n == 1) c.boundary_length += glm::distance(t.vertices[e.first], t.vertices[e.second]);
    }
    for (const auto& f : t.triangles) {
        const vec2 a = t.vertices[f[0]], b = t.vertices[f[1]], d = t.vertices[f[2]];
        const double a2 = (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x);
        if (!(a2 > 0)) c.conforming = false;
        c.area += 0.5 * a2;
        const vec2 g = (a + b + d) / 3.0;
        bool in = false;
        for (const auto& p : outline) in = in || point_in_polygon(p, g);
        c.inside = c.inside && in;
        const double ang = smallest_angle_deg(a, b, d);
        c.min_angle = std::min(c.min_angle, ang);
        if (ang < 15) ++c.below_15;
    }
    return c;
}

/// Options with a custom material.
inline filigree::structure_options options(double E, double nu, double density_t_mm3, double yield, double pressure_pa, double g) {
    filigree::structure_options o;
    o.material = {{E, nu, density_t_mm3}, yield};
    o.pressure_pa = pressure_pa;
    o.gravity_m_s2 = g;
    return o;
}

}  // namespace recon_test

TEST_CASE("reconstruct: one straight strip has area L w + pi w^2 / 4", "[filigree][reconstruct]") {
    using namespace recon_test;
    const double L = 30, w = 2, tol = 0.01;
    const auto g = segment({1, 2}, {1 + L * std::cos(0.3), 2 + L * std::sin(0.3)}, w, w);
    const auto out = filigree::strip_outline(std::span(&g, 1), tol);
    REQUIRE(out.size() == 1);
    CHECK(out[0].holes.empty());
    const double exact = L * w + pi * w * w / 4;
    INFO("area " << area(out) << " exact " << exact);
    // chords inside the circles: short by at most perimeter x tolerance
    CHECK(area(out) <= exact);
    CHECK(exact - area(out) <= outline_perimeter(out) * tol);

    // Varying width: hull of discs (c1, r1), (c2, r2) at distance d: two sectors plus two
    // right trapezoids, r1^2 (pi - g) + r2^2 g + (r1 + r2) sqrt(d^2 - (r1 - r2)^2), cos g = (r1 - r2) / d.
    const double r1 = 1.5, r2 = 0.5, d = 12;
    const auto h = segment({0, 0}, {0, d}, 2 * r1, 2 * r2);
    const auto hull = filigree::strip_outline(std::span(&h, 1), tol);
    const double gam = std::acos((r1 - r2) / d);
    const double hull_exact = r1 * r1 * (pi - gam) + r2 * r2 * gam + (r1 + r2) * std::sqrt(d * d - (r1 - r2) * (r1 - r2));
    INFO("hull area " << area(hull) << " exact " << hull_exact);
    REQUIRE(hull.size() == 1);
    CHECK(area(hull) <= hull_exact);
    CHECK(hull_exact - area(hull) <= outline_perimeter(hull) * tol);
}

TEST_CASE("reconstruct: two crossing strips have the sum of their areas minus the overlap", "[filigree][reconstruct]") {
    using namespace recon_test;
    const double L = 20, w = 1, tol = 0.005;
    // perpendicular strips crossing at their midpoints: the overlap is the w x w square
    std::vector<skeleton_graph<vec2>> two{segment({0, 0}, {L, 0}, w, w), segment({L / 2, -L / 2}, {L / 2, L / 2}, w, w)};
    const auto out = filigree::strip_outline(two, tol);
    REQUIRE(out.size() == 1);
    const double exact = 2 * (L * w + pi * w * w / 4) - w * w;
    INFO("area " << area(out) << " exact " << exact);
    CHECK(area(out) <= exact + 1e-9);
    CHECK(exact - area(out) <= outline_perimeter(out) * tol);
    // clipped to the half plane x <= L / 2 (a domain): one full cap, half of the vertical strip
    const std::vector<polygon_with_holes> half{rectangle(-5, -20, L / 2, 20)};
    const auto clipped = filigree::strip_outline(two, half, tol);
    const double clipped_exact = (L / 2) * w + pi * w * w / 8 + L * (w / 2) + 2 * pi * (w / 2) * (w / 2) / 4 - (w / 2) * w;
    INFO("clipped " << area(clipped) << " exact " << clipped_exact);
    CHECK(std::abs(area(clipped) - clipped_exact) <= outline_perimeter(clipped) * tol);
}

TEST_CASE("reconstruct: printable extrusion is watertight with volume = area x thickness", "[filigree][reconstruct]") {
    using namespace recon_test;
    // a closed loop of four strips (an outline with a hole) and a crossing pair
    skeleton_graph<vec2> loop;
    const auto a = loop.add_vertex({0, 0}, 1.2), b = loop.add_vertex({10, 0}, 0.8), c = loop.add_vertex({10, 8}, 1.2),
               d = loop.add_vertex({0, 8}, 0.8);
    loop.add_edge(a, b), loop.add_edge(b, c), loop.add_edge(c, d), loop.add_edge(d, a);
    std::vector<skeleton_graph<vec2>> parts{loop, segment({-4, 4}, {14, 5}, 1.0, 1.0)};
    const auto out = filigree::strip_outline(parts, 0.01);
    REQUIRE(!out.empty());
    std::size_t holes = 0;
    for (const auto& p : out) holes += p.holes.size();
    CHECK(holes == 2);  // the crossing strip cuts the loop's hole in two
    const double t = 1.5;
    const triangle_mesh m = filigree::printable_extrusion(out, t);
    const auto use = directed_edges(m.faces);
    bool closed = true;
    for (const auto& [e, n] : use) {
        const auto it = use.find({e.second, e.first});
        closed = closed && n == 1 && it != use.end() && it->second == 1;
    }
    CHECK(closed);
    CHECK(divergence_volume(m) == Approx(area(out) * t).epsilon(1e-9));
    for (const vec3& v : m.vertices) CHECK((v.z == 0.0 || v.z == t));
    CHECK_THROWS_AS(filigree::printable_extrusion({}, 1.0), invalid_input);
    CHECK_THROWS_AS(filigree::printable_extrusion(out, 0.0), invalid_input);
    CHECK_THROWS_AS(filigree::printable_extrusion(out, std::nan("")), invalid_input);
}

TEST_CASE("reconstruct: fem triangulation is conforming, exact in area, without slivers", "[filigree][reconstruct]") {
    using namespace recon_test;
    const auto strip_graph = segment({0, 0}, {25, 6}, 2.0, 2.0);
    const std::vector<std::pair<const char*, std::vector<polygon_with_holes>>> cases{
        {"strip", filigree::strip_outline(std::span(&strip_graph, 1), 0.01)},
        {"annulus", {annulus(10, 6, 96)}},
        {"rectangle", {rectangle(0, 0, 10, 100)}},
    };
    for (const auto& [name, outline] : cases)
        for (double h : {0.4, 1.0, 3.0}) {
            INFO(name << " h = " << h);
            const filigree::fem_triangulation tri = filigree::make_fem_triangulation(outline, h);
            const mesh_check c = check_mesh(tri.mesh, outline);
            INFO("triangles " << tri.mesh.triangles.size() << " min angle " << c.min_angle << " reported " << tri.min_angle_deg);
            CHECK(c.conforming);
            CHECK(c.inside);
            CHECK(std::abs(c.area - area(outline)) <= 1e-6 * area(outline));
            CHECK(c.boundary_length == Approx(outline_perimeter(outline)).epsilon(1e-9));
            CHECK(c.min_angle > 10);
            CHECK(c.below_15 == 0);
            CHECK(tri.min_angle_deg == Approx(c.min_angle).margin(1e-6));
            CHECK(!tri.budget_exhausted);
            CHECK(tri.below_target == 0);
            // edge lengths near h: no edge much longer than the target (circumradius <= h)
            double longest = 0;
            for (const auto& f : tri.mesh.triangles)
                for (int i = 0; i < 3; ++i) longest = std::max(longest, glm::distance(tri.mesh.vertices[f[i]], tri.mesh.vertices[f[(i + 1) % 3]]));
            CHECK(longest <= 2 * h + 1e-9);
        }
    CHECK_THROWS_AS(filigree::make_fem_triangulation({}, 1.0), invalid_input);
    CHECK_THROWS_AS(filigree::make_fem_triangulation({rectangle(0, 0, 1, 1)}, 0.0), invalid_input);
    CHECK_THROWS_AS(filigree::make_fem_triangulation({rectangle(0, 0, 1, 1)}, std::nan("")), invalid_input);
}

TEST_CASE("reconstruct: sharp solid corners are cut where they are as wide as asked", "[filigree][reconstruct]") {
    using namespace recon_test;
    // A wedge of apex angle 10 degrees at the origin, 10 mm long, closed by a flat end: its apex is cut
    // where the two sides are 0.5 mm apart, 0.5 / (2 tan 5 deg) = 2.86 mm from it; its 85-degree
    // corners stay.
    const double half = 5 * pi / 180, len = 10;
    const ring2 wedge{{0, 0}, {len, -len * std::tan(half)}, {len, len * std::tan(half)}};
    const auto cut = filigree::blunt_sharp_corners({polygon_with_holes{wedge, {}}}, pi / 6, 0.5);
    REQUIRE(cut.size() == 1);
    double min_x = 1e9, max_x = 0;
    for (const vec2& p : cut[0].outer) min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    const double x_cut = 0.5 / (2 * std::tan(half));
    CHECK(min_x > x_cut - 0.01);
    CHECK(min_x < x_cut + 0.125 * 0.5 / std::cos(half) + 0.01);  // the walk's step along the sides
    CHECK(max_x == Approx(len));
    const double tip = x_cut * x_cut * std::tan(half);  // area of the tip removed, at x_cut
    CHECK(area(cut) == Approx(len * len * std::tan(half) - tip).epsilon(0.03));
    // A ring clipped by the domain where its inner side grazes the edge: a solid cusp between the
    // edge y = 0 and the inner circle. The triangulation of the coarsened outline keeps its angles;
    // the raw outline's refinement splits toward the cusp down to h / 200 (well-shaped triangles
    // of 1e-6 mm^2).
    const double R = 5, r = 4.6, cy = r + 0.02;
    ring2 outer, inner;
    for (int k = 0; k < 720; ++k) {
        const double a = 2 * pi * k / 720;
        outer.push_back({R * std::cos(a), cy + R * std::sin(a)});
        inner.push_back({r * std::cos(-a), cy + r * std::sin(-a)});
    }
    const auto ring = polygon_intersection({polygon_with_holes{outer, {inner}}}, {rectangle(-10, 0, 10, 20)});
    const double h = 0.3;
    auto smallest = [](const filigree::fem_triangulation& t) {
        double a = 1e9;
        for (const auto& f : t.mesh.triangles) {
            const vec2 p = t.mesh.vertices[f[0]], q = t.mesh.vertices[f[1]], s = t.mesh.vertices[f[2]];
            a = std::min(a, 0.5 * std::abs(orient2d(p, q, s)));
        }
        return a;
    };
    const auto raw = filigree::make_fem_triangulation(ring, h);
    const auto coarse = filigree::make_fem_triangulation(filigree::coarsened_outline(ring, 0.25 * h), h);
    INFO("raw: min angle " << raw.min_angle_deg << ", smallest triangle " << smallest(raw) << "; coarsened: " << coarse.min_angle_deg << ", "
                           << smallest(coarse));
    CHECK(smallest(raw) < 1e-4 * h * h);
    CHECK(coarse.min_angle_deg >= 20);
    CHECK(smallest(coarse) > 1e-3 * h * h);
    CHECK(area(filigree::coarsened_outline(ring, 0.25 * h)) == Approx(area(ring)).epsilon(0.01));
    CHECK_THROWS_AS(filigree::blunt_sharp_corners(ring, 0, 0.1), invalid_input);
    CHECK_THROWS_AS(filigree::blunt_sharp_corners(ring, 0.5, 0), invalid_input);
}

TEST_CASE("reconstruct: a wall far thinner than the mesh is opened before the FEM triangulation", "[filigree][reconstruct]") {
    using namespace recon_test;
    // A 10 x 10 mm plate with a 6 x 5 mm hole 2 um above its bottom edge: no sharp corner, so the
    // coarsened outline keeps the wall, and refinement splits toward it. piece_triangulation opens it
    // (the hole becomes a notch open at the bottom, still one piece) and keeps every edge >= h / 50.
    const double h = 1.0;
    polygon_with_holes plate = rectangle(0, 0, 10, 10);
    plate.holes.push_back({{2, 0.002}, {2, 5}, {8, 5}, {8, 0.002}});
    const std::vector<polygon_with_holes> outline{plate};
    const auto plain = filigree::make_fem_triangulation(filigree::coarsened_outline(outline, 0.25 * h), h);
    const auto piece = filigree::piece_triangulation(outline, h);
    INFO("shortest edge: plain " << filigree::shortest_edge(plain) << ", piece " << filigree::shortest_edge(piece));
    CHECK(filigree::shortest_edge(plain) < 0.02 * h);
    CHECK(filigree::shortest_edge(piece) >= 0.02 * h);
    double a = 0;
    for (const auto& f : piece.mesh.triangles) a += 0.5 * orient2d(piece.mesh.vertices[f[0]], piece.mesh.vertices[f[1]], piece.mesh.vertices[f[2]]);
    CHECK(a == Approx(100 - 30).epsilon(0.01));  // the plate less the hole, the wall's 0.012 mm^2 and rounded corners aside
}

TEST_CASE("structure: a clamped shell strip under pressure matches the Euler-Bernoulli cantilever", "[filigree][structure]") {
    using namespace recon_test;
    // strip b x L along y, clamped at y = 0 (support_fraction 0: the lowest edge only), pressure p;
    // nu = 0 so that the plate strip is a beam (no anticlastic bending at the clamp)
    const double b = 10, L = 100, t = 1, E = 2000, p_pa = 1000;
    const std::vector<polygon_with_holes> outline{rectangle(0, 0, b, L)};
    const filigree::fem_triangulation tri = filigree::make_fem_triangulation(outline, 1.5);
    auto opt = options(E, 0.0, 1.0e-9, 40, p_pa, 0.0);
    opt.support_fraction = 0;
    const filigree::structural_report rep = filigree::analyse_structure(tri, t, opt);
    const double q = p_pa * 1e-6 * b;  // N/mm
    const double I = b * t * t * t / 12;
    const double w_tip = q * L * L * L * L / (8 * E * I);
    const double sigma_root = 6 * (q * L * L / 2) / (b * t * t);
    double tip = 0, root = 0;
    int tips = 0;
    for (std::size_t i = 0; i < rep.node_positions.size(); ++i) {
        if (rep.node_positions[i].y == L) tip += rep.node_deflection[i], ++tips;
        if (rep.node_positions[i].y == 0) root = std::max(root, rep.node_von_mises[i]);
    }
    REQUIRE(tips > 0);
    tip /= tips;
    INFO("tip " << tip << " oracle " << -w_tip << "; root stress " << root << " oracle " << sigma_root << "; nodes " << rep.node_positions.size());
    CHECK(std::abs(-tip - w_tip) / w_tip < 0.02);
    CHECK(std::abs(root - sigma_root) / sigma_root < 0.05);
    CHECK(rep.max_von_mises == Approx(root).epsilon(1e-12));  // the root is the most stressed section
    CHECK(rep.support_reaction.z == Approx(q * L).epsilon(1e-6));  // to the solve residual
    CHECK(rep.support_nodes.size() >= 2);
    CHECK(rep.thickness == t);
}

TEST_CASE("structure: under gravity alone the supports carry the weight", "[filigree][structure]") {
    using namespace recon_test;
    const auto g = segment({0, 0}, {40, 10}, 3.0, 3.0);
    const auto outline = filigree::strip_outline(std::span(&g, 1), 0.01);
    const filigree::fem_triangulation tri = filigree::make_fem_triangulation(outline, 1.0);
    filigree::structure_options opt;
    opt.material = filigree::preset_material(filigree::material_preset::pla);
    opt.pressure_pa = 0;
    const double t = 1.2;
    const filigree::structural_report rep = filigree::analyse_structure(tri, t, opt);
    // weight in SI: 1240 kg/m^3 x 9.81 m/s^2 x volume (mm^3 -> m^3)
    const double weight = 1240.0 * 9.81 * (area(outline) * t * 1e-9);
    CHECK(rep.support_reaction.z == Approx(weight).epsilon(1e-9));
    CHECK(std::abs(rep.support_reaction.x) < 1e-12);
    CHECK(std::abs(rep.support_reaction.y) < 1e-12);
    // default support: the nodes in the lowest 5% of the height
    double y_lo = 1e9, y_hi = -1e9;
    for (const vec2& v : tri.mesh.vertices) y_lo = std::min(y_lo, v.y), y_hi = std::max(y_hi, v.y);
    const double limit = y_lo + 0.05 * (y_hi - y_lo);
    std::size_t expected = 0;
    for (const vec2& v : tri.mesh.vertices) expected += v.y <= limit;
    CHECK(rep.support_nodes.size() == expected);
    for (std::uint32_t n : rep.support_nodes) CHECK(tri.mesh.vertices[n].y <= limit + 1e-9);
    // histogram: every node counted once, bins of 5 MPa up to 2 x 50 MPa and one open bin
    CHECK(rep.histogram.size() == 21);
    std::size_t counted = 0;
    for (std::size_t c : rep.histogram) counted += c;
    CHECK(counted == rep.node_positions.size());
    CHECK(rep.weak_nodes.empty());
    CHECK(rep.weak_fraction == 0.0);
    // same bits with one thread
    set_num_threads(1);
    const filigree::structural_report one = filigree::analyse_structure(tri, t, opt);
    set_num_threads(0);
    CHECK(one.node_von_mises == rep.node_von_mises);
}

TEST_CASE("structure: phase 2 thickens by 10% per iteration until no node is weak", "[filigree][structure]") {
    using namespace recon_test;
    // pressure only: the piece works in plate bending, so every stress scales as 1 / t^2
    const std::vector<polygon_with_holes> outline{rectangle(0, 0, 6, 40)};
    const filigree::fem_triangulation tri = filigree::make_fem_triangulation(outline, 2.0);
    filigree::structure_options opt;  // ABS, yield 40 MPa, lowest 5% clamped
    opt.gravity_m_s2 = 0;
    opt.pressure_pa = 4000;
    const double t0 = 0.5;
    const filigree::structural_report first = filigree::analyse_structure(tri, t0, opt);
    REQUIRE(first.weak_fraction > 0);
    // oracle: the smallest k with max stress (t0 / t_k)^2 <= yield, t_k = t0 1.1^k
    int k = 0;
    while (first.max_von_mises / std::pow(1.1, 2 * k) > 40.0) ++k;
    const double margin = first.max_von_mises / std::pow(1.1, 2 * k);
    INFO("max stress at t0 " << first.max_von_mises << ", predicted k " << k << " (stress then " << margin << ")");
    REQUIRE(margin < 40.0 * 0.999);  // not at the threshold: the prediction is unambiguous
    REQUIRE(first.max_von_mises / std::pow(1.1, 2 * (k - 1)) > 40.0 * 1.001);
    const filigree::thickening_result r = filigree::thicken_until_strong(tri, t0, opt);
    CHECK(r.converged);
    CHECK(r.iterations == k);
    CHECK(r.thickness == Approx(t0 * std::pow(1.1, k)).epsilon(1e-12));
    CHECK(r.report.weak_fraction == 0.0);
    REQUIRE(r.thickness_history.size() == static_cast<std::size_t>(k + 1));
    for (int i = 0; i < k; ++i) CHECK(r.weak_fraction_history[static_cast<std::size_t>(i)] > 0);
    for (int i = 0; i <= k; ++i)
        CHECK(r.max_von_mises_history[static_cast<std::size_t>(i)] == Approx(first.max_von_mises / std::pow(1.1, 2 * i)).epsilon(1e-6));
    // a bound on the iterations is honoured
    const filigree::thickening_result capped = filigree::thicken_until_strong(tri, t0, opt, {.growth = 1.1, .max_iterations = k - 1});
    CHECK(!capped.converged);
    CHECK(capped.iterations == k - 1);
}

TEST_CASE("structure: a filigree piece end to end: the supports carry pressure and weight", "[filigree][structure]") {
    using namespace recon_test;
    // a 3 x 3 grid of strips with varying widths and a diagonal: crossings, junctions, holes
    skeleton_graph<vec2> g;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) g.add_vertex({12.0 * i, 12.0 * j}, 1.0 + 0.25 * ((i + j) % 3));
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            if (i < 2) g.add_edge(static_cast<graph::vertex_id>(3 * j + i), static_cast<graph::vertex_id>(3 * j + i + 1));
            if (j < 2) g.add_edge(static_cast<graph::vertex_id>(3 * j + i), static_cast<graph::vertex_id>(3 * j + i + 3));
        }
    g.add_edge(0, 8);
    const auto outline = filigree::strip_outline(std::span(&g, 1), 0.01);
    REQUIRE(outline.size() == 1);
    CHECK(outline[0].holes.size() == 6);  // four cells, two of them cut by the diagonal
    const filigree::fem_triangulation tri = filigree::make_fem_triangulation(outline, 1.0);
    const mesh_check c = check_mesh(tri.mesh, outline);
    INFO("triangles " << tri.mesh.triangles.size() << " min angle " << c.min_angle);
    CHECK(c.conforming);
    CHECK(std::abs(c.area - area(outline)) <= 1e-6 * area(outline));
    CHECK(c.below_15 == 0);
    const double t = 0.8, p = 1000;
    const filigree::structure_options opt;  // ABS, 1 kPa, gravity, lowest 5%
    const filigree::structural_report rep = filigree::analyse_structure(tri, t, opt);
    // total load in SI units: pressure x area plus 1040 kg/m^3 x 9.81 m/s^2 x volume
    const double load = p * area(outline) * 1e-6 + 1040.0 * 9.81 * area(outline) * t * 1e-9;
    CHECK(rep.support_reaction.z == Approx(load).epsilon(1e-6));
    CHECK(rep.max_deflection > 0);
    CHECK(rep.max_von_mises == Approx(*std::max_element(rep.node_von_mises.begin(), rep.node_von_mises.end())));
    CHECK(rep.weak_fraction == Approx(static_cast<double>(rep.weak_nodes.size()) / static_cast<double>(rep.node_positions.size())));
    for (std::uint32_t n : rep.weak_nodes) CHECK(rep.node_von_mises[n] > 40.0);
}

TEST_CASE("structure: weak nodes cluster into region centres", "[filigree][structure]") {
    using namespace recon_test;
    filigree::structural_report rep;
    rep.node_positions = {{0, 0}, {1, 0}, {50, 50}, {0.5, 0.8}, {51, 50}, {100, 0}, {20, 20}};
    rep.weak_nodes = {0, 1, 2, 3, 4, 5};  // node 6 is strong
    const auto c = filigree::weak_region_centres(rep, 1.5);
    REQUIRE(c.size() == 3);
    CHECK(c[0].x == Approx(0.5));
    CHECK(c[0].y == Approx(0.8 / 3));
    CHECK(c[1].x == Approx(50.5));
    CHECK(c[1].y == Approx(50));
    CHECK(c[2].x == Approx(100));
    CHECK(filigree::weak_region_centres(rep, 200).size() == 1);
    CHECK_THROWS_AS(filigree::weak_region_centres(rep, 0.0), invalid_input);
}

TEST_CASE("structure: bad input names the problem", "[filigree][structure]") {
    using namespace recon_test;
    const filigree::fem_triangulation tri = filigree::make_fem_triangulation({rectangle(0, 0, 5, 20)}, 2.0);
    CHECK_THROWS_AS(filigree::analyse_structure(filigree::fem_triangulation{}, 1.0), invalid_input);
    CHECK_THROWS_AS(filigree::analyse_structure(tri, 0.0), invalid_input);
    CHECK_THROWS_AS(filigree::analyse_structure(tri, -1.0), invalid_input);
    CHECK_THROWS_AS(filigree::analyse_structure(tri, std::nan("")), invalid_input);
    CHECK_THROWS_AS(filigree::analyse_structure(tri, INFINITY), invalid_input);
    filigree::structure_options nowhere;
    nowhere.support = [](const vec2& p) { return p.y < -1; };
    CHECK_THROWS_WITH(filigree::analyse_structure(tri, 1.0, nowhere), Catch::Contains("support"));
    CHECK_THROWS_AS(filigree::analyse_structure(tri, 1.0, nowhere), invalid_input);
    filigree::structure_options bad_fraction;
    bad_fraction.support_fraction = 1.5;
    CHECK_THROWS_AS(filigree::analyse_structure(tri, 1.0, bad_fraction), invalid_input);
    CHECK_THROWS_AS(filigree::thicken_until_strong(tri, 1.0, {}, {.growth = 1.0, .max_iterations = 3}), invalid_input);
}
