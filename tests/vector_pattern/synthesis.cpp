// Tests for vector_pattern/synthesis.hpp (with vector_pattern/offsets.hpp, vector_pattern/stitching.hpp, vector_pattern/contours.hpp)
// and the raster topology oracle of tests/support/raster_topology.hpp.
#include <catch2/catch.hpp>

#include "support/test_util.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "fabsynth/io/svg.hpp"
#include "fabsynth/vector_pattern.hpp"
#include "support/raster_topology.hpp"
#include "support/vector_band.hpp"

using namespace fabsynth;
using vector_pattern::exemplar;

namespace {

using fabsynth::test::rect_ring;

// Oracle counts of a band result (closed: glued at u = 0 / u = L by column wrap-around).
test::raster_topology_result oracle(const std::vector<polygon_with_holes>& polys, double L, bool closed, double pixel = 0.05) {
    const box2 b = bounding_box(polys);
    return test::raster_topology(polys, {0.0, b.lo.y}, {L, b.hi.y}, pixel, closed);
}

// Properties every band result must have.
void check_band(const vector_pattern::synthesis_result& r, double L, bool closed) {
    REQUIRE_FALSE(r.polygons.empty());
    for (const polygon_with_holes& p : r.polygons) {
        REQUIRE(is_simple(p.outer));
        REQUIRE(signed_area(p.outer) > 0.0);
        for (const ring2& h : p.holes) {
            REQUIRE(is_simple(h));
            REQUIRE(signed_area(h) < 0.0);
        }
        for (const vec2& q : p.outer) {
            REQUIRE(q.x >= 0.0);
            REQUIRE(q.x <= L);
        }
    }
    if (closed) {
        // The cut at u = 0 equals the cut at u = L.
        const auto a = vector_pattern::detail::side_portals(r.polygons, 0.0), b = vector_pattern::detail::side_portals(r.polygons, L);
        REQUIRE(a.size() == b.size());
        for (std::size_t k = 0; k < a.size(); ++k) {
            REQUIRE(a[k].top == b[k].top);
            REQUIRE(a[k].bottom == b[k].bottom);
        }
    }
    auto t = oracle(r.polygons, L, closed);
    if (t.components != r.components || t.holes != r.holes) t = oracle(r.polygons, L, closed, 0.02);  // near-contacts
    CHECK(t.components == r.components);
    CHECK(t.holes == r.holes);
}

}  // namespace

TEST_CASE("raster topology oracle counts simple configurations", "[pattern][synthesis][oracle]") {
    // A frame with two windows, and a separate square.
    polygon_with_holes frame{rect_ring(0, 0, 10, 5), {rect_ring(1, 1, 4, 4), rect_ring(5, 1, 9, 4)}};
    orient(frame);
    polygon_with_holes square{rect_ring(12, 0, 14, 2), {}};
    auto t = test::raster_topology({frame, square}, {0, 0}, {14, 5}, 0.05);
    CHECK(t.components == 2);
    CHECK(t.holes == 2);
    // A 'C' open towards x = 0: no hole, unless x wraps around and a bar at x = 0 closes it.
    polygon_with_holes c{{{0, 0}, {10, 0}, {10, 5}, {0, 5}, {0, 4}, {9, 4}, {9, 1}, {0, 1}}, {}};
    orient(c);
    CHECK(test::raster_topology({c}, {0, 0}, {10, 5}, 0.05, false).holes == 0);
    polygon_with_holes bar{rect_ring(0, 0, 0.5, 5), {}};
    polygon_with_holes c2{{{1, 0}, {10, 0}, {10, 5}, {1, 5}, {1, 4}, {9, 4}, {9, 1}, {1, 1}}, {}};
    orient(c2);
    // Without wrap the bar and the C are apart; with wrap the bar (at x = 0) touches the C's right side.
    auto open_t = test::raster_topology({bar, c2}, {0, 0}, {10, 5}, 0.05, false);
    CHECK(open_t.components == 2);
    auto wrap_t = test::raster_topology({bar, c2}, {0, 0}, {10, 5}, 0.05, true);
    CHECK(wrap_t.components == 1);
    CHECK(wrap_t.holes == 0);  // the C's opening still reaches the top and bottom border through x in (0.5, 1)
}

