// topology_cut.hpp (filigree-synthesis.md §4.5): case 1 on a T with a short stub, case 2 on a
// lens of two loops (Fig. 9b) and on a loop branch against a dangling branch (Fig. 9d) with the
// importance of eq. 4 worked out by hand, case 1 at a crossing case 2 leaves in a cluster, a cut refused because it would isolate a third element,
// no crossings, a randomized check against a brute-force connectivity oracle, the same cut with
// every skeleton in a random frame of its own (topology_cut_in_frames; the random patterns hold
// exact copies of a segment, which must stay non-crossing), determinism and input errors.
#include <catch2/catch.hpp>

#include <fabsynth/core/rng.hpp>
#include <fabsynth/filigree/topology_cut.hpp>
#include <fabsynth/geometry/rigid_motion.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <numeric>
#include <utility>
#include <vector>

namespace topocut_test {

using fabsynth::vec2;
using fabsynth::filigree::topology_cut;
using fabsynth::filigree::topology_cut_options;
using fabsynth::filigree::topology_cut_report;
using skel = fabsynth::graph::skeleton_graph<vec2>;
using pair_list = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

/// A polyline (closed: the last point joins the first) of constant width w.
inline skel polyline(const std::vector<vec2>& points, double w, bool closed = false) {
    skel g;
    for (const vec2& p : points) g.add_vertex(p, w);
    for (std::uint32_t i = 0; i + 1 < points.size(); ++i) g.add_edge(i, i + 1);
    if (closed) g.add_edge(static_cast<std::uint32_t>(points.size() - 1), 0);
    return g;
}

inline topology_cut_report run(std::vector<skel>& instances, const pair_list& pairs, const topology_cut_options& opt = {}) {
    return topology_cut(instances, std::span<const std::pair<std::uint32_t, std::uint32_t>>(pairs), opt);
}

/// True iff some live edge of g has both end points within 1e-9 of the segment [a, b] (an axis
/// parallel segment: checked by coordinates).
inline bool has_edge_on(const skel& g, vec2 a, vec2 b) {
    const vec2 lo = glm::min(a, b) - vec2(1e-9), hi = glm::max(a, b) + vec2(1e-9);
    auto inside = [&](vec2 p) { return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y; };
    for (std::uint32_t e = 0; e < g.edge_slots(); ++e)
        if (g.edge_alive(e) && inside(g.position(g.endpoints(e).first)) && inside(g.position(g.endpoints(e).second))) return true;
    return false;
}

// ---- the brute-force oracle (shares no code with the header) ---------------------------------

struct strip_segment {
    vec2 a, b;
    double wa, wb;
};

inline std::vector<strip_segment> live_segments(const skel& g) {
    std::vector<strip_segment> out;
    for (std::uint32_t e = 0; e < g.edge_slots(); ++e) {
        if (!g.edge_alive(e)) continue;
        const auto [u, v] = g.endpoints(e);
        out.push_back({g.position(u), g.position(v), g.width(u), g.width(v)});
    }
    return out;
}

/// Parameter of the point of [a, b] nearest to p.
inline double nearest_parameter(vec2 p, vec2 a, vec2 b) {
    const vec2 d = b - a;
    const double dd = d.x * d.x + d.y * d.y;
    if (dd == 0.0) return 0.0;
    const double t = ((p.x - a.x) * d.x + (p.y - a.y) * d.y) / dd;
    return t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
}

/// Strips touch: minimise |A(u) - B(v)| over the unit square (the crossing of the two lines
/// when it lies inside, else the best of the four sides, each a clamped projection) and compare
/// with the mean width there.
inline bool strips_touch(const strip_segment& s, const strip_segment& r) {
    double best = std::numeric_limits<double>::infinity(), reach = 0.0;
    auto at = [&](double u, double v) {
        const vec2 p = s.a + u * (s.b - s.a), q = r.a + v * (r.b - r.a);
        const double d = std::hypot(p.x - q.x, p.y - q.y);
        if (d < best) best = d, reach = 0.5 * ((s.wa + u * (s.wb - s.wa)) + (r.wa + v * (r.wb - r.wa)));
    };
    const vec2 ds = s.b - s.a, dr = r.b - r.a, w = r.a - s.a;
    const double det = ds.x * (-dr.y) - ds.y * (-dr.x);  // solve u ds - v dr = w by Cramer's rule
    if (det != 0.0) {
        const double u = (w.x * (-dr.y) - w.y * (-dr.x)) / det, v = (ds.x * w.y - ds.y * w.x) / det;
        if (u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0) at(u, v);
    }
    for (const double u : {0.0, 1.0}) at(u, nearest_parameter(s.a + u * ds, r.a, r.b));
    for (const double v : {0.0, 1.0}) at(nearest_parameter(r.a + v * dr, s.a, s.b), v);
    return best <= reach;
}

/// Tiny disjoint sets for the oracle.
struct oracle_sets {
    std::vector<std::size_t> up;
    explicit oracle_sets(std::size_t n) : up(n) { std::iota(up.begin(), up.end(), std::size_t{0}); }
    std::size_t root(std::size_t x) {
        while (up[x] != x) x = up[x] = up[up[x]];
        return x;
    }
    void join(std::size_t a, std::size_t b) { up[root(a)] = root(b); }
};

/// Number of components of g's live edges (isolated vertices ignored).
inline std::size_t pieces(const skel& g) {
    oracle_sets sets(g.num_vertices());
    std::vector<bool> used(g.num_vertices(), false);
    for (std::uint32_t e = 0; e < g.edge_slots(); ++e)
        if (g.edge_alive(e)) {
            const auto [u, v] = g.endpoints(e);
            sets.join(u, v);
            used[u] = used[v] = true;
        }
    std::size_t n = 0;
    for (std::size_t v = 0; v < g.num_vertices(); ++v) n += used[v] && sets.root(v) == v;
    return n;
}

/// True iff instances a and b touch (every segment pair tried).
inline bool instances_touch(const skel& a, const skel& b) {
    const auto sa = live_segments(a), sb = live_segments(b);
    for (const auto& s : sa)
        for (const auto& r : sb)
            if (strips_touch(s, r)) return true;
    return false;
}

/// The whole pattern is one piece: the live segments of all instances, joined where they share a
/// vertex (same instance) or touch (different instances, every segment pair tried), form one set.
inline bool pattern_connected(const std::vector<skel>& instances) {
    struct tagged {
        std::size_t inst;
        std::uint32_t u, v;
        strip_segment seg;
    };
    std::vector<tagged> all;
    for (std::size_t k = 0; k < instances.size(); ++k)
        for (std::uint32_t e = 0; e < instances[k].edge_slots(); ++e)
            if (instances[k].edge_alive(e)) {
                const auto [u, v] = instances[k].endpoints(e);
                const skel& g = instances[k];
                all.push_back({k, u, v, {g.position(u), g.position(v), g.width(u), g.width(v)}});
            }
    oracle_sets sets(all.size());
    for (std::size_t i = 0; i < all.size(); ++i)
        for (std::size_t j = i + 1; j < all.size(); ++j) {
            const tagged &x = all[i], &y = all[j];
            const bool joined = x.inst == y.inst ? (x.u == y.u || x.u == y.v || x.v == y.u || x.v == y.v) : strips_touch(x.seg, y.seg);
            if (joined) sets.join(i, j);
        }
    std::size_t roots = 0;
    for (std::size_t i = 0; i < all.size(); ++i) roots += sets.root(i) == i;
    return roots == 1;
}

/// Every touching pair (i < j), in increasing order: the connected pairs of a synthesized layout.
inline pair_list touching_pairs(const std::vector<skel>& instances) {
    pair_list out;
    for (std::uint32_t i = 0; i < instances.size(); ++i)
        for (std::uint32_t j = i + 1; j < instances.size(); ++j)
            if (instances_touch(instances[i], instances[j])) out.emplace_back(i, j);
    return out;
}

/// `count` random polylines in a 20 mm square: wandering runs, sometimes with a side branch or
/// closed into a loop, widths varying per vertex; the last `satellites` are short caps placed just
/// beyond a free end of an earlier run, touching it (when that end is a stub beyond a crossing, it
/// is the only link of the cap). Redrawn (next attempt) until the oracle finds the pattern
/// connected.
inline std::vector<skel> random_pattern(std::uint64_t seed, std::size_t count = 20, std::size_t satellites = 5) {
    constexpr double turn = 6.283185307179586;
    for (std::uint64_t attempt = 0;; ++attempt) {
        fabsynth::counter_rng rng(seed, attempt);
        std::vector<skel> out;
        for (std::size_t k = 0; k + satellites < count; ++k) {
            skel g;
            const double w = rng.uniform(0.4, 0.9);
            auto width = [&] { return w * rng.uniform(0.8, 1.2); };
            vec2 p(rng.uniform(0.0, 20.0), rng.uniform(0.0, 20.0));
            double heading = rng.uniform(0.0, turn);
            const auto n = 5 + rng.uniform_int(6);
            std::uint32_t prev = g.add_vertex(p, width());
            for (std::uint64_t i = 1; i < n; ++i) {
                heading += rng.uniform(-0.9, 0.9);
                p += rng.uniform(1.5, 3.5) * vec2(std::cos(heading), std::sin(heading));
                const std::uint32_t v = g.add_vertex(p, width());
                g.add_edge(prev, v);
                prev = v;
            }
            const std::uint32_t main_end = prev;
            if (rng.uniform() < 0.5) {  // a side branch from an interior vertex
                std::uint32_t at = static_cast<std::uint32_t>(1 + rng.uniform_int(n - 2));
                vec2 q = g.position(at);
                double h = rng.uniform(0.0, turn);
                const auto m = 1 + rng.uniform_int(3);
                for (std::uint64_t i = 0; i < m; ++i) {
                    h += rng.uniform(-0.7, 0.7);
                    q += rng.uniform(0.8, 2.5) * vec2(std::cos(h), std::sin(h));
                    const std::uint32_t v = g.add_vertex(q, width());
                    g.add_edge(at, v);
                    at = v;
                }
            }
            if (rng.uniform() < 0.3) g.add_edge(main_end, 0);  // a loop
            out.push_back(std::move(g));
        }
        for (std::size_t k = 0; k < satellites; ++k) {
            const skel& host = out[rng.uniform_int(count - satellites)];
            std::vector<std::uint32_t> ends;
            for (std::uint32_t v = 0; v < host.num_vertices(); ++v)
                if (host.valence(v) == 1) ends.push_back(v);
            const double ws = 0.3;
            if (ends.empty()) {  // a loop without free ends: a lone cap somewhere
                const vec2 c(rng.uniform(0.0, 20.0), rng.uniform(0.0, 20.0));
                out.push_back(polyline({c, c + vec2(0.8, 0.0)}, ws));
                continue;
            }
            const std::uint32_t end = ends[rng.uniform_int(ends.size())];
            const std::uint32_t inner = host.other(host.incident(end)[0], end);
            const vec2 dir = glm::normalize(host.position(end) - host.position(inner)), across(-dir.y, dir.x);
            const vec2 c = host.position(end) + 0.7 * 0.5 * (host.width(end) + ws) * dir;
            out.push_back(polyline({c - 0.4 * across, c + 0.4 * across}, ws));
        }
        if (pattern_connected(out)) return out;
    }
}

inline bool same_skeleton(const skel& a, const skel& b) {
    if (a.num_vertices() != b.num_vertices() || a.edge_slots() != b.edge_slots()) return false;
    for (std::uint32_t v = 0; v < a.num_vertices(); ++v)
        if (a.position(v) != b.position(v) || a.width(v) != b.width(v)) return false;
    for (std::uint32_t e = 0; e < a.edge_slots(); ++e)
        if (a.edge_alive(e) != b.edge_alive(e) || a.endpoints(e) != b.endpoints(e)) return false;
    return true;
}

/// The square loop [0, 10]^2 of width 1 (length 40).
inline skel square_p() { return polyline({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, 1.0, true); }

/// A loop of width 1 whose left tip (9, 5) pokes into the square through its right side, crossing
/// it at (10, 4) and (10, 6): the lens of Fig. 9b.
inline skel lens_q() { return polyline({{9, 5}, {12, 2}, {16, 2}, {16, 8}, {12, 8}}, 1.0, true); }

// The test cases live in the namespace too: in the module's unity build a sibling file's
// using-directive could otherwise make a helper name ambiguous.

TEST_CASE("topology cut: a short stub beyond a single crossing is trimmed (Fig. 9a)", "[filigree][topology_cut]") {
    SECTION("1.0 mm stub, threshold 30 x 0.5 mm: trimmed, the crossing becomes a T") {
        std::vector<skel> v{polyline({{0, 0}, {10, 0}}, 0.5), polyline({{5, 8}, {5, -1.0}}, 0.5)};
        const auto r = run(v, {{0, 1}});
        CHECK(r.protrusions_trimmed == 1);
        CHECK(r.branches_cut == 0);
        CHECK(r.cuts_refused_for_connectivity == 0);
        CHECK(v[0].total_length() == Approx(10.0));  // the bar: split at the crossing, nothing removed
        CHECK(v[0].num_edges() == 2);
        CHECK(v[1].total_length() == Approx(8.0));   // the stem down to the bar
        CHECK(v[1].num_edges() == 1);
        CHECK_FALSE(has_edge_on(v[1], {5, -1.0}, {5, -1e-3}));
        CHECK(pattern_connected(v));
    }
    SECTION("only the shortest of the four arms goes: an X becomes a T") {
        // arms: bar 3 and 7, stem 4 and 4; the bar's 3 mm left arm is cut, nothing else
        std::vector<skel> v{polyline({{0, 0}, {10, 0}}, 0.5), polyline({{3, 4}, {3, -4}}, 0.5)};
        const auto r = run(v, {{0, 1}});
        CHECK(r.protrusions_trimmed == 1);
        CHECK(v[0].total_length() == Approx(7.0));
        CHECK_FALSE(has_edge_on(v[0], {0, 0}, {3, 0}));
        CHECK(v[1].total_length() == Approx(8.0));  // the stem crosses whole
        CHECK(pattern_connected(v));
    }
    SECTION("every arm longer than the threshold: kept (split only)") {
        std::vector<skel> v{polyline({{0, 0}, {40, 0}}, 0.5), polyline({{20, 20}, {20, -16}}, 0.5)};
        const auto r = run(v, {{0, 1}});
        CHECK(r.protrusions_trimmed == 0);  // shortest arm 16 mm >= 30 x 0.5 mm
        CHECK(v[0].total_length() == Approx(40.0));
        CHECK(v[1].total_length() == Approx(36.0));
        CHECK(v[1].num_edges() == 2);
    }
    SECTION("explicit protrusion_length 0.8 mm: the 1.0 mm stub stays") {
        std::vector<skel> v{polyline({{0, 0}, {10, 0}}, 0.5), polyline({{5, 8}, {5, -1.0}}, 0.5)};
        topology_cut_options opt;
        opt.protrusion_length = 0.8;
        CHECK(run(v, {{0, 1}}, opt).protrusions_trimmed == 0);
        CHECK(v[1].total_length() == Approx(9.0));
    }
}

TEST_CASE("topology cut: of two conflicting branches of a lens the lower eq. 4 importance goes (Fig. 9b)", "[filigree][topology_cut]") {
    // By hand. P = the square (length 40); A = its side from (10,4) to (10,6): L = 2, the other
    // subgraph of P is the rest of the square, 38. Q = the lens loop, length 6 sqrt2 + 14; B = its
    // tip (10,4)-(9,5)-(10,6): L = 2 sqrt2, the rest of Q 4 sqrt2 + 14.
    const double s2 = std::sqrt(2.0);
    const double la = 2.0, lb = 2.0 * s2, q_total = 6.0 * s2 + 14.0;
    const double ia = la + (40.0 - la), ib = lb + (q_total - lb);  // alpha = beta = 1
    REQUIRE(ib < ia);  // B goes although it is the longer branch: F decides
    REQUIRE(lb > la);
    for (const bool reversed : {false, true}) {
        INFO("pair given as " << (reversed ? "(Q, P)" : "(P, Q)"));
        std::vector<skel> v{square_p(), lens_q()};
        const pair_list pairs = reversed ? pair_list{{1, 0}} : pair_list{{0, 1}};
        const auto r = run(v, pairs);
        CHECK(r.branches_cut == 1);
        CHECK(r.protrusions_trimmed == 0);
        CHECK(r.cuts_refused_for_connectivity == 0);
        CHECK(v[0].total_length() == Approx(40.0));
        CHECK(has_edge_on(v[0], {10, 4}, {10, 6}));  // A kept
        CHECK(v[1].total_length() == Approx(q_total - lb));
        CHECK(v[1].valence(0) == 0);  // the tip (9, 5) is gone
        CHECK(pieces(v[1]) == 1);
        CHECK(pattern_connected(v));
    }
    SECTION("crossings 2 mm apart along P are not close below close_intersections = 1.5 mm") {
        std::vector<skel> v{square_p(), lens_q()};
        topology_cut_options opt;
        opt.close_intersections = 1.5;
        const auto r = run(v, {{0, 1}}, opt);
        CHECK(r.branches_cut == 0);
        CHECK(v[1].total_length() == Approx(q_total));
    }
}

TEST_CASE("topology cut: a branch inside a loop beats a dangling branch (Fig. 9d)", "[filigree][topology_cut]") {
    // Q comes up from below, dips into the square through its bottom side at (4.5, 0), leaves at
    // (5.5, 0) and ends 1.118 mm further. By hand: A = P's side from (4.5,0) to (5.5,0), L = 1,
    // F = 39 (the rest of the loop): I = 40. Q's subgraphs: body 7 + c, B = 2c, tail c with
    // c = sqrt(1.25): I(B) = 2c + min(7 + c, c) = 3c. B goes, and the tail it leaves hanging
    // (shorter than 1.5 x 1 mm) with it.
    const double c = std::sqrt(1.25);
    REQUIRE(3.0 * c < 40.0);
    REQUIRE(2.0 * c > 1.0);  // the loop branch is the shorter one
    std::vector<skel> v{square_p(), polyline({{4, -8}, {4, -1}, {5, 1}, {6, -1}}, 1.0)};
    const auto r = run(v, {{0, 1}});
    CHECK(r.branches_cut == 1);
    CHECK(r.cuts_refused_for_connectivity == 0);
    CHECK(v[0].total_length() == Approx(40.0));
    CHECK(has_edge_on(v[0], {4.5, 0}, {5.5, 0}));  // the loop branch stays
    CHECK(v[1].total_length() == Approx(7.0 + c));
    CHECK(v[1].valence(2) == 0);  // (5, 1) inside the square
    CHECK(v[1].valence(3) == 0);  // the tail's end (6, -1)
    CHECK(pattern_connected(v));
}

TEST_CASE("topology cut: a conflicting branch may split its element when both remains stay joined (Fig. 9c)", "[filigree][topology_cut]") {
    // Q dips into the square through its bottom side at (4.5, 0) and (5.5, 0) and goes on down on
    // both sides. By hand: A = P's side between the crossings, I = 1 + 39 = 40; Q's tip B = 2c,
    // its two legs 7 + c each (c = sqrt(1.25)): I(B) = 2c + 7 + c. B goes; each leg ends on the
    // square's side, so the pattern stays one piece although Q is now two.
    const double c = std::sqrt(1.25);
    REQUIRE(7.0 + 3.0 * c < 40.0);
    std::vector<skel> v{square_p(), polyline({{4, -8}, {4, -1}, {5, 1}, {6, -1}, {6, -8}}, 1.0)};
    REQUIRE(pattern_connected(v));
    const auto r = run(v, {{0, 1}});
    CHECK(r.branches_cut == 1);
    CHECK(r.cuts_refused_for_connectivity == 0);
    CHECK(v[0].total_length() == Approx(40.0));
    CHECK(v[1].total_length() == Approx(2.0 * (7.0 + c)));
    CHECK(pieces(v[1]) == 2);
    CHECK(pattern_connected(v));
}

TEST_CASE("topology cut: a crossing that case 2 leaves among close crossings gets case 1", "[filigree][topology_cut]") {
    // By hand, widths 0.8, all three crossings one cluster (close_intersections 30 mm). P is a
    // hairpin: bottom strand y = 0 from x = -10 to 10, up to y = 2, top strand back to x = -10
    // (42 mm). Q comes up x = 0 from y = -5 to 5, right to x = 5, down to (5, 1) between the strands.
    // Sites: a (0, 0), b (0, 2), c (5, 2). P's subgraphs: {a} 10, {a, c} 17, {b, c} 5, {b} 10;
    // Q's: {a} 5, {a, b} 2, {b, c} 11, {c} 1. Only {b, c} is on both: eq. 4 gives P's 5 + 10 = 15
    // and Q's 11 + 1 = 12, so Q's arc goes and takes its 1 mm tail along (< 1.5 x 0.8 mm). That
    // leaves both skeletons passing through a: case 1 there cuts the shortest dangling arm, Q's
    // 5 mm stem below P (P's is 10), and Q ends as the 2 mm rung between the strands.
    std::vector<skel> v{polyline({{-10, 0}, {10, 0}, {10, 2}, {-10, 2}}, 0.8), polyline({{0, -5}, {0, 5}, {5, 5}, {5, 1}}, 0.8)};
    topology_cut_options opt;
    opt.close_intersections = 30.0;
    const auto r = run(v, {{0, 1}}, opt);
    CHECK(r.branches_cut == 1);
    CHECK(r.protrusions_trimmed == 1);
    CHECK(r.cuts_refused_for_connectivity == 0);
    CHECK(v[0].total_length() == Approx(42.0));
    CHECK(v[1].total_length() == Approx(2.0));
    CHECK(has_edge_on(v[1], {0, 0}, {0, 2}));
    CHECK_FALSE(has_edge_on(v[1], {0, -5}, {0, -1e-3}));  // the stem that crossed P at a
    CHECK(pattern_connected(v));
}

TEST_CASE("topology cut: a cut that would isolate a third element is refused", "[filigree][topology_cut]") {
    // R (width 0.2) sits 0.4 mm left of the lens tip (9, 5): it touches B (reach 0.6) and nothing
    // else (1.4 mm from P's side). Removing B, the lower-importance branch, would cut R off.
    std::vector<skel> v{square_p(), lens_q(), polyline({{8.6, 4.5}, {8.6, 5.5}}, 0.2)};
    REQUIRE(pattern_connected(v));
    REQUIRE_FALSE(instances_touch(v[0], v[2]));
    const auto r = run(v, {{0, 1}});
    CHECK(r.branches_cut == 0);
    CHECK(r.cuts_refused_for_connectivity == 1);
    CHECK(v[0].total_length() == Approx(40.0));
    CHECK(v[1].total_length() == Approx(6.0 * std::sqrt(2.0) + 14.0));
    CHECK(v[2].total_length() == Approx(1.0));
    CHECK(pattern_connected(v));
}

TEST_CASE("topology cut: no crossings, nothing changes", "[filigree][topology_cut]") {
    // parallel strips that touch (1 mm apart, width 1) but whose skeletons never cross
    std::vector<skel> v{polyline({{0, 0}, {4, 0}, {10, 0}}, 1.0), polyline({{0, 1}, {10, 1}}, 1.0),
                        polyline({{20, 0}, {30, 0}, {30, 10}}, 1.0)};
    const auto before = v;
    const auto r = run(v, {{0, 1}, {1, 2}, {0, 2}});
    CHECK(r.protrusions_trimmed == 0);
    CHECK(r.branches_cut == 0);
    CHECK(r.cuts_refused_for_connectivity == 0);
    for (std::size_t k = 0; k < v.size(); ++k) CHECK(same_skeleton(v[k], before[k]));
}

TEST_CASE("topology cut: random patterns stay one component (brute-force oracle)", "[filigree][topology_cut]") {
    std::size_t trimmed = 0, cut = 0, refused = 0, split = 0;
    for (std::uint64_t seed = 1; seed <= 16; ++seed) {
        INFO("seed " << seed);
        std::vector<skel> v = random_pattern(seed);
        const pair_list pairs = touching_pairs(v);
        std::vector<double> lengths;
        for (const skel& g : v) lengths.push_back(g.total_length());
        const auto r = run(v, pairs);
        trimmed += r.protrusions_trimmed, cut += r.branches_cut, refused += r.cuts_refused_for_connectivity;
        CHECK(pattern_connected(v));
        for (std::size_t k = 0; k < v.size(); ++k) {
            split += pieces(v[k]) > 1;
            CHECK(pieces(v[k]) >= 1);
            CHECK(v[k].total_length() <= lengths[k] * (1.0 + 1e-12));
        }
    }
    INFO("trimmed " << trimmed << ", branches cut " << cut << ", refused " << refused << ", instances in pieces " << split);
    CHECK(trimmed > 0);
    CHECK(cut > 0);
    CHECK(refused > 0);
}

TEST_CASE("topology cut: same input, same output", "[filigree][topology_cut]") {
    const std::vector<skel> input = random_pattern(11);
    const pair_list pairs = touching_pairs(input);
    std::vector<skel> a = input, b = input;
    const auto ra = run(a, pairs), rb = run(b, pairs);
    CHECK(ra.protrusions_trimmed == rb.protrusions_trimmed);
    CHECK(ra.branches_cut == rb.branches_cut);
    CHECK(ra.cuts_refused_for_connectivity == rb.cuts_refused_for_connectivity);
    for (std::size_t k = 0; k < a.size(); ++k) CHECK(same_skeleton(a[k], b[k]));
}

TEST_CASE("topology cut in frames: every skeleton in a random frame of its own gives the planar cut", "[filigree][topology_cut]") {
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
        INFO("seed " << seed);
        std::vector<skel> world = random_pattern(seed);
        const pair_list pairs = touching_pairs(world);
        // frame k -> world: rotation by angle[k], then translation shift[k] (composed by hand here)
        fabsynth::counter_rng r(seed, 100u);
        std::vector<double> angle;
        std::vector<vec2> shift;
        std::vector<skel> own;
        for (const skel& g : world) {
            angle.push_back(r.uniform(-3.0, 3.0)), shift.emplace_back(r.uniform(-50.0, 50.0), r.uniform(-50.0, 50.0));
            const double c = std::cos(angle.back()), s = std::sin(angle.back());
            skel o = g;
            for (std::uint32_t v = 0; v < o.num_vertices(); ++v) {  // world -> own: R^T (x - t)
                const vec2 d = g.position(v) - shift.back();
                o.set_position(v, {c * d.x + s * d.y, -s * d.x + c * d.y});
            }
            own.push_back(std::move(o));
        }
        fabsynth::filigree::instance_frames frames;
        frames.pose = [&](std::uint32_t a, std::uint32_t b) -> std::optional<fabsynth::rigid_motion2> {
            // b's coordinates to a's: R_a^T (R_b x + t_b - t_a)
            const double th = angle[b] - angle[a], ca = std::cos(angle[a]), sa = std::sin(angle[a]);
            const vec2 d = shift[b] - shift[a];
            return fabsynth::rigid_motion2{std::cos(th), std::sin(th), vec2(ca * d.x + sa * d.y, -sa * d.x + ca * d.y)};
        };
        frames.neighbours = [&](std::uint32_t) {
            std::vector<std::uint32_t> all(world.size());
            std::iota(all.begin(), all.end(), 0u);
            return all;
        };
        const auto planar = run(world, pairs);
        const auto framed = fabsynth::filigree::topology_cut_in_frames(own, std::span<const std::pair<std::uint32_t, std::uint32_t>>(pairs), frames);
        CHECK(framed.protrusions_trimmed == planar.protrusions_trimmed);
        CHECK(framed.branches_cut == planar.branches_cut);
        CHECK(framed.cuts_refused_for_connectivity == planar.cuts_refused_for_connectivity);
        for (std::size_t k = 0; k < world.size(); ++k) {
            REQUIRE(own[k].num_vertices() == world[k].num_vertices());
            REQUIRE(own[k].edge_slots() == world[k].edge_slots());
            const double c = std::cos(angle[k]), s = std::sin(angle[k]);
            for (std::uint32_t v = 0; v < own[k].num_vertices(); ++v) {
                const vec2 x = own[k].position(v), back = vec2(c * x.x - s * x.y, s * x.x + c * x.y) + shift[k];
                CHECK(glm::distance(back, world[k].position(v)) < 1e-9);
            }
            for (std::uint32_t e = 0; e < own[k].edge_slots(); ++e) {
                CHECK(own[k].edge_alive(e) == world[k].edge_alive(e));
                CHECK(own[k].endpoints(e) == world[k].endpoints(e));
            }
        }
    }
}

TEST_CASE("topology cut: bad input is refused by name, nothing changed", "[filigree][topology_cut]") {
    std::vector<skel> v{square_p(), lens_q()};
    const auto before = v;
    CHECK_THROWS_AS(run(v, {{0, 1}, {0, 2}}), fabsynth::invalid_input);
    CHECK_THROWS_WITH(run(v, {{0, 1}, {0, 2}}), Catch::Contains("connected pair 1 (0, 2)") && Catch::Contains("instance 2"));
    CHECK_THROWS_WITH(run(v, {{1, 1}}), Catch::Contains("with itself"));
    topology_cut_options opt;
    opt.close_intersections = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH(run(v, {{0, 1}}, opt), Catch::Contains("close_intersections"));
    opt = {};
    opt.detached_length = std::numeric_limits<double>::infinity();
    CHECK_THROWS_WITH(run(v, {{0, 1}}, opt), Catch::Contains("detached_length"));
    opt = {};
    opt.beta = -1.0;
    CHECK_THROWS_WITH(run(v, {{0, 1}}, opt), Catch::Contains("beta"));
    for (std::size_t k = 0; k < v.size(); ++k) CHECK(same_skeleton(v[k], before[k]));
}

}  // namespace topocut_test
