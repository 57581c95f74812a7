// SPDX-License-Identifier: MIT
#pragma once
/// @file beam_model.hpp  The simplified beam-wedge model of structurally-sound-patterns.md §5.2.1
/// ("Score Based on Force Profile", Figure 8): every abstract-graph vertex becomes a fan of wedge
/// elements in its tangent plane, every abstract edge a hexahedral beam joining the wedge fans of
/// its two endpoints; empty edges are softened to rho_min; the score of an edge is
/// |s1| + |s2| + |s3| of its beam's stress. Solves go through fem::solve_context, so changing
/// edge states only rescales element matrices and reuses the one symbolic analysis.
///
/// Input is plain data (no dependency on the synthesizer): vertices (position [mm], outward
/// normal) and edges (a, b, solid). Usage:
///   std::vector<fabsynth::surface_pattern::beam_vertex> v = ...;  // abstract vertices: shell voxel centres
///   std::vector<fabsynth::surface_pattern::beam_edge> e = ...;    // abstract edges with rho(e) = solid
///   fabsynth::surface_pattern::beam_model model(v, e, {.thickness_mm = 1.5});
///   std::vector<double> score = model.solve();                   // MPa per edge
///   model.set_edge_solid(k, true);                               // rho of one beam: 1
///   score = model.solve();                                       // no new analysis
///
/// Geometry (all decisions of this file; the paper gives none of these details):
/// - Frame: the abstract vertex p lies on the outer surface; the model is extruded inward, from p
///   to p - thickness n (as the printed shell, fabricate.hpp's thicken_inward). Every vertex has
///   a right-handed tangent frame (t1, t2, n).
/// - Beam width w: beam_options::beam_width_mm, or by default 0.2 x the median edge length,
///   capped at 0.6 x the shortest edge (so no hub must exceed its edges). Every beam has the
///   cross-section w x thickness.
/// - Directions: each neighbour (other endpoint of an incident edge) is projected into the tangent
///   plane and sorted by angle. A neighbour along the normal (projection < 1e-9 of its distance)
///   gets the middle of the largest angular gap of the others.
/// - Hub radius r: each incident edge owns one polygon side, a chord of width w perpendicular to
///   its direction at distance r from p, subtending 2 beta, beta = atan(w / 2r). r is chosen so
///   that sides take at most q = 75% of the smallest angular gap g between directions and
///   beta <= 45 deg: r = (w/2) / tan(min(q g / 2, 45 deg)) >= w/2. r is capped at 0.35 x the
///   shortest incident edge (so every beam keeps >= 30% of its edge length). When the cap binds,
///   the directions are spread apart to the separation s = 2 beta(r_cap) / q by the least-squares
///   closest angles with those gaps (isotonic regression, pool-adjacent-violators, cut at the
///   largest gap); if that does not close around the circle, or k s > 2 pi, the directions become
///   evenly spaced (phase = circular mean of the sorted angles), with r = (w/2) / tan(q pi / k) in
///   the second case; if that r exceeds 0.45 x the shortest incident edge (too many neighbours for
///   the beam width), r becomes 0.45 x that edge and this hub's sides are narrowed to fit (half-
///   width r tan(q pi / k)): its beams taper towards it (statistics().narrowed_hubs counts them).
///   A beam whose side is rotated by the spreading is simply skewed.
/// - Polygon: corners L_j = p + r d_j - (w/2) n x d_j and R_j = p + r d_j + (w/2) n x d_j for each
///   direction d_j, and in each gap between sides extra corners on the same circle (radius
///   sqrt(r^2 + w^2/4)), evenly spaced so that no step exceeds 60 deg. A vertex with no edge gets a
///   regular hexagon of circumradius w/2; one edge gives one side plus ~5 gap corners. The polygon
///   is fan-triangulated from p, every triangle extruded by the thickness along -n: one wedge6 per
///   polygon step (bottom = inner face, counter-clockwise about n), all with positive Jacobians.
/// - Beams: the hex8 of edge (a, b) shares the four nodes (outer and inner L, R) of a's side for
///   it and the four of b's side, in the order (L_a, R_b, L_b, R_a) about n; if its Jacobian is
///   negative at all corners the faces are swapped; if no order of b's four nodes gives a valid hex
///   (the frames fold between a and b: an edge across a thin part joins voxels of opposite
///   normals, or runs along a normal), the edge is split at a knot: an extra hub at the chord
///   midpoint whose normal is perpendicular to the chord, joined to a and b by one hex each (each
///   half bends by at most ~90 degrees), or at the edge's own knot point (beam_edge::knot). If a
///   half still folds, the hubs of both ends are extruded by half as much (twice, down to 1/4 of
///   the thickness): in a part thinner than twice the thickness the inner faces of the hubs on
///   its two sides overlap, and no element can join them. Such thin hubs make the model locally
///   weaker (conservative). Knots carry no load; a split edge scores its more stressed half. An
///   edge that still folds is left out of the FEM as a last resort (statistics().unmodelled_edges:
///   a few in a thousand on the bunny, at its thinnest parts) and scores the largest score of the
///   modelled edges at its ends. A part that only unmodelled edges join to the rest is fixed
///   where it stands (statistics().cut_off_vertices).
/// - Stiffness: wedges rho = 1, solid beams 1, empty beams rho_min (the paper's K_e = rho(e) K_e).
/// - Supports: every node whose height along -gravity lies in the lowest support_fraction of the
///   nodes' extent (ties within 1e-9 of it included) is fixed in x, y, z. A force_profile may
///   instead list fixed vertices (all nodes of their hubs fixed). Each connected part of the graph
///   (empty edges count: rho_min keeps parts attached) needs a fixed node, else no_solution names
///   its vertices; a part held at a single node or line throws solver_error from the FEM support
///   check (rigid-body mode), also at construction.
/// - Loads: load_per_vertex_n [N] along gravity at every vertex ("arbitrary but constant"), or the
///   force_profile's vector loads [N], spread over the vertex's hub nodes by lumped wedge volume
///   (each wedge gives 1/6 of its volume to each node), so the resultant acts at the hub centroid.
/// - Score: |s1| + |s2| + |s3| [MPa = N/mm^2] of the beam's stress, by default averaged over its
///   eight Gauss points (the centroid alone would miss bending: bending stress vanishes on the beam
///   axis). As in the paper (sigma_e = B E u_e), the stress is C eps without rho, i.e. what the
///   edge would carry if it were solid under the current deformation; carried_stress = true gives
///   rho C eps instead. Solid and empty edges are scored alike.
/// - rho_min = 1e-4: the paper gives no value. An empty beam must carry a negligible share, and
///   not only axially: next to a solid beam of width w it forms a couple over the lever d whose
///   stiffness relative to the solid beam's bending is ~12 rho (d / w)^2, ~0.3 at rho = 1e-3 and
///   d / w = 5 (a ladder panel then still sends 7% of its load through the "empty" side; the test
///   measures it), ~0.03 at 1e-4. Smaller values only worsen the conditioning (contrast 1 / rho for
///   LDL^T and CG) while rho_min > 0 keeps solid parts that no solid edge joins yet attached, so
///   the loop can score the empty edges between them.
/// - Accuracy: each beam is one hex8 (full integration) and each hub one wedge layer, so a beam
///   carries axial load exactly (tested against statics) but its bending is stiffened by shear
///   locking, and a beam next to a fixed hub also feels that hub's clamped Poisson contraction.
///   The scores rank edges; they are not a converged stress analysis of the printed pattern.
///   Checked once by hand against CalculiX (ccx on fem::write_inp(mesh(), load_case()) of the
///   ladder test with one empty beam): displacements agree to 0.8% of the largest (not a test).
/// Cost: O(V + E) elements (about 2k wedges per vertex of degree k, one hex per edge), 3 DOFs per
/// node; the solve is fem::solve_context's with default_beam_solver() (direct, refactorized).
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/fem/boundary.hpp"
#include "fabsynth/fem/material.hpp"
#include "fabsynth/fem/mesh.hpp"
#include "fabsynth/fem/solve_context.hpp"
#include "fabsynth/fem/stress.hpp"