TEST_CASE("offsets: sparse solve equals a dense least-squares solve", "[pattern][synthesis][offsets]") {
    for (int closed = 0; closed < 2; ++closed)
        for (std::uint64_t seed = 1; seed <= 20; ++seed) {
            counter_rng rng(seed, closed);
            const std::size_t pieces = 2 + rng.uniform_int(30);
            const std::size_t junctions = closed ? pieces : pieces - 1;
            std::vector<double> tau(junctions), w(junctions);
            for (std::size_t k = 0; k < junctions; ++k) {
                tau[k] = rng.uniform(-5.0, 5.0);
                w[k] = rng.uniform() < 0.2 ? 0.0 : double(2 * (1 + rng.uniform_int(3)));  // some junctions without portals
            }
            const std::vector<double> delta = vector_pattern::solve_offsets(tau, w, closed != 0);
            REQUIRE(delta.size() == pieces);
            REQUIRE(delta[0] == 0.0);
            if (!closed) REQUIRE(delta[pieces - 1] == 0.0);
            // Dense: unknowns = free pieces; minimum-norm least squares (floating blocks centred at 0).
            std::vector<int> col(pieces, -1);
            int m = 0;
            for (std::size_t i = 1; i < pieces; ++i)
                if (closed || i + 1 < pieces) col[i] = m++;
            if (m == 0) continue;
            Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(junctions), m);
            Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(junctions));
            for (std::size_t k = 0; k < junctions; ++k) {
                const std::size_t i = k, j = (k + 1) % pieces;
                const double s = std::sqrt(w[k]);
                if (col[i] >= 0) A(static_cast<Eigen::Index>(k), col[i]) += s;
                if (col[j] >= 0) A(static_cast<Eigen::Index>(k), col[j]) -= s;
                b[static_cast<Eigen::Index>(k)] = -s * tau[k];
            }
            const Eigen::VectorXd x = A.completeOrthogonalDecomposition().solve(b);
            for (std::size_t i = 0; i < pieces; ++i)
                if (col[i] >= 0) REQUIRE(delta[i] == Approx(x[col[i]]).margin(1e-9));
        }
    CHECK_THROWS_AS(vector_pattern::solve_offsets(std::vector<double>{1.0}, std::vector<double>{}, false), invalid_input);
    CHECK_THROWS_AS(vector_pattern::solve_offsets(std::vector<double>{std::nan("")}, std::vector<double>{1.0}, false), invalid_input);
}

TEST_CASE("LRI chain: rigid motions are reproduced and end constraints met", "[pattern][synthesis][stitching]") {
    std::vector<vec2> pts;
    for (int i = 0; i <= 40; ++i) {
        const double t = i / 40.0;
        pts.emplace_back(10.0 * t, 2.0 * std::sin(6.0 * t) + 0.3 * t * t);
    }
    const vector_pattern::lri_chain chain(pts);
    for (double angle : {0.0, 0.3, 1.7, -2.9}) {
        const double c = std::cos(angle), s = std::sin(angle);
        const vec2 shift(3.5, -1.25);
        auto T = [&](vec2 p) { return vec2(c * p.x - s * p.y, s * p.x + c * p.y) + shift; };
        auto R = [&](vec2 d) { return vec2(c * d.x - s * d.y, s * d.x + c * d.y); };
        const auto out = chain.deform(T(pts.front()), T(pts.back()), R(pts[1] - pts[0]), R(pts.back() - pts[pts.size() - 2]));
        REQUIRE(out.size() == pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i) {
            REQUIRE(out[i].x == Approx(T(pts[i]).x).margin(1e-9));
            REQUIRE(out[i].y == Approx(T(pts[i]).y).margin(1e-9));
        }
    }
    // Non-rigid targets: the ends are met exactly, the end edges follow the requested directions.
    const vec2 a(-1.0, 0.5), b(12.0, -0.5), da(1.0, 1.0), db(1.0, -0.2);
    const auto out = chain.deform(a, b, da, db);
    REQUIRE(out.front() == a);
    REQUIRE(out.back() == b);
    const vec2 e0 = glm::normalize(out[1] - out[0]), e1 = glm::normalize(out.back() - out[out.size() - 2]);
    // End directions enter through the frames; the position solve is least squares over all edges,
    // so the end edges follow them closely but not exactly (see stitching.hpp).
    CHECK(glm::dot(e0, glm::normalize(da)) > 0.9);
    CHECK(glm::dot(e1, glm::normalize(db)) > 0.9);
    CHECK_THROWS_AS(vector_pattern::lri_chain(std::vector<vec2>{{0, 0}}), invalid_input);
    CHECK_THROWS_AS(vector_pattern::lri_chain(std::vector<vec2>{{0, 0}, {0, 0}}), invalid_input);
}

