// SPDX-License-Identifier: MIT
#pragma once
/// @file contact.hpp  The planner of the two tangential-contact cases of Fig. 6
/// (filigree-synthesis.md §4.3.2 "Smooth Connection via Non-rigid Deformation"): where element P
/// should move to touch its neighbour Q, as hard constraints of ffd.hpp's free-form deformation,
/// and SMOOTHCONNECTION (plan, deform, accept below the distortion bound).
///
/// Usage:
///   using namespace fabsynth::filigree;
///   // Fig. 6: bring element P into tangential contact with its neighbour Q.
///   if (auto plan = plan_tangent_contact(p_pos, p_edges, q_pos, q_edges, p_junctions, {}))
///       r = ffd_deform(p_pos, p_edges, plan->constraints);
///   auto accepted = smooth_connection(p_pos, p_edges, q_pos, q_edges, p_junctions);  // both steps
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/filigree/ffd.hpp"
#include "fabsynth/geometry/segment.hpp"
#include "fabsynth/graph/skeleton_graph.hpp"

namespace fabsynth::filigree {

/// The two cases of Fig. 6.
enum class contact_case : std::uint8_t {
    close_intersections,  ///< (1) a branch of P crosses a branch of Q twice, the crossings close together
    narrow_gap,           ///< (2) a branch of P passes a branch of Q at a narrow gap without crossing it
};

/// What counts as a contact to smooth. The paper gives no values; the defaults suit elements of
/// 10-50 mm drawn with strokes of about 1 mm.
struct contact_options {
    double max_intersection_gap = 2.0;  ///< case 1: largest distance between the two crossings (mm, > 0)
    double max_gap = 0.5;               ///< case 2: largest gap between the branches (mm, > 0)
    bool pin_far_end = true;            ///< also fix the vertex of P farthest from the contact point
    /// Also move the moving vertex's two branch neighbours by its displacement, so P is locally
    /// translated and keeps its tangent at the contact (not in the paper; off by default).
    bool keep_tangent = false;
};

/// The constraints that bring P into tangential contact with Q.
struct connection_plan {
    contact_case kind = contact_case::narrow_gap;
    /// [0] moves the moving vertex; then (keep_tangent) its branch neighbours by the same vector;
    /// then the fixed vertices, in increasing id.
    std::vector<point_constraint> constraints;
    vec2 contact{0.0};                          ///< where P will touch Q: the moving vertex's target (mm)
    std::uint32_t moving_vertex = 0;            ///< vertex of P that moves (= constraints[0].vertex)
    std::size_t p_branch = 0;                   ///< the branch of P, in skeleton_graph::branches() order
    std::size_t q_branch = 0;                   ///< the branch of Q, likewise
    double gap = 0.0;                           ///< case 1: distance between the two crossings; case 2: the gap (mm)
};

namespace detail::ffd {

/// A branch as positions along its walk and the vertex id of each (closed branches repeat the
/// first vertex at the end).
struct branch_path {
    std::vector<vec2> points;
    std::vector<std::uint32_t> vertices;
    bool closed = false;
    [[nodiscard]] std::size_t segments() const noexcept { return points.size() - 1; }
};

/// The branches of a skeleton (graph::skeleton_graph::branches(): runs between vertices of valence
/// != 2, then the cycles).
[[nodiscard]] inline std::vector<branch_path> branches_of(std::span<const vec2> positions, std::span<const std::array<std::uint32_t, 2>> edges) {
    graph::skeleton_graph<vec2> g;
    for (const vec2& p : positions) (void)g.add_vertex(p);
    for (const auto& [a, b] : edges) (void)g.add_edge(a, b);
    std::vector<branch_path> out;
    for (const graph::skeleton_branch& b : g.branches()) {
        branch_path p;
        p.closed = b.closed();
        for (const graph::vertex_id v : b.vertices) p.vertices.push_back(v), p.points.push_back(positions[v]);
        out.push_back(std::move(p));
    }
    return out;
}

[[nodiscard]] inline double cross(vec2 a, vec2 b) noexcept { return a.x * b.y - a.y * b.x; }

/// A point where a branch of P meets a branch of Q; `at` = segment index + parameter along P.
struct crossing {
    double at = 0.0;
    vec2 point{0.0};
};

/// Every point where branch p meets branch q, sorted along p. Segments are closed, with a
/// parameter slack of 1e-12 so that a crossing through a vertex is not lost to rounding; crossings
/// within `touch` (mm) of the previous one along p (or, on a closed branch, of the first) are one
/// point. Parallel (collinear) overlaps are not reported. O(segments(p) * segments(q)).
[[nodiscard]] inline std::vector<crossing> crossings(const branch_path& p, const branch_path& q, double touch) {
    std::vector<crossing> found;
    constexpr double slack = 1e-12;
    auto in_segment = [](double t) { return t >= -slack && t <= 1.0 + slack; };
    for (std::size_t i = 0; i < p.segments(); ++i) {
        const vec2 a = p.points[i], ab = p.points[i + 1] - a;
        for (std::size_t j = 0; j < q.segments(); ++j) {
            const vec2 c = q.points[j], cd = q.points[j + 1] - c;
            const double denom = cross(ab, cd);
            if (!(std::abs(denom) > 1e-14 * glm::length(ab) * glm::length(cd))) continue;  // parallel or degenerate
            const double t = cross(c - a, cd) / denom, u = cross(c - a, ab) / denom;
            if (in_segment(t) && in_segment(u)) found.push_back({static_cast<double>(i) + std::clamp(t, 0.0, 1.0), a + t * ab});
        }
    }
    std::stable_sort(found.begin(), found.end(), [](const crossing& x, const crossing& y) { return x.at < y.at; });
    std::vector<crossing> out;
    for (const crossing& x : found)
        if (out.empty() || glm::distance(x.point, out.back().point) > touch) out.push_back(x);
    if (p.closed && out.size() > 1 && glm::distance(out.back().point, out.front().point) <= touch) out.pop_back();
    return out;
}

/// Unit tangent of branch p at its walk position k (central difference; one-sided at open ends;
/// zero if the neighbours coincide).
[[nodiscard]] inline vec2 tangent(const branch_path& p, std::size_t k) {
    const std::size_t n = p.segments();
    const std::size_t prev = k > 0 ? k - 1 : (p.closed ? n - 1 : 0);
    const std::size_t next = k < n ? k + 1 : (p.closed ? 1 : n);
    const vec2 d = p.points[next] - p.points[prev];
    const double l = glm::length(d);
    return l > 0.0 ? d / l : vec2(0.0);
}

/// A candidate contact: the moving vertex, its target and the gap that ranks it.
struct contact_candidate {
    contact_case kind;
    std::size_t walk;  // position of the moving vertex along its branch of P
    std::uint32_t vertex;
    vec2 target;
    double gap;
    double span = 0.0;  // case 1: length of P between the two crossings (mm), breaks ties in gap
    std::size_t p_branch = 0, q_branch = 0;
};

/// Arc length along branch p from its start to walk position `at` (segment index + parameter).
[[nodiscard]] inline double arc_length(const branch_path& p, const std::vector<double>& cumulative, double at) {
    const auto seg = std::min(static_cast<std::size_t>(at), p.segments() - 1);
    return cumulative[seg] + (at - static_cast<double>(seg)) * glm::distance(p.points[seg], p.points[seg + 1]);
}

/// Case 1 on one pair of branches: over consecutive crossings x1, x2 along p (cyclically on a
/// closed branch) closer than max_gap, the non-fixed vertex of p strictly between them whose
/// tangent is most nearly parallel to the line x1 x2, moved to its projection onto that line.
/// The closest pair of crossings wins, then the shorter stretch of p between them (on a loop
/// crossed twice, both stretches join the same two crossings: the short one is the bulge).
[[nodiscard]] inline std::optional<contact_candidate> close_intersection_contact(const branch_path& p, const std::vector<crossing>& xs, double max_gap,
                                                                                 double touch, const std::vector<std::uint8_t>& fixed) {
    std::optional<contact_candidate> best;
    const std::size_t n = p.segments();
    std::vector<double> cumulative(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) cumulative[i + 1] = cumulative[i] + glm::distance(p.points[i], p.points[i + 1]);
    const std::size_t pairs = p.closed && xs.size() >= 2 ? xs.size() : (xs.size() >= 2 ? xs.size() - 1 : 0);
    for (std::size_t k = 0; k < pairs; ++k) {
        const crossing& x1 = xs[k];
        const crossing& x2 = xs[(k + 1) % xs.size()];
        const double gap = glm::distance(x1.point, x2.point);
        if (!(gap < max_gap) || gap <= touch || (best && gap > best->gap)) continue;
        double span = arc_length(p, cumulative, x2.at) - arc_length(p, cumulative, x1.at);
        if (span <= 0.0) span += cumulative[n];  // wraps on a closed branch
        if (best && gap == best->gap && !(span < best->span)) continue;
        const vec2 dir = (x2.point - x1.point) / gap;
        const double end = x2.at > x1.at ? x2.at : x2.at + static_cast<double>(n);
        std::optional<std::pair<double, std::size_t>> pick;                            // (1 - |cos|, walk position)
        for (double w = std::floor(x1.at) + 1.0; w < end; w += 1.0) {
            const auto pos = static_cast<std::size_t>(w) % n;
            if (fixed[p.vertices[pos]]) continue;
            const vec2 t = tangent(p, pos);
            if (t == vec2(0.0)) continue;
            const double misalign = 1.0 - std::abs(glm::dot(t, dir));
            if (!pick || misalign < pick->first) pick = std::pair{misalign, pos};
        }
        if (!pick) continue;
        const vec2 v = p.points[pick->second];
        best = contact_candidate{contact_case::close_intersections, pick->second, p.vertices[pick->second],
                                 x1.point + glm::dot(v - x1.point, dir) * dir, gap, span};
    }
    return best;
}

/// Case 2 on one pair of branches that do not meet: the non-fixed vertex of p nearest to q and
/// its closest point on q, if nearer than max_gap and farther than `touch` (already in contact).
[[nodiscard]] inline std::optional<contact_candidate> narrow_gap_contact(const branch_path& p, const branch_path& q, double max_gap,
                                                                         double touch, const std::vector<std::uint8_t>& fixed) {
    std::optional<contact_candidate> best;
    for (std::size_t k = 0; k < p.points.size(); ++k) {
        if (fixed[p.vertices[k]]) continue;
        const vec2 v = p.points[k];
        for (std::size_t j = 0; j < q.segments(); ++j) {
            const double gap = segment_distance(v, q.points[j], q.points[j + 1]);
            if (!(gap < max_gap) || gap <= touch || (best && !(gap < best->gap))) continue;
            const double t = segment_closest_parameter(v, q.points[j], q.points[j + 1]);
            best = contact_candidate{contact_case::narrow_gap, k, p.vertices[k], q.points[j] + t * (q.points[j + 1] - q.points[j]), gap};
        }
    }
    return best;
}

inline void check_contact_input(std::span<const vec2> p_positions, std::span<const std::array<std::uint32_t, 2>> p_edges,
                                std::span<const vec2> q_positions, std::span<const std::array<std::uint32_t, 2>> q_edges,
                                std::span<const std::uint32_t> fixed_vertices, const contact_options& opt) {
    constexpr const char* fn = "plan_tangent_contact";
    check_points(fn, "p_positions", p_positions);
    check_points(fn, "q_positions", q_positions);
    check_edges(fn, "p_edges", p_edges, p_positions.size());
    check_edges(fn, "q_edges", q_edges, q_positions.size());
    for (std::size_t i = 0; i < fixed_vertices.size(); ++i)
        if (fixed_vertices[i] >= p_positions.size())
            throw invalid_input(std::string(fn) + ": " + index_name("fixed_vertices", i) + " = " + std::to_string(fixed_vertices[i]) +
                                " is out of range for " + std::to_string(p_positions.size()) + " vertices of P");
    require_positive(opt.max_intersection_gap, "plan_tangent_contact: max_intersection_gap");
    require_positive(opt.max_gap, "plan_tangent_contact: max_gap");
}

/// The best contact over all branch pairs: case 1 before case 2 (an existing double crossing is
/// a connection to smooth), then the smaller gap, then the earlier (P branch, Q branch) pair.
[[nodiscard]] inline std::optional<contact_candidate> best_contact(const std::vector<branch_path>& pb, const std::vector<branch_path>& qb,
                                                                   const contact_options& opt, double touch, const std::vector<std::uint8_t>& fixed) {
    std::optional<contact_candidate> best;
    auto better = [&](const contact_candidate& c) {
        if (!best) return true;
        if (c.kind != best->kind) return c.kind == contact_case::close_intersections;
        return c.gap < best->gap || (c.gap == best->gap && c.span < best->span);
    };
    for (std::size_t i = 0; i < pb.size(); ++i)
        for (std::size_t j = 0; j < qb.size(); ++j) {
            const std::vector<crossing> xs = crossings(pb[i], qb[j], touch);
            auto c = xs.empty() ? narrow_gap_contact(pb[i], qb[j], opt.max_gap, touch, fixed)
                                : close_intersection_contact(pb[i], xs, opt.max_intersection_gap, touch, fixed);
            if (!c) continue;
            c->p_branch = i, c->q_branch = j;
            if (better(*c)) best = c;
        }
    return best;
}

/// The distance below which two points of P and Q touch (mm): 1e-9 of their largest coordinate
/// (plus 1e-9 mm), so rounding never turns a touching pair into a gap or two crossings.
[[nodiscard]] inline double touch_tolerance(std::span<const vec2> p_positions, std::span<const vec2> q_positions) {
    box2 b;
    for (const vec2& v : p_positions) b.extend(v);
    for (const vec2& v : q_positions) b.extend(v);
    return 1e-9 * (1.0 + std::max({std::abs(b.lo.x), std::abs(b.lo.y), std::abs(b.hi.x), std::abs(b.hi.y)}));
}

/// The plan: the moving constraint, (keep_tangent) its branch neighbours moved alike, then the
/// fixed vertices (the caller's, plus the far end).
[[nodiscard]] inline connection_plan make_plan(const contact_candidate& c, const branch_path& branch, std::span<const vec2> p_positions,
                                               std::vector<std::uint8_t> fixed, const contact_options& opt) {
    connection_plan plan;
    plan.kind = c.kind;
    plan.contact = c.target;
    plan.moving_vertex = c.vertex;
    plan.p_branch = c.p_branch, plan.q_branch = c.q_branch;
    plan.gap = c.gap;
    plan.constraints.push_back({c.vertex, c.target});
    std::vector<std::uint8_t> moving(p_positions.size(), 0);
    moving[c.vertex] = 1;
    if (opt.keep_tangent) {
        const std::size_t n = branch.segments();
        const std::size_t walks[] = {c.walk > 0 ? c.walk - 1 : (branch.closed ? n - 1 : c.walk), c.walk < n ? c.walk + 1 : (branch.closed ? 1 : c.walk)};
        for (const std::size_t w : walks) {
            const std::uint32_t v = branch.vertices[w];
            if (moving[v] || fixed[v]) continue;
            moving[v] = 1;
            plan.constraints.push_back({v, p_positions[v] + (c.target - p_positions[c.vertex])});
        }
    }
    if (opt.pin_far_end) {
        // The vertex of P farthest from the contact anchors the rest of the element, which would
        // otherwise translate as a whole (a translation costs nothing in eq. 14).
        std::size_t far = 0;
        for (std::size_t v = 1; v < p_positions.size(); ++v)
            if (glm::distance(p_positions[v], c.target) > glm::distance(p_positions[far], c.target)) far = v;
        if (!moving[far]) fixed[far] = 1;
    }
    for (std::size_t v = 0; v < fixed.size(); ++v)
        if (fixed[v]) plan.constraints.push_back({static_cast<std::uint32_t>(v), p_positions[v]});
    return plan;
}

}  // namespace detail::ffd

/// Plans the deformation of element P that brings it into tangential contact with its neighbour
/// Q (§4.3.2, Fig. 6). Branches are those of graph::skeleton_graph::branches().
///  - Case 1: a branch of P crosses a branch of Q at two points x1, x2, consecutive along P's
///    branch and closer than opt.max_intersection_gap. The moving vertex is the vertex of P
///    strictly between x1 and x2 along the branch (on a loop crossed twice: along the shorter
///    stretch) whose tangent is closest to the direction of the line x1 x2; its target is its
///    projection onto that line (the paper's rule). P then
///    touches the chord x1 x2, which lies off Q by Q's sagitta over it: that remaining sliver is
///    a case-2 gap, which a second call closes.
///  - Case 2: a branch of P does not meet a branch of Q, but one of its vertices is within
///    opt.max_gap of it. The moving vertex is the P vertex nearest to Q; its target is its
///    closest point on Q.
/// Case 1 is preferred to case 2, then the smaller gap. Points of P and Q closer than
/// 1e-9 * (1 + largest |coordinate|) mm touch: they are one crossing, not a gap. With
/// opt.keep_tangent the moving vertex's branch neighbours (unless fixed) get the same
/// displacement. Fixed points (targets = own positions): every vertex
/// of `fixed_vertices` (P's intersections with its other neighbours, which must not move), plus,
/// if opt.pin_far_end, the vertex of P farthest from the contact point (lowest id on ties).
/// Fixed vertices are never chosen to move.
/// @param p_positions, p_edges  skeleton of P (mm; index pairs, in range, no self loops)
/// @param q_positions, q_edges  skeleton of Q (mm), which does not move
/// @param fixed_vertices        vertices of P to keep still (in range; repeats allowed)
/// @param opt                   contact thresholds (mm)
/// @return the plan, or nullopt if no branch pair is in either case. Throws invalid_input for bad
///         input. O(segments(P) * segments(Q)).
[[nodiscard]] inline std::optional<connection_plan> plan_tangent_contact(std::span<const vec2> p_positions,
                                                                         std::span<const std::array<std::uint32_t, 2>> p_edges,
                                                                         std::span<const vec2> q_positions,
                                                                         std::span<const std::array<std::uint32_t, 2>> q_edges,
                                                                         std::span<const std::uint32_t> fixed_vertices,
                                                                         const contact_options& opt = {}) {
    namespace d = detail::ffd;
    d::check_contact_input(p_positions, p_edges, q_positions, q_edges, fixed_vertices, opt);
    std::vector<std::uint8_t> fixed(p_positions.size(), 0);
    for (const std::uint32_t v : fixed_vertices) fixed[v] = 1;
    const std::vector<d::branch_path> p_branches = d::branches_of(p_positions, p_edges);
    const double touch = d::touch_tolerance(p_positions, q_positions);
    const auto contact = d::best_contact(p_branches, d::branches_of(q_positions, q_edges), opt, touch, fixed);
    if (!contact) return std::nullopt;
    return d::make_plan(*contact, p_branches[contact->p_branch], p_positions, std::move(fixed), opt);
}

/// SMOOTHCONNECTION of Algorithm 1 (§4.3.2): plan_tangent_contact, then ffd_deform of P with the
/// plan's constraints; the result only if its distortion is below sigma_d (dimensionless, > 0;
/// Table 1: 0.13-0.17). nullopt if there is no contact to smooth or the deformation is rejected.
/// Throws as plan_tangent_contact and ffd_deform do (e.g. solver_error for more than 15 fixed
/// vertices).
[[nodiscard]] inline std::optional<ffd_result> smooth_connection(std::span<const vec2> p_positions,
                                                                 std::span<const std::array<std::uint32_t, 2>> p_edges,
                                                                 std::span<const vec2> q_positions,
                                                                 std::span<const std::array<std::uint32_t, 2>> q_edges,
                                                                 std::span<const std::uint32_t> fixed_vertices, const contact_options& opt = {},
                                                                 const ffd_weights& w = {}, double sigma_d = default_sigma_d) {
    require_positive(sigma_d, "smooth_connection: sigma_d");
    const std::optional<connection_plan> plan = plan_tangent_contact(p_positions, p_edges, q_positions, q_edges, fixed_vertices, opt);
    if (!plan) return std::nullopt;
    ffd_result r = ffd_deform(p_positions, p_edges, plan->constraints, w);
    if (!(r.distortion < sigma_d)) return std::nullopt;
    return r;
}

}  // namespace fabsynth::filigree