namespace fabsynth::surface_pattern {

/// An abstract vertex: position [mm] (a shell voxel centre, on the outer surface) and its
/// outward normal (normalized here; must be finite and non-zero).
struct beam_vertex {
    vec3 position{0.0};
    vec3 normal{0.0, 0.0, 1.0};
};
/// An abstract edge between vertices a and b; solid: rho = 1, else rho_min. `knot`: where the
/// edge is split if no single hex can join its ends (see the file comment), e.g. the middle of the
/// voxel path it stands for; empty = the chord midpoint.
struct beam_edge {
    std::uint32_t a = 0, b = 0;
    bool solid = true;
    std::optional<beam_vertex> knot{};
};

/// Where the beam stress of an edge is sampled for its score.
enum class beam_stress_sample : std::uint8_t {
    gauss_mean,  ///< mean of |s1|+|s2|+|s3| over the 8 Gauss points (default; sees bending)
    gauss_max,   ///< maximum over the 8 Gauss points
    centre,      ///< at the beam centroid (axial stress and shear only; bending is zero there)
};

/// The solver a beam model uses unless told otherwise: a direct factorization (CHOLMOD when the
/// build has it, else LDL^T), refactorized numerically after state changes (reuse_preconditioner
/// off). The model is a single layer of elements, so its factor has 2D-like fill: on the
/// 1000-vertex sphere (72k free DOFs) CHOLMOD factorizes in ~0.6 s, while AMG-CG (what
/// solver_method::automatic picks for solid meshes above 20000 DOFs) needs ~160 iterations and
/// ~2.5 s, and CG on the previous factor needs ~20 iterations even for one changed edge, which
/// costs as much as refactorizing. The symbolic analysis is never repeated either way.
[[nodiscard]] inline fem::solve_options default_beam_solver() {
    fem::solve_options o;
    o.method = fem::method_available(fem::solver_method::cholmod) ? fem::solver_method::cholmod : fem::solver_method::ldlt;
    o.reuse_preconditioner = false;
    // Empty beams at rho_min next to solid ones and the short, narrowed beams of crowded hubs make
    // the system ill-conditioned (a direct solve leaves |K u - f| / |f| ~ 1e-5 on the bunny); the
    // scores only rank edges, so a residual of 1e-3 is accepted.
    o.residual_tolerance = 1e-3;
    return o;
}

struct beam_options {
    double thickness_mm = 1.0;   ///< shell thickness: extrusion along -normal (inward) [mm], > 0
    double beam_width_mm = 0;    ///< in-plane width of the beams [mm]; 0 = 0.2 x median edge length, <= 0.6 x shortest
    double rho_min = 1e-4;       ///< stiffness scale of empty edges, in (0, 1] (the paper gives none; see the file comment)
    fem::isotropic_material material = fem::isotropic_material::abs();
    vec3 gravity{0.0, 0.0, -1.0};   ///< load direction of the default force profile (normalized), non-zero
    double support_fraction = 0.10; ///< nodes in this lowest fraction of the extent along gravity are fixed, in [0, 1]
    double load_per_vertex_n = 1.0; ///< force per abstract vertex [N] ("arbitrary but constant", §5.2.1)
    beam_stress_sample sample = beam_stress_sample::gauss_mean;
    bool carried_stress = false;    ///< false: C eps (paper); true: rho C eps, the stress the beam really carries
    fem::solve_options solver = default_beam_solver();  ///< passed to fem::solve_context (method, reuse, tolerances)
};

/// A user force profile (e.g. a pinch grip, Stava et al. 2012): fixed_vertices have every node of
/// their hub fixed in x, y, z (empty = the default supports of beam_options); loads are forces [N]
/// on vertices, spread over their hubs like the gravity loads (empty = the default gravity loads).
struct force_profile {
    std::vector<std::uint32_t> fixed_vertices;
    std::vector<std::pair<std::uint32_t, vec3>> loads;
};

/// Sizes and work of a beam_model (times: wall clock seconds).
struct beam_statistics {
    std::size_t vertices = 0, edges = 0;
    std::size_t nodes = 0, wedges = 0, hexes = 0, dofs = 0, free_dofs = 0, fixed_nodes = 0;
    std::size_t knots = 0;  ///< folded edges split at a knot (two hexes each)
    std::size_t narrowed_hubs = 0;  ///< hubs whose sides are narrower than the beam width (too many neighbours)
    std::size_t thinned_hubs = 0;   ///< vertices extruded by less than the thickness (ends of folded edges)
    std::size_t unmodelled_edges = 0;  ///< edges no element could represent (left out, scored by their neighbours)
    std::size_t cut_off_vertices = 0;  ///< vertices of parts joined only by unmodelled edges, fixed where they stand
    double beam_width_mm = 0;
    std::string method;  ///< solver method of the context (ldlt, amg, ...)
    int analyses = 0, factorizations = 0, solves = 0, reused_solves = 0;
    double build_seconds = 0;       ///< constructor: geometry, checks, assembly and analysis
    double last_solve_seconds = 0;  ///< last solve(): FEM solve and stress scores
    double total_solve_seconds = 0;
};

namespace detail {

/// det J of element E at its nodes, centroid and quadrature points: (min, max).
template <class E>
[[nodiscard]] std::pair<double, double> jacobian_range(const typename E::nodes_t& X) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    auto at = [&](const vec3& xi) {
        const auto d = E::shape_derivatives(xi);
        Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
        for (int a = 0; a < E::num_nodes; ++a)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) J(i, j) += d(i, a) * X[static_cast<std::size_t>(a)][j];
        const double det = J.determinant();
        lo = std::min(lo, det), hi = std::max(hi, det);
    };
    for (int a = 0; a < E::num_nodes; ++a) at(fem::node_natural_coordinates<E>(a));
    at(E::centroid());
    for (const auto& g : E::quadrature()) at(g.xi);  // the assembly checks these
    return {lo, hi};
}