TEST_CASE("stitching a piece stretched along u reproduces the stretched piece", "[pattern][synthesis][stitching]") {
    // Oracle: the piece's own rings under x -> u0 + (x - x0) s. With targets on that map (stretched
    // endpoint tangents too) the stretched rest shape is met exactly, for a compression and an extension.
    const exemplar ex = test::load_vector_exemplar("greek_key.svg");
    const auto pieces = vector_pattern::slice(ex, std::vector<double>{ex.bounds.lo.x + 101.2345, ex.bounds.lo.x + 203.4567});
    const vector_pattern::piece& P = pieces[1];
    REQUIRE_FALSE(P.left.empty());
    REQUIRE_FALSE(P.right.empty());
    for (double s : {0.8, 1.0, 1.2}) {
        INFO("u_scale " << s);
        const double u0 = 10.0, u1 = u0 + (P.x1 - P.x0) * s;
        auto stretch = [&](vec2 q) { return vec2(u0 + (q.x - P.x0) * s, q.y); };
        auto targets = [&](vector_pattern::piece_side side, double u) {
            std::vector<vector_pattern::endpoint_target> t;
            const auto h = P.heights(side);
            const auto g = P.tangents(side);
            for (std::size_t e = 0; e < h.size(); ++e) t.push_back({{u, h[e]}, glm::normalize(vec2(g[e].x * s, g[e].y))});
            return t;
        };
        const vector_pattern::piece_boundary pb(P, s);
        const auto rings = pb.deform(targets(vector_pattern::piece_side::left, u0), targets(vector_pattern::piece_side::right, u1), {u0, u1, 0.0, 0.0});
        double stretched_area = 0.0, stitched_area = 0.0;
        for (const auto& poly : P.polygons) {
            stretched_area += s * area(poly);
        }
        std::size_t far = 0;
        for (const ring2& r : rings) {
            stitched_area += signed_area(r);
            REQUIRE(is_simple(r));
            for (const vec2& q : r) {
                double best = std::numeric_limits<double>::infinity();
                for (const auto& poly : P.polygons) {
                    for (const vec2& o : poly.outer) best = std::min(best, glm::length(stretch(o) - q));
                    for (const ring2& h : poly.holes)
                        for (const vec2& o : h) best = std::min(best, glm::length(stretch(o) - q));
                }
                if (best > 1e-7) ++far;
            }
        }
        CHECK(far == 0);
        CHECK(stitched_area == Approx(stretched_area).epsilon(1e-9));
    }
    CHECK_THROWS_AS(vector_pattern::piece_boundary(P, 0.0), invalid_input);
    CHECK_THROWS_AS(vector_pattern::piece_boundary(P, std::nan("")), invalid_input);
}

TEST_CASE("stitched seams: matching portal endpoints of neighbouring pieces coincide", "[pattern][synthesis][stitching]") {
    const exemplar ex = test::load_vector_exemplar("greek_key.svg");
    const auto pieces = vector_pattern::slice(ex, std::vector<double>{ex.bounds.lo.x + 101.2345, ex.bounds.lo.x + 203.4567});
    const vector_pattern::piece &A = pieces[0], &B = pieces[1];
    REQUIRE(A.right.size() == B.left.size());
    REQUIRE_FALSE(A.right.empty());
    // Junction targets as synthesize_along builds them: averages of both sides, at u = 50.
    std::vector<vector_pattern::endpoint_target> tr, tl;
    const auto ha = A.heights(vector_pattern::piece_side::right), hb = B.heights(vector_pattern::piece_side::left);
    for (std::size_t e = 0; e < ha.size(); ++e) {
        const double v = 0.5 * (ha[e] + 0.7 + hb[e]);  // A slid by 0.7
        tr.push_back({{50.0, v}, {1.0, 0.1}});
        tl.push_back({{50.0, v}, {1.0, 0.1}});
    }
    std::vector<vector_pattern::endpoint_target> left_end, right_end;
    for (double y : A.heights(vector_pattern::piece_side::left)) left_end.push_back({{0.0, y}, {1.0, 0.0}});
    for (double y : B.heights(vector_pattern::piece_side::right)) right_end.push_back({{120.0, y}, {1.0, 0.0}});
    const vector_pattern::piece_boundary pa(A), pb(B);
    const auto ra = pa.deform(left_end, tr, {0.0, 50.0, 0.0, 0.7});
    const auto rb = pb.deform(tl, right_end, {50.0, 120.0, 0.0, 0.0});
    // Every junction endpoint appears in both pieces' rings, at the same place (1e-9).
    for (const auto& t : tr) {
        auto has = [&](const std::vector<ring2>& rings) {
            for (const ring2& r : rings)
                for (const vec2& q : r)
                    if (glm::length(q - t.position) <= 1e-9) return true;
            return false;
        };
        CHECK(has(ra));
        CHECK(has(rb));
    }
    // Each junction portal is the same straight segment (an edge) in both pieces.
    auto has_edge = [](const std::vector<ring2>& rings, vec2 p, vec2 q) {
        for (const ring2& r : rings)
            for (std::size_t i = 0; i < r.size(); ++i) {
                const vec2 a = r[i], b = r[(i + 1) % r.size()];
                if ((a == p && b == q) || (a == q && b == p)) return true;
            }
        return false;
    };
    for (std::size_t k = 0; k + 1 < tr.size(); k += 2) {
        CHECK(has_edge(ra, tr[k].position, tr[k + 1].position));
        CHECK(has_edge(rb, tl[k].position, tl[k + 1].position));
    }
}

namespace {
void sweep(const std::vector<std::string>& files, const std::vector<double>& factors) {
    // Every case either returns a pattern whose topology the raster oracle confirms, or throws.
    // solver_error (stitched geometry failing validation, see synthesis.hpp) is counted; it must
    // stay rare.
    std::size_t cases = 0, refused = 0, retried = 0;
    for (const std::string& f : files) {
        const exemplar ex = test::load_vector_exemplar(f);
        for (int closed = 0; closed < 2; ++closed) {
            for (double factor : factors) {
                const double L = std::round(factor * ex.width());
                INFO(f << " closed=" << closed << " L=" << L);
                vector_pattern::synthesis_options o;
                o.length = L;
                o.closed = closed != 0;
                if (ex.components() == 1) o.components = 1;
                ++cases;
                vector_pattern::synthesis_result r;
                try {
                    r = vector_pattern::synthesize_along(ex, o);
                } catch (const solver_error& e) {
                    WARN(e.what());
                    ++refused;
                    continue;
                }
                if (r.attempts > 1) ++retried;  // met, but only after a validation retry
                check_band(r, L, o.closed);
                if (o.components) CHECK(r.components == 1);
                // Ask again for exactly what was produced, with another seed: met exactly or refused.
                vector_pattern::synthesis_options o2 = o;
                o2.components = r.components;
                o2.holes = r.holes;
                o2.seed = 7;
                try {
                    const auto r2 = vector_pattern::synthesize_along(ex, o2);
                    check_band(r2, L, o.closed);
                    CHECK(r2.components == r.components);
                    CHECK(r2.holes == r.holes);
                } catch (const solver_error& e) {
                    WARN(e.what());
                }
            }
        }
    }
    // Measured figures are in benchmarks/README.md ("Robustness"); allow at most 5 % refusals,
    // i.e. no refusal at all in the 3-case default sweep.
    WARN("synthesis sweep: " << cases << " requests, " << refused << " refused, " << retried
                             << " met only after a validation retry");
    CHECK(refused * 20 <= cases);
}
}  // namespace

TEST_CASE("synthesis along open and closed bands meets topology requests exactly", "[pattern][synthesis]") {
    sweep({"greek_key.svg", "zigzag.svg", "quatrefoil.svg"}, {0.6});
}

TEST_CASE("synthesis sweep over every bundled exemplar and several lengths", "[pattern][synthesis][slow]") {
    sweep(std::vector<std::string>(std::begin(test::bundled_vector_files), std::end(test::bundled_vector_files)), {0.55, 0.8, 1.15});
}