/// Least-squares angles y (y[i+1] - y[i] >= s) closest to sorted x: isotonic regression of
/// x[i] - i s by pool-adjacent-violators, then y[i] = z[i] + i s.
[[nodiscard]] inline std::vector<double> spread_angles(const std::vector<double>& x, double s) {
    struct block {
        double sum;
        std::size_t count;
    };
    std::vector<block> blocks;
    for (std::size_t i = 0; i < x.size(); ++i) {
        blocks.push_back({x[i] - static_cast<double>(i) * s, 1});
        while (blocks.size() > 1) {
            const block& b = blocks.back();
            const block& a = blocks[blocks.size() - 2];
            if (a.sum / static_cast<double>(a.count) <= b.sum / static_cast<double>(b.count)) break;
            const block m{a.sum + b.sum, a.count + b.count};
            blocks.pop_back();
            blocks.back() = m;
        }
    }
    std::vector<double> y;
    for (const block& b : blocks)
        for (std::size_t c = 0; c < b.count; ++c) y.push_back(b.sum / static_cast<double>(b.count) + static_cast<double>(y.size()) * s);
    return y;
}

}  // namespace detail

class beam_model {
public:
    /// Builds the model and analyses it once (fem::solve_context). Throws invalid_input for bad
    /// input (edge index out of range, a == b, duplicate edge, coincident endpoints, non-finite
    /// positions, zero normal, bad options, knots or force profile, beams folded even through a
    /// knot), no_solution for a part of the graph without supports, solver_error
    /// for a part the supports cannot hold.
    beam_model(std::span<const beam_vertex> vertices, std::span<const beam_edge> edges, const beam_options& opt = {},
               const std::optional<force_profile>& profile = std::nullopt)
        : opt_(opt), vertices_(vertices.begin(), vertices.end()), edges_(edges.begin(), edges.end()) {
        const auto t0 = clock::now();
        validate_input(profile);
        choose_width();
        user_vertices_ = vertices_.size();
        // Folded edges: first split at a knot, then halve the extrusion at both ends (thin parts).
        std::vector<std::uint8_t> split(edges_.size(), 0);
        std::vector<double> thinning(user_vertices_, 1.0);
        for (int attempt = 0;; ++attempt) {
            make_segments(split, thinning);
            build_hubs();
            const std::vector<std::size_t> folded = build_beams();
            if (folded.empty()) break;
            if (attempt == 12 + max_thinning) throw_folded(folded.front());
            for (const std::size_t seg : folded) {
                const std::uint32_t e = segments_[seg].edge;
                if (attempt >= 1 + max_thinning) {
                    split[e] = 2;  // last resort: left out of the FEM (scored by its neighbours)
                    continue;
                }
                if (!split[e]) {
                    split[e] = 1;
                    continue;
                }
                for (const std::uint32_t v : {edges_[e].a, edges_[e].b})
                    if (thinning[v] > std::ldexp(1.0, -max_thinning) * 1.5) thinning[v] *= 0.5;
            }
            mesh_ = {};
            narrowed_hubs_ = 0;
            vertices_.resize(user_vertices_);
        }
        for (std::size_t e = 0; e < edges_.size(); ++e) unmodelled_ += modelled(e) ? 0 : 1;
        mesh_.sections.push_back({opt_.material, 0.0});
        build_supports_and_loads(profile);
        try {
            ctx_ = std::make_unique<fem::solve_context>(std::move(mesh_), supports_, opt_.solver);  // mesh_ is spent
        } catch (const solver_error& e) {
            throw solver_error(std::string("beam_model: the supports cannot hold the beam model: ") + e.what());
        }
        stats_.build_seconds = seconds_since(t0);
    }

    [[nodiscard]] std::size_t num_vertices() const noexcept { return user_vertices_; }
    [[nodiscard]] std::size_t num_edges() const noexcept { return edges_.size(); }
    [[nodiscard]] bool edge_solid(std::size_t edge) const { return edges_.at(edge).solid; }
    [[nodiscard]] double beam_width() const noexcept { return width_; }
    /// Hub radius r of vertex i (distance from p to each side) [mm].
    [[nodiscard]] double hub_radius(std::size_t i) const { return hub_radius_.at(i); }
    /// Index in mesh() of the (first) hex8 beam of an edge; a folded edge has two (edge_elements).
    /// Throws invalid_input for an unmodelled edge (statistics().unmodelled_edges).
    [[nodiscard]] std::size_t edge_element(std::size_t edge) const {
        check_edge(edge, "edge_element");
        if (!modelled(edge)) throw invalid_input("beam_model::edge_element: edge " + std::to_string(edge) + " has no element (unmodelled)");
        return first_hex_ + edge_segment_begin_[edge];
    }
    /// Indices in mesh() of all hex8 beams of an edge [first, last): one, or two through a knot.
    [[nodiscard]] std::pair<std::size_t, std::size_t> edge_elements(std::size_t edge) const {
        check_edge(edge, "edge_elements");
        return {first_hex_ + edge_segment_begin_[edge], first_hex_ + edge_segment_begin_[edge + 1]};
    }
    /// Whether an edge was split at a knot because no single hex joins its ends (see the file comment).
    [[nodiscard]] bool edge_split(std::size_t edge) const {
        check_edge(edge, "edge_split");
        return edge_segment_begin_[edge + 1] - edge_segment_begin_[edge] > 1;
    }
    /// Node indices [first, last) in mesh() of vertex i's hub (centre outer, centre inner, then
    /// each polygon corner outer, inner).
    [[nodiscard]] std::pair<std::uint32_t, std::uint32_t> vertex_nodes(std::size_t i) const {
        return {hub_begin_.at(i), hub_begin_.at(i + 1)};
    }
    /// The FEM model with the current stiffness scales (for VTK output or a CalculiX deck).
    [[nodiscard]] const fem::mesh& mesh() const noexcept { return ctx_->model(); }
    /// The fixed DOFs and the nodal forces of the force profile.
    [[nodiscard]] const fem::load_case& supports() const noexcept { return supports_; }
    [[nodiscard]] const fem::load_case& loads() const noexcept { return loads_; }
    /// Supports and loads in one case (e.g. for fem::write_inp).
    [[nodiscard]] fem::load_case load_case() const {
        fem::load_case lc = loads_;
        lc.fixed = supports_.fixed;
        return lc;
    }
    [[nodiscard]] const fem::solve_context& context() const noexcept { return *ctx_; }
    /// Result of the last solve() (displacements, reactions); empty before the first.
    [[nodiscard]] const fem::static_result& last_result() const noexcept { return last_; }