namespace {
double point_segment_distance(vec2 p, vec2 a, vec2 b) {
    const vec2 d = b - a;
    const double t = std::clamp(glm::dot(p - a, d) / std::max(glm::dot(d, d), 1e-300), 0.0, 1.0);
    return glm::length(p - (a + t * d));
}
// Smallest distance from a vertex of a hole of area < 1 mm^2 to any other ring (brute force).
double tiny_hole_clearance(const std::vector<polygon_with_holes>& polys) {
    std::vector<ring2> all;
    for (const auto& p : polys) {
        all.push_back(p.outer);
        for (const ring2& h : p.holes) all.push_back(h);
    }
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (!(-signed_area(all[i]) < 1.0 && signed_area(all[i]) < 0.0)) continue;
        for (std::size_t j = 0; j < all.size(); ++j)
            if (j != i)
                for (const vec2& q : all[i])
                    for (std::size_t e = 0; e < all[j].size(); ++e)
                        best = std::min(best, point_segment_distance(q, all[j][e], all[j][(e + 1) % all[j].size()]));
    }
    return best;
}
}  // namespace

TEST_CASE("holes near a stitched chain keep their clearance", "[pattern][synthesis][stitching]") {
    // vine.svg has four holes of 0.043 mm^2 about 0.036 mm from the boundary around them. Moved with
    // the piece instead of with their nearest chain they were cut or touched (clearance 0) at
    // junctions; here they must stay apart and keep their area.
    const exemplar ex = test::load_vector_exemplar("vine.svg");
    const double original = tiny_hole_clearance(ex.polygons);
    REQUIRE(original > 0.02);
    REQUIRE(original < 0.05);
    for (bool closed : {false, true}) {
        INFO("closed " << closed);
        const auto r = vector_pattern::synthesize_along(ex, {.length = 384.0, .closed = closed, .components = 1});
        CHECK(tiny_hole_clearance(r.polygons) > 0.5 * original);
        for (const auto& p : r.polygons)
            for (const ring2& h : p.holes)
                if (-signed_area(h) < 1.0) CHECK(-signed_area(h) == Approx(0.0431).epsilon(0.1));
    }
}

TEST_CASE("synthesis is deterministic", "[pattern][synthesis]") {
    const exemplar ex = test::load_vector_exemplar("quatrefoil.svg");
    vector_pattern::synthesis_options o{.length = 300.0, .closed = true, .seed = 42};
    const auto a = vector_pattern::synthesize_along(ex, o), b = vector_pattern::synthesize_along(ex, o);
    CHECK(a.polygons == b.polygons);
    CHECK(a.sequence == b.sequence);
}

TEST_CASE("impossible or malformed requests throw the right error quickly", "[pattern][synthesis]") {
    const exemplar zig = test::load_vector_exemplar("zigzag.svg");
    const auto start = std::chrono::steady_clock::now();
    // The zigzag is one simple polygon: no arrangement of its pieces has a hole.
    CHECK_THROWS_AS(vector_pattern::synthesize_along(zig, {.length = 300.0, .holes = 1}), no_solution);
    CHECK_THROWS_AS(vector_pattern::synthesize_along(zig, {.length = 300.0, .components = 2}), no_solution);
    // Shorter than the first and last pieces together.
    CHECK_THROWS_AS(vector_pattern::synthesize_along(zig, {.length = 1.0}), no_solution);
    CHECK_THROWS_AS(vector_pattern::synthesize_along(zig, {.length = std::nan("")}), invalid_input);
    CHECK_THROWS_AS(vector_pattern::synthesize_along(zig, {.length = -5.0}), invalid_input);
    CHECK_THROWS_AS(vector_pattern::synthesize_along(zig, {.length = 300.0, .components = 0}), invalid_input);
    CHECK_THROWS_AS(vector_pattern::synthesize_along(exemplar{}, {.length = 300.0}), invalid_input);
    // A single piece with one portal on its left and none on its right: no piece can follow it,
    // so no closed loop exists.
    vector_pattern::exemplar_shape wedge;
    wedge.subpaths = {{{0, 0}, {30, 5}, {0, 10}}};
    const exemplar w = vector_pattern::make_exemplar({wedge});
    vector_pattern::synthesis_options ow{.length = 100.0, .closed = true};
    ow.slicing = vector_pattern::slicing_method::uniform;
    ow.uniform_lines = 0;
    CHECK_THROWS_AS(vector_pattern::synthesize_along(w, ow), no_solution);
    // Met only by stretching far from the target length (one piece across the whole curve): refused.
    ow.closed = false;
    ow.length = 100.0;
    CHECK_THROWS_AS(vector_pattern::synthesize_along(w, ow), no_solution);
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 60.0);
}

TEST_CASE("rectangles have the exact size and the requested topology", "[pattern][synthesis][rectangle]") {
    const exemplar ex = test::load_vector_exemplar("greek_key.svg");
    for (auto [W, H] : {std::pair{250.0, 200.0}, std::pair{400.0, 130.0}}) {
        INFO("W=" << W << " H=" << H);
        const auto r = vector_pattern::synthesize_rectangle(ex, {.width = W, .height = H, .components = 1});
        const box2 b = bounding_box(r.polygons);
        CHECK(b.lo.x == 0.0);
        CHECK(b.hi.x == W);
        CHECK(b.lo.y == 0.0);
        CHECK(b.hi.y == H);
        for (const auto& p : r.polygons) {
            REQUIRE(is_simple(p.outer));
            for (const auto& h : p.holes) REQUIRE(is_simple(h));
        }
        const auto t = test::raster_topology(r.polygons, {0, 0}, {W, H}, 0.1);
        CHECK(t.components == 1);
        CHECK(t.holes == r.holes);
        const auto r2 = vector_pattern::synthesize_rectangle(ex, {.width = W, .height = H, .components = 1, .holes = r.holes, .seed = 3});
        CHECK(test::raster_topology(r2.polygons, {0, 0}, {W, H}, 0.1).holes == r.holes);
    }
}

TEST_CASE("synthesis phases called one by one give synthesize_along's result", "[pattern][synthesis][phases]") {
    namespace d = vector_pattern::detail;
    const exemplar ex = test::load_vector_exemplar("greek_key.svg");
    for (bool closed : {false, true}) {
        INFO("closed " << closed);
        const vector_pattern::synthesis_options o{.length = std::round(0.6 * ex.width()), .closed = closed, .components = 1};
        const d::prepared_pieces pp = d::prepare_pieces(ex, o);
        if (closed) {
            CHECK(pp.dp.size() == pp.pieces.size());
        } else {
            // The band-end copies of P_0 and P_t, their outer sides stripped from the descriptor.
            REQUIRE(pp.dp.size() == pp.pieces.size() + 2);
            REQUIRE(pp.first.size() == 1);
            REQUIRE(pp.last.size() == 1);
            CHECK(pp.descriptors[pp.first[0]].left().empty());
            CHECK(pp.descriptors[pp.last[0]].right().size() == 0);
            CHECK(pp.descriptors[pp.first[0]].right().size() == pp.pieces.front().right.size());
        }
        const dp::transition_table table = d::junction_costs(pp, o, {}, {});
        const d::chosen_sequence chosen = d::solve_piece_sequence(pp, table, o);
        const std::vector<std::size_t>& placed = chosen.solution.pieces;
        const std::vector<double> delta = d::piece_offsets(pp, table, placed, o);
        REQUIRE(delta.size() == placed.size());
        CHECK(delta.front() == 0.0);
        if (!closed) CHECK(delta.back() == 0.0);
        const d::stitch_targets targets = d::junction_targets(pp, placed, delta, chosen.solution.length, o);
        REQUIRE(targets.u.size() == placed.size() + 1);
        CHECK(targets.u.front() == 0.0);
        CHECK(targets.u.back() == o.length);
        CHECK(targets.u_scale == Approx(o.length / chosen.solution.length));
        const d::stitched_rings stitched = d::deform_pieces(pp, placed, delta, targets);
        REQUIRE(stitched.rings.size() == stitched.owner.size());
        const d::merged_band merged = d::merge_band(stitched, o.length);
        const vector_pattern::band_counts counts = d::validate_band(stitched, merged.polygons, o);
        CHECK(counts.components == 1);
        // The whole pipeline does the same when its first attempt validates.
        const vector_pattern::synthesis_result r = vector_pattern::synthesize_along(ex, o);
        REQUIRE(r.attempts == 1);
        CHECK(r.polygons == merged.polygons);
        CHECK(r.offsets == delta);
        CHECK(r.holes == counts.holes);
        // validate_band refuses geometry that does not meet the request.
        vector_pattern::synthesis_options wrong = o;
        wrong.components = 2;
        CHECK_THROWS_AS(d::validate_band(stitched, merged.polygons, wrong), d::geometry_mismatch);
    }
}