    /// Marks an edge solid (rho = 1) or empty (rho_min): changes its beam's stiffness scale only.
    void set_edge_solid(std::size_t edge, bool solid) { set_edges_solid(std::span<const std::size_t>(&edge, 1), solid); }
    /// Same for several edges at once (one pass over the stored matrix).
    void set_edges_solid(std::span<const std::size_t> edge_list, bool solid) {
        std::vector<std::size_t> elements;
        std::vector<double> scales;
        for (std::size_t e : edge_list) {
            check_edge(e, "set_edge_solid");
            if (edges_[e].solid == solid) continue;
            edges_[e].solid = solid;
            for (std::uint32_t s = edge_segment_begin_[e]; s < edge_segment_begin_[e + 1]; ++s) {
                elements.push_back(first_hex_ + s);
                scales.push_back(solid ? 1.0 : opt_.rho_min);
            }
        }
        ctx_->set_stiffness_scales(elements, scales);
    }

    /// Solves for the current edge states and returns the score |s1| + |s2| + |s3| [MPa] of every
    /// edge (edge order). Reuses the context's analysis (and its factorization where CG on it
    /// converges fast). Throws solver_error on numerical failure.
    std::vector<double> solve() {
        const auto t0 = clock::now();
        last_ = ctx_->solve(loads_);
        const fem::mesh& m = ctx_->model();
        const fem::stress_options so{.apply_stiffness_scale = opt_.carried_stress};
        std::vector<double> score(edges_.size());
        parallel_for(0, edges_.size(), [&](std::size_t e) {
            double best = 0;  // a split edge scores its more stressed half
            for (std::uint32_t seg = edge_segment_begin_[e]; seg < edge_segment_begin_[e + 1]; ++seg) {
                const std::size_t el = first_hex_ + seg;
                if (opt_.sample == beam_stress_sample::centre) {
                    best = std::max(best, fem::principal_stress_score(fem::element_stress(m, last_, el, fem::hex8::centroid(), so)));
                    continue;
                }
                double sum = 0, mx = 0;
                for (const vec3& xi : fem::hex8::stress_points()) {
                    const double s = fem::principal_stress_score(fem::element_stress(m, last_, el, xi, so));
                    sum += s, mx = std::max(mx, s);
                }
                best = std::max(best, opt_.sample == beam_stress_sample::gauss_max ? mx
                                                                                  : sum / static_cast<double>(fem::hex8::stress_points().size()));
            }
            score[e] = best;
        }, {.grain = 64});
        // unmodelled edges: the largest score of the modelled edges at either end
        if (unmodelled_ > 0) {
            std::vector<double> at(user_vertices_, 0.0);
            for (std::size_t e = 0; e < edges_.size(); ++e)
                if (modelled(e)) at[edges_[e].a] = std::max(at[edges_[e].a], score[e]), at[edges_[e].b] = std::max(at[edges_[e].b], score[e]);
            for (std::size_t e = 0; e < edges_.size(); ++e)
                if (!modelled(e)) score[e] = std::max(at[edges_[e].a], at[edges_[e].b]);
        }
        stats_.last_solve_seconds = seconds_since(t0);
        stats_.total_solve_seconds += stats_.last_solve_seconds;
        return score;
    }