TEST_CASE("synthesis retry rule: bans first, derived seeds when nothing is to blame", "[pattern][synthesis][phases]") {
    namespace d = vector_pattern::detail;
    const vector_pattern::synthesis_options o{.length = 100.0, .seed = 3};
    d::retry_state retry;
    const d::cost_variation first = retry.next_attempt(o);
    CHECK(first.seed == 3);
    CHECK(first.variation == o.seed_variation);
    CHECK_FALSE(retry.drop_bans());  // nothing banned: a no_solution is final
    // A mismatch with no piece to blame perturbs the next attempt's costs.
    retry.blame("mismatch", {}, clip_grid{}, {0, 1}, o);
    CHECK(retry.banned().empty());
    CHECK(retry.last_error() == "mismatch");
    const d::cost_variation second = retry.next_attempt(o);
    CHECK(second.seed == hash64(3, std::size_t{1}));
    CHECK(second.variation == Approx(0.25));
}

TEST_CASE("merge_contours: the tree of unions gives the one-shot union's region and topology", "[pattern][synthesis][contours]") {
    // 300 unit pieces in a row sharing their sides (as stitched pieces share portals), each with a
    // square hole, and every third carrying a second ring that overlaps its neighbour.
    const int n = 300;
    std::vector<ring2> rings;
    std::vector<std::size_t> piece;
    auto square = [](double x0, double y0, double x1, double y1, bool hole) {
        ring2 r{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
        if (hole) std::reverse(r.begin(), r.end());
        return r;
    };
    for (int i = 0; i < n; ++i) {
        const double x = i;
        rings.push_back(square(x, 0, x + 1, 1, false)), piece.push_back(static_cast<std::size_t>(i));
        rings.push_back(square(x + 0.25, 0.25, x + 0.75, 0.75, true)), piece.push_back(static_cast<std::size_t>(i));
        if (i % 3 == 0) rings.push_back(square(x + 0.8, 0.9, x + 1.3, 1.2, false)), piece.push_back(static_cast<std::size_t>(i));
    }
    const double L = n - 0.5;  // the strip cuts through the last piece
    box2 b;
    for (const ring2& r : rings)
        for (const vec2& p : r) b.extend(p);
    b.extend(vec2(L, b.hi.y + 1)).extend(vec2(0, b.lo.y - 1));
    const clip_grid grid = clip_grid::for_bounds(b);
    const ring2 strip{{0.0, b.lo.y - 1}, {L, b.lo.y - 1}, {L, b.hi.y + 1}, {0.0, b.hi.y + 1}};
    const auto one_shot = polygon_boolean(clip_op::intersection, rings, fill_rule::nonzero, {strip}, fill_rule::nonzero, grid, false);
    for (const bool with_pieces : {true, false}) {
        INFO("piece ids given: " << with_pieces);
        const auto tree = vector_pattern::merge_contours(rings, L, grid, with_pieces ? &piece : nullptr);
        std::size_t holes_tree = 0, holes_one = 0;
        for (const auto& p : tree) holes_tree += p.holes.size();
        for (const auto& p : one_shot) holes_one += p.holes.size();
        CHECK(tree.size() == one_shot.size());
        CHECK(holes_tree == holes_one);
        CHECK(holes_tree == static_cast<std::size_t>(n - 1));  // the last hole is cut open by the strip at 299.5
        CHECK(area(tree) == Approx(area(one_shot)).epsilon(1e-12));
        // the symmetric difference is empty up to the grid's rounding
        CHECK(area(polygon_boolean(clip_op::xor_, to_rings(tree), fill_rule::nonzero, to_rings(one_shot), fill_rule::nonzero, grid)) < 1e-9);
    }
    const std::vector<std::size_t> too_few(3);
    CHECK_THROWS_AS(vector_pattern::merge_contours(rings, L, grid, &too_few), invalid_input);
}