    [[nodiscard]] beam_statistics statistics() const {
        beam_statistics s = stats_;
        const fem::solve_statistics& c = ctx_->statistics();
        s.vertices = user_vertices_, s.edges = edges_.size();
        s.knots = vertices_.size() - user_vertices_;
        s.narrowed_hubs = narrowed_hubs_;
        s.unmodelled_edges = unmodelled_;
        s.cut_off_vertices = cut_off_fixed_;
        for (std::size_t v = 0; v < user_vertices_; ++v) s.thinned_hubs += vertex_thickness_[v] < opt_.thickness_mm;
        s.nodes = ctx_->model().nodes.size(), s.hexes = segments_.size(), s.wedges = first_hex_;
        s.dofs = ctx_->dofs().total, s.free_dofs = c.free_dofs;
        s.fixed_nodes = c.fixed_dofs / 3;
        s.beam_width_mm = width_;
        s.method = c.method;
        s.analyses = c.analyses, s.factorizations = c.factorizations, s.solves = c.solves, s.reused_solves = c.reused_solves;
        return s;
    }

private:
    using clock = std::chrono::steady_clock;
    static double seconds_since(clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); }

    /// Per incident edge of a vertex: outer L, outer R, inner L, inner R node of its side.
    using side_nodes = std::array<std::uint32_t, 4>;

    void check_edge(std::size_t e, const char* what) const {
        if (e >= edges_.size())
            throw invalid_input(std::string("beam_model::") + what + ": edge index " + std::to_string(e) + " is out of range (" +
                                std::to_string(edges_.size()) + " edges)");
    }

    static std::string vstr(const vec3& v) {
        std::string s = "(";  // appended piecewise: GCC 12 warns (-Wrestrict) on "(" + to_string(...)
        s.append(std::to_string(v.x)).append(", ").append(std::to_string(v.y)).append(", ").append(std::to_string(v.z)).append(")");
        return s;
    }

    void validate_input(const std::optional<force_profile>& profile) {
        const auto finite_positive = [](double v) { return std::isfinite(v) && v > 0; };
        if (!finite_positive(opt_.thickness_mm))
            throw invalid_input("beam_model: thickness_mm must be finite and > 0, got " + std::to_string(opt_.thickness_mm));
        if (!(std::isfinite(opt_.beam_width_mm) && opt_.beam_width_mm >= 0))
            throw invalid_input("beam_model: beam_width_mm must be finite and >= 0 (0 = default), got " + std::to_string(opt_.beam_width_mm));
        if (!(finite_positive(opt_.rho_min) && opt_.rho_min <= 1))
            throw invalid_input("beam_model: rho_min must lie in (0, 1], got " + std::to_string(opt_.rho_min));
        opt_.material.validate();
        if (!all_finite(opt_.gravity) || !(glm::length(opt_.gravity) > 0))
            throw invalid_input("beam_model: gravity must be a finite non-zero direction, got " + vstr(opt_.gravity));
        if (!(std::isfinite(opt_.support_fraction) && opt_.support_fraction >= 0 && opt_.support_fraction <= 1))
            throw invalid_input("beam_model: support_fraction must lie in [0, 1], got " + std::to_string(opt_.support_fraction));
        if (!std::isfinite(opt_.load_per_vertex_n))
            throw invalid_input("beam_model: load_per_vertex_n must be finite, got " + std::to_string(opt_.load_per_vertex_n));
        if (vertices_.size() >= (std::size_t{1} << 26)) throw invalid_input("beam_model: too many vertices");
        if (edges_.size() >= (std::size_t{1} << 28)) throw invalid_input("beam_model: too many edges");
        for (std::size_t i = 0; i < vertices_.size(); ++i) {
            beam_vertex& v = vertices_[i];
            if (!all_finite(v.position)) throw invalid_input("beam_model: vertex " + std::to_string(i) + " has a non-finite position");
            const double len = all_finite(v.normal) ? glm::length(v.normal) : 0.0;
            if (!(len > 1e-12 && std::isfinite(len)))
                throw invalid_input("beam_model: vertex " + std::to_string(i) + " has a zero or non-finite normal " + vstr(v.normal));
            v.normal /= len;
        }
        std::vector<std::pair<std::uint64_t, std::size_t>> keys;
        keys.reserve(edges_.size());
        for (std::size_t e = 0; e < edges_.size(); ++e) {
            const beam_edge& E = edges_[e];
            const std::string name = "beam_model: edge " + std::to_string(e) + " (" + std::to_string(E.a) + ", " + std::to_string(E.b) + ")";
            if (E.a >= vertices_.size() || E.b >= vertices_.size())
                throw invalid_input(name + " references a vertex out of range (" + std::to_string(vertices_.size()) + " vertices)");
            if (E.a == E.b) throw invalid_input(name + " joins a vertex to itself");
            const vec3 d = vertices_[E.b].position - vertices_[E.a].position;
            const double scale = std::max({1.0, glm::length(vertices_[E.a].position), glm::length(vertices_[E.b].position)});
            if (!(glm::length(d) > 1e-9 * scale)) throw invalid_input(name + " joins two vertices at the same position");
            if (E.knot) {
                beam_vertex& k = edges_[e].knot.value();
                const double len = all_finite(k.normal) ? glm::length(k.normal) : 0.0;
                if (!all_finite(k.position) || !(len > 1e-12 && std::isfinite(len)))
                    throw invalid_input(name + " has a knot with a non-finite position or a zero normal");
                k.normal /= len;
                const double da = glm::length(k.position - vertices_[E.a].position), db = glm::length(k.position - vertices_[E.b].position);
                if (!(da > 1e-9 * scale && db > 1e-9 * scale)) throw invalid_input(name + " has its knot on an endpoint");
            }
            keys.emplace_back((std::uint64_t{std::min(E.a, E.b)} << 32) | std::max(E.a, E.b), e);
        }
        std::sort(keys.begin(), keys.end());
        for (std::size_t i = 1; i < keys.size(); ++i)
            if (keys[i].first == keys[i - 1].first)
                throw invalid_input("beam_model: edge " + std::to_string(keys[i].second) + " duplicates edge " + std::to_string(keys[i - 1].second));
        if (profile) {
            for (std::uint32_t v : profile->fixed_vertices)
                if (v >= vertices_.size())
                    throw invalid_input("beam_model: force profile fixes vertex " + std::to_string(v) + ", out of range (" +
                                        std::to_string(vertices_.size()) + " vertices)");
            for (const auto& [v, f] : profile->loads) {
                if (v >= vertices_.size())
                    throw invalid_input("beam_model: force profile loads vertex " + std::to_string(v) + ", out of range (" +
                                        std::to_string(vertices_.size()) + " vertices)");
                if (!all_finite(f)) throw invalid_input("beam_model: force profile load on vertex " + std::to_string(v) + " is not finite");
            }
        }
    }

    void choose_width() {
        if (opt_.beam_width_mm > 0) {
            width_ = opt_.beam_width_mm;
            return;
        }
        if (edges_.empty()) {
            width_ = opt_.thickness_mm;
            return;
        }
        std::vector<double> len;
        len.reserve(edges_.size());
        for (const beam_edge& e : edges_) len.push_back(glm::length(vertices_[e.b].position - vertices_[e.a].position));
        std::sort(len.begin(), len.end());
        const std::size_t n = len.size();
        const double median = n % 2 ? len[n / 2] : 0.5 * (len[n / 2 - 1] + len[n / 2]);
        width_ = std::min(0.2 * median, 0.6 * len.front());
    }

    /// The beams: one segment per edge, or two through a knot vertex (appended to vertices_) for
    /// the edges marked in split. The knot sits at the chord midpoint; its normal is the mean of
    /// the end normals made perpendicular to the chord (else n_a's perpendicular part, else any
    /// perpendicular), so both half-chords lie in its tangent plane and each half bends by at most
    /// about 90 degrees where a single beam would have to fold through 180.
    void make_segments(std::span<const std::uint8_t> split, std::span<const double> thinning) {
        segments_.clear();
        vertex_thickness_.resize(user_vertices_);
        for (std::size_t v = 0; v < user_vertices_; ++v) vertex_thickness_[v] = opt_.thickness_mm * thinning[v];
        edge_segment_begin_.assign(edges_.size() + 1, 0);
        for (std::size_t e = 0; e < edges_.size(); ++e) {
            const beam_edge& E = edges_[e];
            const auto edge = static_cast<std::uint32_t>(e);
            edge_segment_begin_[e] = static_cast<std::uint32_t>(segments_.size());
            if (split[e] == 0) {
                segments_.push_back({E.a, E.b, edge});
                continue;
            }
            if (split[e] == 2) continue;  // unmodelled
            const auto knot = static_cast<std::uint32_t>(vertices_.size());
            if (E.knot) {
                vertices_.push_back(*E.knot);
            } else {
                const beam_vertex &A = vertices_[E.a], &B = vertices_[E.b];
                const vec3 d = glm::normalize(B.position - A.position);
                const auto perpendicular = [&](const vec3& v) { return v - glm::dot(v, d) * d; };
                vec3 n = perpendicular(A.normal + B.normal);
                if (glm::length(n) < 0.1) n = perpendicular(A.normal);
                if (glm::length(n) < 0.1) n = perpendicular(std::abs(d.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0));
                vertices_.push_back({0.5 * (A.position + B.position), glm::normalize(n)});
            }
            vertex_thickness_.push_back(std::min(vertex_thickness_[E.a], vertex_thickness_[E.b]));
            segments_.push_back({E.a, knot, edge});
            segments_.push_back({knot, E.b, edge});
        }
        edge_segment_begin_[edges_.size()] = static_cast<std::uint32_t>(segments_.size());
    }

    /// Incident segments of every vertex (CSR, by segment index) and the hub of each vertex.
    void build_hubs() {
        const std::size_t nv = vertices_.size();
        std::vector<std::uint32_t> start(nv + 1, 0);
        for (const segment& e : segments_) ++start[e.a + 1], ++start[e.b + 1];
        for (std::size_t i = 0; i < nv; ++i) start[i + 1] += start[i];
        std::vector<std::uint32_t> incident(start.back()), fill(start.begin(), start.end() - 1);
        for (std::size_t e = 0; e < segments_.size(); ++e)
            incident[fill[segments_[e].a]++] = static_cast<std::uint32_t>(e), incident[fill[segments_[e].b]++] = static_cast<std::uint32_t>(e);
        sides_.assign(segments_.size(), {});
        hub_radius_.assign(nv, 0.0);
        hub_begin_.assign(nv + 1, 0);
        for (std::size_t i = 0; i < nv; ++i) {
            hub_begin_[i] = static_cast<std::uint32_t>(mesh_.nodes.size());
            build_hub(i, std::span<const std::uint32_t>(incident.data() + start[i], start[i + 1] - start[i]));
        }
        hub_begin_[nv] = static_cast<std::uint32_t>(mesh_.nodes.size());
        first_hex_ = mesh_.elements.size();
    }

    void build_hub(std::size_t i, std::span<const std::uint32_t> inc) {
        constexpr double pi = std::numbers::pi, two_pi = 2 * std::numbers::pi;
        constexpr double q = 0.75;                 // sides take at most 75% of the smallest gap
        constexpr double max_step = pi / 3;        // largest angular step of the polygon
        const beam_vertex& V = vertices_[i];
        const vec3 n = V.normal, p = V.position;
        const vec3 ax = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z) ? vec3(1, 0, 0)
                        : std::abs(n.y) <= std::abs(n.z)                                   ? vec3(0, 1, 0)
                                                                                            : vec3(0, 0, 1);
        const vec3 t1 = glm::normalize(glm::cross(n, ax)), t2 = glm::cross(n, t1);
        const std::size_t k = inc.size();
        double hw = 0.5 * width_;  // narrowed below at a hub with too many neighbours for the width

        // Directions: angle of each incident edge's neighbour in the tangent plane.
        double shortest = std::numeric_limits<double>::infinity();
        std::vector<std::pair<double, std::uint32_t>> dir;  // (angle, edge), undefined angles = NaN
        std::vector<std::uint32_t> undefined;
        for (std::uint32_t e : inc) {
            const std::uint32_t other = segments_[e].a == i ? segments_[e].b : segments_[e].a;
            const vec3 d = vertices_[other].position - p;
            shortest = std::min(shortest, glm::length(d));
            const vec3 t = d - glm::dot(d, n) * n;
            if (glm::length(t) <= 1e-9 * glm::length(d)) undefined.push_back(e);
            else dir.emplace_back(std::atan2(glm::dot(t, t2), glm::dot(t, t1)), e);
        }
        std::sort(dir.begin(), dir.end());
        for (std::uint32_t e : undefined) {  // middle of the largest gap of the defined directions
            double angle = 0;
            if (!dir.empty()) {
                std::size_t best = dir.size() - 1;
                double best_gap = dir.front().first + two_pi - dir.back().first;
                for (std::size_t j = 0; j + 1 < dir.size(); ++j)
                    if (dir[j + 1].first - dir[j].first > best_gap) best_gap = dir[j + 1].first - dir[j].first, best = j;
                angle = dir[best].first + 0.5 * best_gap;
                if (angle > pi) angle -= two_pi;
            }
            dir.emplace_back(angle, e);
            std::sort(dir.begin(), dir.end());
        }

        // Hub radius and (when needed) spread directions.
        std::vector<double> y(k);
        for (std::size_t j = 0; j < k; ++j) y[j] = dir[j].first;
        double r = hw, beta = pi / 4;
        if (k > 0) {
            double gmin = two_pi;
            for (std::size_t j = 0; j + 1 < k; ++j) gmin = std::min(gmin, y[j + 1] - y[j]);
            if (k > 1) gmin = std::min(gmin, y[0] + two_pi - y[k - 1]);
            const double r_cap = 0.35 * shortest;
            beta = std::min(0.5 * q * gmin, pi / 4);
            r = beta > 0 ? hw / std::tan(beta) : std::numeric_limits<double>::infinity();
            if (r > r_cap) {
                r = r_cap;
                // Narrower sides first (each still faces its neighbour); spreading the directions
                // turns the sides away from their neighbours and twists short beams inside out.
                const double fit = r_cap * std::tan(beta);
                if (fit >= 0.25 * hw) {
                    hw = fit;
                    ++narrowed_hubs_;
                } else {
                    hw *= 0.25;
                    ++narrowed_hubs_;
                }
                beta = std::atan(hw / r);
                const double s = 2 * beta / q;
                if (static_cast<double>(k) * s > two_pi) {  // even spacing, and a larger hub
                    beta = q * pi / static_cast<double>(k);
                    r = hw / std::tan(beta);
                    if (r > 0.45 * shortest) {  // narrower sides here: the beams taper towards this hub
                        r = 0.45 * shortest;
                        hw = r * std::tan(beta);
                        ++narrowed_hubs_;
                    }
                    make_uniform(y);
                } else if (gmin < s) {
                    // Cut the circle at the largest gap (after y[cut]), spread, check the wrap-around gap.
                    std::size_t cut = k - 1;
                    double big = y[0] + two_pi - y[k - 1];
                    for (std::size_t j = 0; j + 1 < k; ++j)
                        if (y[j + 1] - y[j] > big) big = y[j + 1] - y[j], cut = j;
                    std::vector<double> x(k);
                    for (std::size_t j = 0; j < k; ++j) {
                        const std::size_t src = (cut + 1 + j) % k;
                        x[j] = y[src] + (src <= cut ? two_pi : 0.0);
                    }
                    const std::vector<double> z = detail::spread_angles(x, s);
                    if (z.front() + two_pi - z.back() >= s * (1 - 1e-12)) {
                        for (std::size_t j = 0; j < k; ++j) {
                            const std::size_t src = (cut + 1 + j) % k;
                            y[src] = z[j] - (src <= cut ? two_pi : 0.0);  // y stays ascending, span < 2 pi
                        }
                    } else {
                        make_uniform(y);  // k s <= 2 pi: even spacing keeps the capped radius
                    }
                }
            }
        }
        hub_radius_[i] = r;

        // Polygon corners in angular order; side j owns corners (L_j, R_j).
        const double rho = std::sqrt(r * r + hw * hw);
        auto on_circle = [&](double a) { return p + rho * (std::cos(a) * t1 + std::sin(a) * t2); };
        std::vector<vec3> corners;
        std::vector<std::size_t> side_corner(k);  // index of L_j (R_j follows)
        auto add_gap = [&](double from, double to) {
            const double span = to - from;
            const int m = std::max(0, static_cast<int>(std::ceil(span / max_step - 1e-9)) - 1);
            for (int c = 1; c <= m; ++c) corners.push_back(on_circle(from + span * c / (m + 1)));
        };
        if (k == 0) {
            for (int c = 0; c < 6; ++c) corners.push_back(p + hw * (std::cos(c * pi / 3) * t1 + std::sin(c * pi / 3) * t2));
        } else {
            for (std::size_t j = 0; j < k; ++j) {
                const vec3 d = std::cos(y[j]) * t1 + std::sin(y[j]) * t2, e = glm::cross(n, d);
                side_corner[j] = corners.size();
                corners.push_back(p + r * d - hw * e);
                corners.push_back(p + r * d + hw * e);
                add_gap(y[j] + beta, (j + 1 < k ? y[j + 1] : y[0] + two_pi) - beta);
            }
        }
        const auto base = static_cast<std::uint32_t>(mesh_.nodes.size());
        const vec3 down = -vertex_thickness_[i] * n;
        mesh_.nodes.push_back(p);
        mesh_.nodes.push_back(p + down);
        for (const vec3& c : corners) mesh_.nodes.push_back(c), mesh_.nodes.push_back(c + down);
        const auto outer = [&](std::size_t c) { return base + 2 + 2 * static_cast<std::uint32_t>(c); };
        for (std::size_t c = 0; c < corners.size(); ++c) {
            const std::size_t c1 = (c + 1) % corners.size();
            const std::array<std::uint32_t, 6> w = {base + 1, outer(c) + 1, outer(c1) + 1, base, outer(c), outer(c1)};
            fem::wedge6::nodes_t X;
            for (int a = 0; a < 6; ++a) X[static_cast<std::size_t>(a)] = mesh_.nodes[w[static_cast<std::size_t>(a)]];
            const auto [lo, hi] = detail::jacobian_range<fem::wedge6>(X);
            if (!(lo > 1e-12 * hi)) throw invalid_input("beam_model: vertex " + std::to_string(i) + " has a degenerate hub wedge (internal)");
            mesh_.elements.push_back(fem::make_element<fem::wedge6>(w));
        }
        for (std::size_t j = 0; j < k; ++j) {
            const std::uint32_t e = dir[j].second;
            const std::uint32_t L = outer(side_corner[j]), R = outer(side_corner[j] + 1);
            sides_[e][segments_[e].a == i ? 0 : 1] = {L, R, L + 1, R + 1};
        }
    }

    static void make_uniform(std::vector<double>& y) {
        const std::size_t k = y.size();
        const double step = 2 * std::numbers::pi / static_cast<double>(k);
        double sn = 0, cs = 0;
        for (std::size_t j = 0; j < k; ++j) sn += std::sin(y[j] - step * j), cs += std::cos(y[j] - step * j);
        const double phase = std::atan2(sn, cs);
        for (std::size_t j = 0; j < k; ++j) y[j] = phase + step * static_cast<double>(j);
    }

    /// One hex8 per segment; returns the segments no node order makes a valid hex (nothing added then).
    [[nodiscard]] std::vector<std::size_t> build_beams() {
        std::vector<std::size_t> folded;
        for (std::size_t e = 0; e < segments_.size(); ++e) {
            const side_nodes& A = sides_[e][0];
            const side_nodes& B = sides_[e][1];
            // Inner face (L_a, R_b, L_b, R_a), counter-clockwise about n; outer face above it. Where the
            // frames of the two ends disagree (normals turned by curvature, or an edge that crosses a thin
            // part), the end-B side is taken in the order of its four nodes that gives the best Jacobian
            // ratio (all 24 orders are tried when the plain one is poorly shaped); the nodes stay shared
            // with both hubs.
            std::array<std::uint32_t, 8> h{};
            double lo = -1, hi = 1;
            std::array<int, 4> perm = {0, 1, 2, 3};
            bool first = true;
            do {
                const side_nodes b = {B[static_cast<std::size_t>(perm[0])], B[static_cast<std::size_t>(perm[1])],
                                      B[static_cast<std::size_t>(perm[2])], B[static_cast<std::size_t>(perm[3])]};
                std::array<std::uint32_t, 8> c = {A[2], b[3], b[2], A[3], A[0], b[1], b[0], A[1]};
                auto range = [&] {
                    fem::hex8::nodes_t X;
                    for (int a = 0; a < 8; ++a) X[static_cast<std::size_t>(a)] = mesh_.nodes[c[static_cast<std::size_t>(a)]];
                    return detail::jacobian_range<fem::hex8>(X);
                };
                auto [l, u] = range();
                if (u < 0) {
                    for (int a = 0; a < 4; ++a) std::swap(c[static_cast<std::size_t>(a)], c[static_cast<std::size_t>(a + 4)]);
                    std::tie(l, u) = range();
                }
                if (first || (u > 0 && (hi <= 0 || l / u > lo / hi))) h = c, lo = l, hi = u;
                if (first && lo > 0.05 * hi) break;  // the plain order is well shaped: keep it
                first = false;
            } while (std::next_permutation(perm.begin(), perm.end()));
            if (!(lo > 1e-9 * hi)) {
                folded.push_back(e);
                continue;
            }
            if (folded.empty())
                mesh_.elements.push_back(fem::make_element<fem::hex8>(h, 0, edges_[segments_[e].edge].solid ? 1.0 : opt_.rho_min));
        }
        return folded;
    }

    [[noreturn]] void throw_folded(std::size_t seg) const {
        const beam_edge& E = edges_[segments_[seg].edge];
        throw invalid_input("beam_model: the beam of edge " + std::to_string(segments_[seg].edge) + " (" + std::to_string(E.a) + ", " +
                            std::to_string(E.b) +
                            ") is folded or degenerate in every node order, even split at a knot: the vertex frames fold between its "
                            "ends (opposite normals, too sharp curvature or an edge along a normal)");
    }

    void build_supports_and_loads(const std::optional<force_profile>& profile) {
        const std::size_t nv = user_vertices_;
        std::vector<std::uint8_t> fixed(mesh_.nodes.size(), 0);
        if (profile && !profile->fixed_vertices.empty()) {
            for (std::uint32_t v : profile->fixed_vertices)
                for (std::uint32_t a = hub_begin_[v]; a < hub_begin_[v + 1]; ++a) fixed[a] = 1;
        } else if (!mesh_.nodes.empty()) {
            const vec3 up = -glm::normalize(opt_.gravity);
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (const vec3& x : mesh_.nodes) lo = std::min(lo, glm::dot(x, up)), hi = std::max(hi, glm::dot(x, up));
            const double limit = lo + opt_.support_fraction * (hi - lo) + 1e-9 * std::max(hi - lo, 1e-300);
            for (std::size_t a = 0; a < mesh_.nodes.size(); ++a) fixed[a] = glm::dot(mesh_.nodes[a], up) <= limit;
        }
        // Every connected part of the graph needs a fixed node.
        union_find parts(nv), whole(nv);
        for (const beam_edge& e : edges_) whole.unite(e.a, e.b);
        for (std::size_t e = 0; e < edges_.size(); ++e)
            if (modelled(e)) parts.unite(edges_[e].a, edges_[e].b);
        std::vector<std::uint8_t> held(nv, 0);
        for (std::size_t v = 0; v < vertices_.size(); ++v) {
            const std::uint32_t owner = v < nv ? static_cast<std::uint32_t>(v) : knot_owner(v);  // a knot belongs to its edge's part
            for (std::uint32_t a = hub_begin_[v]; a < hub_begin_[v + 1]; ++a)
                if (fixed[a]) held[parts.find(owner)] = 1;
        }
        // A part cut off only by unmodelled edges is fixed where it stands (it carries its own load).
        std::vector<std::uint8_t> whole_held(nv, 0);
        for (std::size_t v = 0; v < nv; ++v)
            if (held[parts.find(static_cast<std::uint32_t>(v))]) whole_held[whole.find(static_cast<std::uint32_t>(v))] = 1;
        for (std::size_t v = 0; v < nv; ++v)
            if (!held[parts.find(static_cast<std::uint32_t>(v))] && whole_held[whole.find(static_cast<std::uint32_t>(v))]) {
                for (std::uint32_t a = hub_begin_[v]; a < hub_begin_[v + 1]; ++a) fixed[a] = 1;
                ++cut_off_fixed_;
            }
        for (std::size_t i = nv; i < vertices_.size(); ++i) {  // knots of such parts too
            const std::uint32_t o = knot_owner(i);
            if (!held[parts.find(o)] && whole_held[whole.find(o)])
                for (std::uint32_t a = hub_begin_[i]; a < hub_begin_[i + 1]; ++a) fixed[a] = 1;
        }
        for (std::size_t a = 0; a < fixed.size(); ++a)
            if (fixed[a])
                for (int d = 0; d < 3; ++d) supports_.fixed.push_back({static_cast<std::uint32_t>(a), d, 0.0});
        for (std::size_t v = 0; v < nv; ++v) {
            const auto root = parts.find(static_cast<std::uint32_t>(v));
            if (held[root] || whole_held[whole.find(static_cast<std::uint32_t>(v))]) continue;
            std::string list;
            std::size_t count = 0;
            for (std::size_t u = 0; u < nv; ++u)
                if (parts.find(static_cast<std::uint32_t>(u)) == root) {
                    if (count < 8) list += (count ? ", " : "") + std::to_string(u);
                    ++count;
                }
            if (count > 8) list += ", ... (" + std::to_string(count) + " vertices)";
            throw no_solution("beam_model: the part of the graph with vertices " + list +
                              " has no support (none of its nodes is fixed: it lies above the lowest " +
                              std::to_string(opt_.support_fraction * 100) +
                              "% along gravity and no fixed vertex of a force profile is in it), so it cannot carry loads");
        }

        // Loads: per-vertex forces spread by lumped wedge volume over the hub nodes.
        std::vector<vec3> force(nv, vec3(0.0));
        if (profile && !profile->loads.empty()) {
            for (const auto& [v, f] : profile->loads) force[v] += f;
        } else {
            const vec3 g = glm::normalize(opt_.gravity) * opt_.load_per_vertex_n;
            std::fill(force.begin(), force.end(), g);
        }
        std::vector<double> weight(mesh_.nodes.size(), 0.0);
        for (std::size_t el = 0; el < first_hex_; ++el) {
            const double V = fem::wedge6::volume(mesh_.element_nodes<fem::wedge6>(el), opt_.material);
            for (int a = 0; a < 6; ++a) weight[mesh_.elements[el].nodes[static_cast<std::size_t>(a)]] += V / 6;
        }
        for (std::size_t v = 0; v < nv; ++v) {
            if (force[v] == vec3(0.0)) continue;
            double total = 0;
            for (std::uint32_t a = hub_begin_[v]; a < hub_begin_[v + 1]; ++a) total += weight[a];
            for (std::uint32_t a = hub_begin_[v]; a < hub_begin_[v + 1]; ++a)
                for (int d = 0; d < 3; ++d)
                    if (force[v][d] != 0.0) loads_.forces.push_back({a, d, force[v][d] * weight[a] / total});
        }
    }

    beam_options opt_;
    std::vector<beam_vertex> vertices_;
    std::vector<beam_edge> edges_;
    double width_ = 0;
    fem::mesh mesh_;  ///< under construction; moved into ctx_, whose model() holds the current scales
    /// A beam: vertices a, b (user vertices or knots) and the user edge it belongs to.
    struct segment {
        std::uint32_t a, b, edge;
    };
    /// Vertex a of the user edge whose knot is vertex v (v >= user_vertices_).
    [[nodiscard]] std::uint32_t knot_owner(std::size_t v) const {
        for (const segment& s : segments_)
            if (s.b == v) return edges_[s.edge].a;
        return 0;
    }

    [[nodiscard]] bool modelled(std::size_t e) const { return edge_segment_begin_[e + 1] > edge_segment_begin_[e]; }
    std::size_t unmodelled_ = 0, cut_off_fixed_ = 0;
    static constexpr int max_thinning = 2;  ///< halvings of a folded edge's end thickness (down to 1/4)
    std::vector<double> vertex_thickness_;   ///< extrusion per vertex (knots: the thinner end's) [mm]
    std::size_t narrowed_hubs_ = 0;
    std::size_t user_vertices_ = 0;                   ///< vertices_ beyond this are knots
    std::vector<segment> segments_;                   ///< one hex8 each, in edge order
    std::vector<std::uint32_t> edge_segment_begin_;   ///< per edge its first segment (size edges + 1)
    std::vector<std::array<side_nodes, 2>> sides_;
    std::vector<double> hub_radius_;
    std::vector<std::uint32_t> hub_begin_;
    std::size_t first_hex_ = 0;
    fem::load_case supports_, loads_;
    std::unique_ptr<fem::solve_context> ctx_;
    fem::static_result last_;
    beam_statistics stats_;
};

}  // namespace fabsynth::surface_pattern
