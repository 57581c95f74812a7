// SPDX-License-Identifier: MIT
#pragma once
/// @file structural.hpp  The structural optimizer of structurally-sound-patterns.md §5
/// (STRUCTURALOPTIM, Algorithm 4, with the reinforcement bridges of §5.2) and the loop of
/// Algorithm 1 (PATTERNSYNTHESIZER) that alternates it with the constrained resynthesis of §4.4.
///
/// Usage:
///   namespace sp = fabsynth::surface_pattern;
///   const sp::surface_graph gs = sp::build_surface_graph(pyramid.levels[0]);     // once per shell
///   sp::structure_options so{.r_pattern_mm = 2.0, .thickness_mm = 1.5};
///   sp::structure_report rep = sp::optimize_structure(syn, result, gs, so);     // result.solid: connected, reinforced
///   for (const auto& it : rep.iterations) log(it.components_before, it.added_connect, it.max_stress_mpa);
///
/// One structural step (structural_step) on the current states s of the level-0 shell voxels:
///  1. G_abstract of the solid voxels (abstract_graph.hpp: Poisson samples, CONNECTSAMPLES), one
///     beam model (beam_model.hpp) per component of G_surface that has abstract edges ("each
///     component on its own", §5.1): each piece of the mesh gets its own supports, the lowest
///     support_fraction of its extent along gravity, and the load (the pattern's weight times
///     load_factor, or design_load_n) spread equally over the abstract vertices of all pieces, along
///     gravity (or the user's profile: `fixed` supports, e.g. plane_support, and point / area
///     `loads` or a `load` callback).
///  2. Connect (§5.2, first criterion): while the solid edges leave more than one component in a
///     piece of the mesh, solve and insert the empty edges of highest score that join two different
///     components, up to edges_per_solve per solve with the dart-throwing exclusion (an edge whose
///     midpoint lies within twice the length of an edge inserted by the same solve is skipped).
///  3. Force (§5.2, second): while the largest score of a *solid* edge exceeds the allowable stress
///     (material tensile strength / safety factor), solve and insert the empty edges of highest
///     score, with the same exclusion. Scores of empty edges are the paper's C eps "as if solid"
///     (beam_model.hpp), i.e. the stress a bridge there would take under the current deformation:
///     they rank the candidates but do not decide when to stop. The paper's stopping rule reads
///     "until the maximum stress of all edges is below a material-dependent threshold"; its empty
///     edges are soft beams (stiffness rho_min), whose own stress is negligible, so "all edges"
///     means what prints. (Scoring empty edges as if solid in the stopping rule, as this loop once
///     did, keeps bridging until every gap could carry the load, which carves the pattern away.)
///     Stops when nothing solid is overloaded, no empty edge remains, or after max_force_solves
///     solves (reported: force_bound_hit). Two choices of ours make the phase lay the fewest
///     bridges that relieve the overload (the paper ranks every empty edge and does not say how
///     many go in per solve): the candidates are the empty edges within two abstract edges of an
///     overloaded solid edge's endpoints (all empty edges when none is that close), and a solve
///     inserts ceil(edges_per_solve x (max / allowable - 1)) of them, at least 1, at most
///     edges_per_solve, so the last bridges go in one at a time. Ranked over the whole graph, the
///     highest "as if solid" scores lie where the deformation is large, often far from the
///     overloaded edge: on the kitten with hooks at 256^3 one edge at 1.04x the allowable stress
///     took 20 bridges in 21 solves, and the run ended at 1.70x the synthesized solid; with both
///     choices it ends at 1.53x (benchmarks/README.md, "Surface patterns: fewer bridges").
///  Ranking (both phases): the cheapest bridge that does the job. Candidates are ranked by score
///  in bands of ratio bridge_band (band 0: scores within bridge_band of the best candidate's,
///  band 1: within bridge_band of band 0's lower end, ...); within a band the path with the fewest
///  empty voxels (the bridge that lays the fewest voxels) comes first, then the higher score.
///  bridge_band 0.25 (a bridge within 4x of the best score counts as near-highest) was chosen on
///  the 256^3 runs of bunny/hooks, kitten/hooks and bunny/spots: 0.8 / 0.5 / 0.25 ended at 1.47 /
///  1.45 / 1.41x, 1.56 / 1.54 / 1.53x and 1.60 / 1.57 / 1.50x the synthesized solid, with Table 3's
///  stress drops kept (benchmarks/README.md).
///  4. Geodesic (§5.2.2): an empty edge (a, b) scores the length of the shortest path from a to b
///     through solid edges (length_mm weights); while some edge scores more than geodesic_factor x
///     the extent of the shell (the longest side of its bounding box), the highest is inserted and
///     all scores are recomputed ("the score of all edges is updated after each addition").
///  5. Every inserted edge's voxel path (recorded by CONNECTSAMPLES) is dilated, geodesic in
///     G_surface, and those voxels become solid reinforcement (state 3). The paper dilates by
///     r_pattern; bridge_radius_mm > 0 lays narrower bridges (the issue of appearance: every bridge
///     voxel is a voxel the exemplar did not choose).
/// The step is done (Algorithm 1's `done`) when it inserted no edge.
///
/// The loop (optimize_structure): SYNTHESIZE is the caller's; then up to max_iterations times:
/// a structural step; if done, stop; else RESYNTHESIZE with every reinforcement voxel so far forced
/// solid (accumulated: a later resynthesis never removes an earlier bridge, §4.4 "the changes will
/// not be removed entirely") and all voxels allowed. When the bound is hit the last step's
/// bridges are kept without a resynthesis after them, so the result is connected even then, and the
/// report says the bound was hit (converged = false).
///
/// Choices the paper leaves open (documented defaults):
///  - Load: the paper applies an "arbitrary but constant" force per vertex and a "manually fixed"
///    stress threshold; the two only mean something together. Here the force is the gravity
///    profile of the pattern itself: its weight (solid shell voxels x voxel area x thickness x the
///    material's density x g; the Poisson samples are uniform over the solid, so equal shares per
///    abstract vertex follow the mass) times load_factor, recomputed every step as bridges add
///    mass; the threshold is the printing material's tensile strength / safety_factor (2).
///    Calibration of load_factor (default 20): the paper's figures it must reproduce are Table 1's
///    final geometry (bunny with hooks: 55 356 voxels, about 1.6x what our synthesis lays at 256^3)
///    and Table 3's effect of the force criterion (99th percentile 5x lower than connected-only),
///    which needs a force phase that acts. On the bunny with hooks at 128^3 (r_pattern 2 px),
///    factors 5 / 10 / 20 / 50 ended at 1.73 / 1.73 / 1.81 / 2.00x the synthesized solid, with
///    0 / 0 / 8 / 24 force bridges (benchmarks/README.md, "Surface patterns: load calibration"):
///    20 is the smallest at which the force phase still acts (below it nothing solid is overloaded
///    once the pattern is connected, so the forces stage would equal the connected one). (Those
///    ratios were measured with bridges dilated by r_pattern and ranked over the whole graph; with
///    the narrow, local bridges of today the same run ends at 1.36x, and at 256^3 at 1.41x.) The former
///    default, a fixed 10 N (about 50x the weight of the carved bunny shell) with the stopping rule
///    over every edge, empty ones as if solid, ended the same run (r_pattern 4 px) at 3.7x the
///    synthesized solid: the exemplar was gone. design_load_n > 0 replaces the rule by a fixed
///    total in N.
///  - Beam width: beam_model's rule, 0.2 x the median edge length (at most 0.6 x the shortest), not
///    the 2 r_pattern of a dilated bridge: with ~1000 samples the edges are only 1-2 bridge widths
///    long, and beams that wide leave hubs so crowded that most beams are short, twisted elements
///    whose stresses are artefacts (tens of GPa on the bunny). Hubs with more neighbours than the
///    width allows get narrower sides (beam_model.hpp). The pattern's features are 2 r_pattern
///    wide, so the scores are scaled by w / (2 r_pattern) (when w is narrower) before
///    they are compared with the allowable stress: to first order the axial and out-of-plane
///    bending stresses of a beam scale with 1 / width (in-plane bending with 1 / width^2, so this
///    is conservative there). Narrow bridges (bridge_radius_mm < r_pattern_mm) are scored at the
///    same width, so their own stress is underestimated by up to 2 r_pattern / (2 bridge radius +
///    one voxel); the full voxel validation (validation.hpp) is the check. An edge no single hex can follow (across
///    a thin part) is split at the voxel half-way along its path.
///  - Specks: the abstract graph gives every solid component a sample, so tiny islands left by
///    the synthesis would be bridged; remove them before (fabricate.hpp remove_specks).
/// Deterministic for any thread count (every building block is).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <limits>
#include <numeric>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/fem/material.hpp"
#include "fabsynth/graph/shortest_paths.hpp"
#include "fabsynth/surface_pattern/abstract_graph.hpp"
#include "fabsynth/surface_pattern/beam_model.hpp"
#include "fabsynth/surface_pattern/shell.hpp"
#include "fabsynth/surface_pattern/synthesis.hpp"

namespace fabsynth::surface_pattern {

/// A printing material: elastic constants and tensile strength.
struct print_material {
    std::string name;
    fem::isotropic_material elastic;
    double tensile_strength_mpa = 0;  ///< [MPa]

    /// ABS: fem's preset (E 2200 MPa, nu 0.35) and 33 MPa, the low end of the 30-50 MPa range of
    /// generic ABS (Granta MaterialUniverse), as printed parts are weaker across layers.
    [[nodiscard]] static print_material abs() { return {"abs", fem::isotropic_material::abs(), 33.0}; }
    /// PLA: fem's preset (E 3500 MPa, nu 0.36) and 50 MPa, a typical tensile strength of printed PLA.
    [[nodiscard]] static print_material pla() { return {"pla", fem::isotropic_material::pla(), 50.0}; }
    /// "abs" or "pla"; throws invalid_input for any other name.
    [[nodiscard]] static print_material named(const std::string& n) {
        if (n == "abs") return abs();
        if (n == "pla") return pla();
        throw invalid_input("unknown material '" + n + "' (expected abs or pla)");
    }
};

/// A force [N] on the pattern at a point [mm] (a finger, a hook, a weight hung from the object),
/// shared equally by the abstract vertices within radius_mm of `at`; when none is that close, the
/// nearest vertex takes all of it (a point load).
struct area_load {
    vec3 at{};                ///< [mm], in the scaled mesh's frame (the shell grid's coordinates)
    vec3 force_n{};           ///< [N]
    double radius_mm = 0;     ///< >= 0; 0 = the nearest abstract vertex
};

/// The supports of §5.2.1 as a band around a plane: fixes the abstract vertices whose distance to
/// the plane through `point` [mm] with normal `normal` is at most band_mm (e.g. the table the
/// object stands on, or a wall it is screwed to). For structure_options::fixed. Throws
/// invalid_input for a zero or non-finite normal, a non-finite point or a band < 0.
[[nodiscard]] inline std::function<bool(const vec3&)> plane_support(vec3 point, vec3 normal, double band_mm) {
    if (!all_finite(point)) throw invalid_input("support plane: the point must be finite");
    if (!all_finite(normal) || !(glm::length(normal) > 0)) throw invalid_input("support plane: the normal must be a finite non-zero vector");
    if (!(std::isfinite(band_mm) && band_mm >= 0)) throw invalid_input("support plane: the band must be finite and >= 0 mm");
    const vec3 n = glm::normalize(normal);
    return [point, n, band_mm](const vec3& p) { return std::abs(glm::dot(p - point, n)) <= band_mm; };
}

/// Which criterion inserted an edge (§5.2).
enum class bridge_criterion : std::uint8_t { connect, force, geodesic };

/// Parameters of the structural optimizer (see the file comment).
struct structure_options {
    double r_pattern_mm = 0;          ///< feature radius of the pattern [mm]: width of its features, resynthesis radius; > 0 (required)
    /// Dilation radius of a bridge's voxel path [mm] (step 5): 0 = r_pattern_mm, the paper's rule;
    /// > 0 a narrower bridge (make_pattern uses the narrowest that prints, see pipeline.hpp).
    double bridge_radius_mm = 0;
    double thickness_mm = 0;          ///< shell thickness of the printed object [mm] (beam extrusion); > 0 (required)
    std::size_t target_samples = 1000;  ///< abstract vertices (paper: 1000)
    std::uint64_t seed = 1;           ///< Poisson-disk priorities
    print_material material = print_material::abs();
    double safety_factor = 2;         ///< allowable stress = tensile strength / safety_factor, > 0
    double load_factor = 20;          ///< default profile: the pattern's weight times this (file comment), >= 0
    double design_load_n = 0;         ///< > 0: a fixed total force [N] instead, spread over the abstract vertices
    vec3 gravity{0, 0, -1};           ///< direction of the force profile and of the supports, non-zero
    double support_fraction = 0.10;   ///< each piece is fixed in its lowest 10% along gravity (§5.2.1)
    /// Optional user force profile (e.g. a pinch grip): an abstract vertex whose position [mm] makes
    /// `fixed` true has its hub fixed (replacing the support rule; every piece needs one), and
    /// `load` gives the force [N] on a vertex from its position (replacing the design load).
    std::function<bool(const vec3&)> fixed{};
    std::function<vec3(const vec3&)> load{};
    /// Forces at points (area_load); non-empty: they are the whole force profile (replacing the
    /// design load and `load`), and a piece of the mesh that none of them reaches is unloaded.
    std::vector<area_load> loads{};
    double geodesic_factor = 1.5;     ///< §5.2.2 threshold: factor x the extent of the shell; <= 0 turns the criterion off
    bool force_criterion = true;      ///< false: connect only, then the geodesic criterion (Table 3 stages)
    int edges_per_solve = 8;          ///< insertions per FEM solve (connect, force), >= 1
    int max_force_solves = 40;        ///< bound on the force phase's solves per step, >= 0
    double beam_width_mm = 0;         ///< 0 = beam_model's rule (0.2 x median edge length, <= 0.6 x shortest)
    double rho_min = 1e-4;            ///< stiffness of empty beams (beam_model.hpp)
    double bridge_band = 0.25;        ///< candidates whose scores lie within this ratio rank by the voxels their bridge adds (file comment); in (0, 1]
    fem::solve_options solver = default_beam_solver();

    [[nodiscard]] double allowable_stress_mpa() const { return material.tensile_strength_mpa / safety_factor; }
    /// The dilation radius of step 5 [mm]: bridge_radius_mm, or r_pattern_mm when it is 0.
    [[nodiscard]] double bridge_radius() const { return bridge_radius_mm > 0 ? bridge_radius_mm : r_pattern_mm; }

    /// Throws invalid_input naming the first bad parameter.
    void validate() const {
        const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
        if (!positive(r_pattern_mm)) throw invalid_input("structure: r_pattern must be finite and > 0 mm, got " + std::to_string(r_pattern_mm));
        if (!positive(thickness_mm)) throw invalid_input("structure: thickness must be finite and > 0 mm, got " + std::to_string(thickness_mm));
        if (!(std::isfinite(bridge_radius_mm) && bridge_radius_mm >= 0)) throw invalid_input("structure: bridge radius must be finite and >= 0 mm, got " + std::to_string(bridge_radius_mm));
        if (target_samples < 2) throw invalid_input("structure: target_samples must be >= 2");
        material.elastic.validate();
        if (!positive(material.tensile_strength_mpa)) throw invalid_input("structure: the material's tensile strength must be > 0 MPa");
        if (!positive(safety_factor)) throw invalid_input("structure: safety factor must be finite and > 0");
        if (!(std::isfinite(design_load_n) && design_load_n >= 0)) throw invalid_input("structure: design load must be finite and >= 0 N");
        if (!(std::isfinite(load_factor) && load_factor >= 0)) throw invalid_input("structure: load factor must be finite and >= 0");
        if (!all_finite(gravity) || !(glm::length(gravity) > 0)) throw invalid_input("structure: gravity must be a finite non-zero direction");
        if (!(support_fraction >= 0 && support_fraction <= 1)) throw invalid_input("structure: support fraction must lie in [0, 1]");
        if (!std::isfinite(geodesic_factor)) throw invalid_input("structure: geodesic factor must be finite");
        if (edges_per_solve < 1) throw invalid_input("structure: edges_per_solve must be >= 1");
        if (max_force_solves < 0) throw invalid_input("structure: max_force_solves must be >= 0");
        if (!(std::isfinite(beam_width_mm) && beam_width_mm >= 0)) throw invalid_input("structure: beam width must be finite and >= 0");
        if (!(bridge_band > 0 && bridge_band <= 1)) throw invalid_input("structure: bridge_band must lie in (0, 1]");
        for (std::size_t i = 0; i < loads.size(); ++i)
            if (!all_finite(loads[i].at) || !all_finite(loads[i].force_n) || !(std::isfinite(loads[i].radius_mm) && loads[i].radius_mm >= 0))
                throw invalid_input("structure: load " + std::to_string(i + 1) + " needs a finite point, a finite force and a radius >= 0 mm");
        if (!loads.empty() && load) throw invalid_input("structure: give either point loads (loads) or a load callback (load), not both");
    }
};

/// What one structural step did.
struct structural_step_report {
    std::size_t samples = 0, solid_edges = 0, empty_edges = 0;  ///< G_abstract as built
    int pieces = 0;               ///< components of G_surface holding samples (each needs one solid component)
    int components_before = 0;    ///< components of the solid edges before the step
    int components_after = 0;     ///< and after it (= pieces when the connect phase finished)
    std::size_t added_connect = 0, added_force = 0, added_geodesic = 0;
    double max_stress_mpa = 0;       ///< largest solid-edge score of the first solve [MPa]
    double max_stress_after_mpa = 0; ///< largest solid-edge score of the last solve (after the force phase) [MPa]
    double allowable_stress_mpa = 0;
    double load_n = 0;               ///< total force of the default profile this step [N] (the sum of |force| of opt.loads when given; unused when opt.load is set)
    bool force_bound_hit = false;    ///< the force phase stopped at max_force_solves while overloaded
    double geodesic_threshold_mm = 0;
    double max_geodesic_mm = 0;      ///< largest geodesic score among empty edges at the end (inf if a piece is disconnected)
    int solves = 0;
    double beam_width_mm = 0;
    std::size_t beam_knots = 0;      ///< folded edges split at a knot (beam_model)
    std::size_t narrowed_hubs = 0;   ///< hubs with sides narrower than the beam width (beam_model)
    std::size_t reinforced_voxels = 0;  ///< voxels newly made solid by the bridges
    double graph_seconds = 0, model_seconds = 0, solve_seconds = 0, seconds = 0;
    /// Inserted abstract edges (indices into the step's G_abstract) and their criteria.
    std::vector<std::pair<std::uint32_t, bridge_criterion>> inserted;
    [[nodiscard]] bool done() const noexcept { return inserted.empty(); }
};

/// What the loop did.
struct structure_report {
    std::vector<structural_step_report> iterations;  ///< one per structural step
    std::vector<resynthesis_report> resyntheses;     ///< one per resynthesis (iterations - 1 when converged)
    bool converged = false;        ///< the last step inserted nothing
    /// The last step's solid edges still exceed the allowable stress (the force phase hit its bound
    /// or ran out of candidates): the pattern is connected but weaker than asked.
    bool overloaded = false;
    std::size_t forced_voxels = 0; ///< reinforcement voxels (state 3) at the end
    double structure_seconds = 0, resynthesis_seconds = 0;
};

namespace detail {

/// The beam models of one step: one per piece of the mesh that has abstract edges.
struct piece_models {
    struct piece {
        std::vector<std::uint32_t> vertex;  ///< local vertex -> sample
        std::vector<std::uint32_t> edge;    ///< local edge -> abstract edge
        std::unique_ptr<beam_model> model;
    };
    std::vector<piece> pieces;
    std::vector<std::uint32_t> local_edge;  ///< abstract edge -> its index in its piece
    std::vector<std::uint32_t> piece_of;    ///< abstract edge -> piece
    double width_mm = 0;
    std::size_t knots = 0, narrowed = 0;
};

[[nodiscard]] inline piece_models build_piece_models(const abstract_graph& ag, const shell_level& l0, const structure_options& opt, double total_load_n) {
    piece_models pm;
    const std::size_t ns = ag.samples.size();
    std::vector<int> comps(ag.surface_component.begin(), ag.surface_component.end());
    std::sort(comps.begin(), comps.end());
    comps.erase(std::unique(comps.begin(), comps.end()), comps.end());
    std::vector<std::uint32_t> local_vertex(ns, 0);
    std::vector<std::vector<std::uint32_t>> members(comps.size());
    std::vector<std::uint32_t> piece_of_sample(ns);
    for (std::size_t k = 0; k < ns; ++k) {
        const auto p = static_cast<std::uint32_t>(std::lower_bound(comps.begin(), comps.end(), ag.surface_component[k]) - comps.begin());
        piece_of_sample[k] = p;
        local_vertex[k] = static_cast<std::uint32_t>(members[p].size());
        members[p].push_back(static_cast<std::uint32_t>(k));
    }
    pm.local_edge.assign(ag.edges.size(), 0);
    pm.piece_of.assign(ag.edges.size(), 0);
    std::vector<std::vector<std::uint32_t>> edges_of(comps.size());
    for (std::size_t e = 0; e < ag.edges.size(); ++e) {
        const std::uint32_t p = piece_of_sample[ag.edges[e].a];  // edges never cross pieces
        pm.piece_of[e] = p;
        pm.local_edge[e] = static_cast<std::uint32_t>(edges_of[p].size());
        edges_of[p].push_back(static_cast<std::uint32_t>(e));
    }
    const double load_per_vertex = ns ? total_load_n / static_cast<double>(ns) : 0.0;
    // user point / area loads: each shared by the samples within its radius (else the nearest)
    std::vector<vec3> user_force;
    if (!opt.loads.empty()) {
        user_force.assign(ns, vec3(0));
        for (const area_load& L : opt.loads) {
            std::vector<std::uint32_t> in;
            std::size_t nearest = 0;
            double best = std::numeric_limits<double>::infinity();
            for (std::size_t k = 0; k < ns; ++k) {
                const double d = glm::length(l0.center(ag.samples[k]) - L.at);
                if (d <= L.radius_mm) in.push_back(static_cast<std::uint32_t>(k));
                if (d < best) best = d, nearest = k;
            }
            if (in.empty() && ns) in.push_back(static_cast<std::uint32_t>(nearest));
            for (const std::uint32_t k : in) user_force[k] += L.force_n / static_cast<double>(in.size());
        }
    }
    const double width = opt.beam_width_mm;  // 0: beam_model's own rule
    pm.pieces.resize(comps.size());
    for (std::size_t p = 0; p < comps.size(); ++p) {
        piece_models::piece& P = pm.pieces[p];
        P.vertex = members[p];
        P.edge = edges_of[p];
        if (P.edge.empty()) continue;  // a single sample: nothing to score
        std::vector<beam_vertex> bv;
        bv.reserve(P.vertex.size());
        for (const std::uint32_t s : P.vertex) bv.push_back({l0.center(ag.samples[s]), l0.normals[ag.samples[s]]});
        std::vector<beam_edge> be;
        be.reserve(P.edge.size());
        for (const std::uint32_t e : P.edge) {
            // knot for a beam that cannot follow its chord: the voxel half-way along the edge's path
            // (around the rim of a thin part rather than through it)
            const std::vector<std::uint32_t>& path = ag.edges[e].path;
            std::optional<beam_vertex> knot;
            if (path.size() >= 3) {
                const std::uint32_t mid = path[path.size() / 2];
                knot = beam_vertex{l0.center(mid), l0.normals[mid]};
            }
            be.push_back({local_vertex[ag.edges[e].a], local_vertex[ag.edges[e].b], ag.edges[e].solid, knot});
        }
        std::optional<force_profile> profile;
        if (opt.fixed || opt.load || !user_force.empty()) {
            force_profile fp;
            for (std::size_t i = 0; i < bv.size(); ++i) {
                if (opt.fixed && opt.fixed(bv[i].position)) fp.fixed_vertices.push_back(static_cast<std::uint32_t>(i));
                if (opt.load) fp.loads.emplace_back(static_cast<std::uint32_t>(i), opt.load(bv[i].position));
                if (!user_force.empty()) fp.loads.emplace_back(static_cast<std::uint32_t>(i), user_force[P.vertex[i]]);  // zeros keep the weight rule off
            }
            if (opt.fixed && fp.fixed_vertices.empty())
                throw no_solution("structure: the force profile fixes no abstract vertex of mesh piece " + std::to_string(comps[p]) +
                                  " (" + std::to_string(bv.size()) + " vertices), so it cannot carry loads");
            profile = std::move(fp);
        }
        beam_options bo{.thickness_mm = opt.thickness_mm, .beam_width_mm = width, .rho_min = opt.rho_min, .material = opt.material.elastic,
                        .gravity = opt.gravity, .support_fraction = opt.support_fraction, .load_per_vertex_n = load_per_vertex};
        bo.solver = opt.solver;
        try {
            P.model = std::make_unique<beam_model>(bv, be, bo, profile);
        } catch (const invalid_input& e) {
            throw invalid_input(std::string("structure: beam model of mesh piece ") + std::to_string(comps[p]) + ": " + e.what());
        }
        pm.knots += P.model->statistics().knots;
        pm.narrowed += P.model->statistics().narrowed_hubs;
    }
    pm.width_mm = width;
    for (const piece_models::piece& P : pm.pieces)
        if (P.model) pm.width_mm = std::max(pm.width_mm, P.model->beam_width());
    return pm;
}

/// Solves every piece; returns the score of every abstract edge [MPa].
[[nodiscard]] inline std::vector<double> solve_pieces(piece_models& pm, std::size_t num_edges, double feature_width_mm,
                                                 structural_step_report& rep) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<double> score(num_edges, 0.0);
    for (piece_models::piece& P : pm.pieces) {
        if (!P.model) continue;
        const std::vector<double> s = P.model->solve();
        const double to_feature = std::min(1.0, P.model->beam_width() / feature_width_mm);  // see the file comment
        for (std::size_t i = 0; i < s.size(); ++i) score[P.edge[i]] = s[i] * to_feature;
    }
    ++rep.solves;
    rep.solve_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return score;
}

/// Midpoint of an abstract edge's chord [mm] and its length [mm] (for the dart exclusion).
[[nodiscard]] inline std::pair<vec3, double> chord(const abstract_graph& ag, const shell_level& l0, std::size_t e) {
    const vec3 a = l0.center(ag.samples[ag.edges[e].a]), b = l0.center(ag.samples[ag.edges[e].b]);
    return {0.5 * (a + b), glm::length(b - a)};
}

/// Inserts up to `limit` of the candidate edges in the ranking of the file comment (score bands of
/// ratio `band`, the fewest empty path voxels `cost[e]` first within a band, then the higher score,
/// then the smaller index) with the dart exclusion; `accept(e)` can veto (and update state for)
/// each. Returns the count.
template <class Accept>
std::size_t insert_batch(std::vector<std::uint32_t> candidates, const std::vector<double>& score, const std::vector<std::uint32_t>& cost,
                         const abstract_graph& ag, const shell_level& l0, int limit, double band, Accept&& accept) {
    double top = 0;
    for (const std::uint32_t e : candidates) top = std::max(top, score[e]);
    const bool by_length = band < 1 && top > 0;  // band 1: plain score order
    std::vector<std::int64_t> b(ag.edges.size(), 0);
    if (by_length)
        for (const std::uint32_t e : candidates)
            b[e] = score[e] > 0 ? static_cast<std::int64_t>(std::floor(std::log(top / score[e]) / std::log(1 / band)))
                                : std::numeric_limits<std::int64_t>::max();
    std::stable_sort(candidates.begin(), candidates.end(), [&](std::uint32_t x, std::uint32_t y) {
        if (b[x] != b[y]) return b[x] < b[y];
        if (by_length && cost[x] != cost[y]) return cost[x] < cost[y];
        return score[x] > score[y];
    });
    std::vector<std::pair<vec3, double>> taken;
    for (const std::uint32_t e : candidates) {
        if (static_cast<int>(taken.size()) >= limit) break;
        const auto [m, len] = chord(ag, l0, e);
        bool near = false;
        for (const auto& [tm, tl] : taken) near = near || glm::length(m - tm) < 2 * tl;
        if (near || !accept(e)) continue;
        taken.emplace_back(m, len);
    }
    return taken.size();
}

}  // namespace detail

/// One STRUCTURALOPTIM step (see the file comment) on `solid` (one 0/1 flag per level-0 shell
/// voxel, updated: bridges become 1). `reinforcement` (resized to the shell) gets 1 on the voxels
/// of this step's dilated bridges (also those that were solid already); `added` (optional, sized
/// to the shell if smaller) gets 1 where a bridge made an empty voxel solid. Throws invalid_input for
/// bad options or sizes, no_solution when a piece of the mesh has no support under the force
/// profile, solver_error when the FEM fails.
template <progress_callback P = no_progress>
structural_step_report structural_step(const surface_graph& gs, const shell_level& l0, std::vector<std::uint8_t>& solid,
                                       std::vector<std::uint8_t>& reinforcement, const structure_options& opt, P&& progress = {},
                                       std::vector<std::uint8_t>* added = nullptr) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    opt.validate();
    if (solid.size() != l0.size()) throw invalid_input("structure: " + std::to_string(solid.size()) + " states for " + std::to_string(l0.size()) + " shell voxels");
    structural_step_report rep;
    rep.allowable_stress_mpa = opt.allowable_stress_mpa();
    reinforcement.assign(l0.size(), 0);
    if (added && added->size() != l0.size()) added->assign(l0.size(), 0);

    // 1. G_abstract and the beam models
    report_progress(progress, 0.0, "abstract graph");
    const abstract_graph ag = build_abstract_graph(gs, l0, solid, {.target_samples = opt.target_samples, .seed = opt.seed});
    rep.samples = ag.samples.size();
    rep.solid_edges = ag.num_solid_edges();
    rep.empty_edges = ag.edges.size() - rep.solid_edges;
    std::vector<std::uint8_t> state(ag.edges.size());
    for (std::size_t e = 0; e < ag.edges.size(); ++e) state[e] = ag.edges[e].solid ? 1 : 0;
    {
        std::vector<int> c(ag.surface_component);
        std::sort(c.begin(), c.end());
        rep.pieces = static_cast<int>(std::unique(c.begin(), c.end()) - c.begin());
    }
    rep.components_before = static_cast<int>(solid_components(ag).count);
    rep.graph_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    if (ag.edges.empty()) {
        rep.components_after = rep.components_before;
        rep.seconds = rep.graph_seconds;
        return rep;
    }
    const auto tm = clock::now();
    report_progress(progress, 0.1, "beam model");
    {
        const double solid_voxels = static_cast<double>(std::count(solid.begin(), solid.end(), std::uint8_t{1}));
        const double area_mm2 = solid_voxels * l0.geometry.spacing.x * l0.geometry.spacing.y;
        constexpr double g_mm_s2 = 9810.0;
        rep.load_n = opt.design_load_n > 0 ? opt.design_load_n : opt.load_factor * area_mm2 * opt.thickness_mm * opt.material.elastic.density * g_mm_s2;
        if (!opt.loads.empty()) {
            rep.load_n = 0;
            for (const area_load& L : opt.loads) rep.load_n += glm::length(L.force_n);
        }
    }
    detail::piece_models pm = detail::build_piece_models(ag, l0, opt, rep.load_n);
    rep.beam_width_mm = pm.width_mm;
    rep.beam_knots = pm.knots;
    rep.narrowed_hubs = pm.narrowed;
    rep.model_seconds = std::chrono::duration<double>(clock::now() - tm).count();
    const auto insert = [&](std::uint32_t e, bridge_criterion c) {
        state[e] = 1;
        rep.inserted.emplace_back(e, c);
        if (auto& m = pm.pieces[pm.piece_of[e]].model) m->set_edge_solid(pm.local_edge[e], true);
    };
    std::vector<std::uint32_t> cost(ag.edges.size(), 0);  // empty voxels on each edge's path: what its bridge lays
    for (std::size_t e = 0; e < ag.edges.size(); ++e)
        for (const std::uint32_t v : ag.edges[e].path) cost[e] += solid[v] ? 0u : 1u;
    const auto empty_edges = [&] {
        std::vector<std::uint32_t> v;
        for (std::size_t e = 0; e < ag.edges.size(); ++e)
            if (!state[e]) v.push_back(static_cast<std::uint32_t>(e));
        return v;
    };

    // 2. connect
    std::vector<double> score = detail::solve_pieces(pm, ag.edges.size(), 2 * opt.r_pattern_mm, rep);
    const auto solid_max = [&] {
        double m = 0;
        for (std::size_t e = 0; e < ag.edges.size(); ++e)
            if (state[e]) m = std::max(m, score[e]);
        return m;
    };
    rep.max_stress_mpa = solid_max();
    for (;;) {
        const graph::graph_components cc = solid_components(ag, state);
        if (static_cast<int>(cc.count) <= rep.pieces) break;
        report_progress(progress, 0.2, "connect: " + std::to_string(cc.count) + " components");
        union_find uf(ag.samples.size());
        for (std::size_t e = 0; e < ag.edges.size(); ++e)
            if (state[e]) uf.unite(ag.edges[e].a, ag.edges[e].b);
        std::vector<std::uint32_t> joining;
        for (const std::uint32_t e : empty_edges())
            if (uf.find(ag.edges[e].a) != uf.find(ag.edges[e].b)) joining.push_back(e);
        const std::size_t n = detail::insert_batch(joining, score, cost, ag, l0, opt.edges_per_solve, opt.bridge_band, [&](std::uint32_t e) {
            if (uf.find(ag.edges[e].a) == uf.find(ag.edges[e].b)) return false;  // joined by an edge of this batch
            uf.unite(ag.edges[e].a, ag.edges[e].b);
            insert(e, bridge_criterion::connect);
            return true;
        });
        rep.added_connect += n;
        score = detail::solve_pieces(pm, ag.edges.size(), 2 * opt.r_pattern_mm, rep);
    }

    // 3. force profile
    const double allowable = opt.allowable_stress_mpa();
    if (opt.force_criterion) {
        for (int s = 0;; ++s) {
            const double mx = solid_max();
            if (mx <= allowable) break;
            std::vector<std::uint32_t> cand = empty_edges();
            if (cand.empty()) break;
            {   // the empty edges around the overloaded solid ones: within two edges of their endpoints
                std::vector<std::uint8_t> near_v(ag.samples.size(), 0);
                for (std::size_t e = 0; e < ag.edges.size(); ++e)
                    if (state[e] && score[e] > allowable) near_v[ag.edges[e].a] = near_v[ag.edges[e].b] = 1;
                for (int ring = 0; ring < 2; ++ring) {
                    std::vector<std::uint8_t> next = near_v;
                    for (const abstract_edge& f : ag.edges)
                        if (near_v[f.a] || near_v[f.b]) next[f.a] = next[f.b] = 1;
                    near_v.swap(next);
                }
                std::vector<std::uint32_t> local;
                for (const std::uint32_t e : cand)
                    if (near_v[ag.edges[e].a] || near_v[ag.edges[e].b]) local.push_back(e);
                if (!local.empty()) cand.swap(local);
            }
            if (s == opt.max_force_solves) {
                rep.force_bound_hit = true;
                break;
            }
            report_progress(progress, 0.5, "force profile: max " + std::to_string(mx) + " MPa");
            // the batch shrinks with the overload, so the last bridges go in one solve at a time
            const int batch = static_cast<int>(std::clamp(std::ceil(opt.edges_per_solve * (mx / allowable - 1)), 1.0, double(opt.edges_per_solve)));
            rep.added_force += detail::insert_batch(cand, score, cost, ag, l0, batch, opt.bridge_band, [&](std::uint32_t e) {
                insert(e, bridge_criterion::force);
                return true;
            });
            score = detail::solve_pieces(pm, ag.edges.size(), 2 * opt.r_pattern_mm, rep);
        }
    }
    rep.max_stress_after_mpa = solid_max();

    // 4. geodesic criterion
    {
        vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (std::size_t v = 0; v < l0.size(); ++v) lo = glm::min(lo, l0.center(v)), hi = glm::max(hi, l0.center(v));
        const vec3 ext = hi - lo + l0.geometry.spacing;
        rep.geodesic_threshold_mm = opt.geodesic_factor * std::max({ext.x, ext.y, ext.z});
    }
    report_progress(progress, 0.8, "geodesic criterion");
    for (;;) {
        const graph::csr_graph<std::uint32_t> sg = solid_edge_graph(ag, state);
        const std::vector<std::uint32_t> cand = empty_edges();
        // one Dijkstra per distinct first endpoint (edges are sorted by (a, b) within each kind)
        std::vector<std::uint32_t> sources;
        for (const std::uint32_t e : cand) sources.push_back(ag.edges[e].a);
        std::sort(sources.begin(), sources.end());
        sources.erase(std::unique(sources.begin(), sources.end()), sources.end());
        std::vector<double> geo(ag.edges.size(), 0.0);
        std::vector<std::vector<std::uint32_t>> by_source(ag.samples.size());
        for (const std::uint32_t e : cand) by_source[ag.edges[e].a].push_back(e);
        parallel_for(0, sources.size(), [&](std::size_t i) {
            const graph::vertex_id src = sources[i];
            const graph::shortest_path_forest f = graph::dijkstra_forest(sg, std::span<const graph::vertex_id>(&src, 1));
            for (const std::uint32_t e : by_source[sources[i]]) geo[e] = f.distance[ag.edges[e].b];
        }, {.grain = 8});
        double best = -1;
        std::uint32_t pick = 0;
        rep.max_geodesic_mm = 0;
        for (const std::uint32_t e : cand) {
            rep.max_geodesic_mm = std::max(rep.max_geodesic_mm, geo[e]);
            if (geo[e] > best) best = geo[e], pick = e;
        }
        if (opt.geodesic_factor <= 0 || cand.empty() || !(best > rep.geodesic_threshold_mm)) break;
        insert(pick, bridge_criterion::geodesic);
        ++rep.added_geodesic;
    }
    rep.components_after = static_cast<int>(solid_components(ag, state).count);

    // 5. bridges: the inserted edges' voxel paths dilated by the bridge radius in G_surface
    if (!rep.inserted.empty()) {
        std::vector<graph::vertex_id> seeds;
        for (const auto& [e, c] : rep.inserted)
            for (const std::uint32_t v : ag.edges[e].path)
                if (!solid[v]) seeds.push_back(v);  // the empty runs: the pattern's own voxels need no bridge
        std::sort(seeds.begin(), seeds.end());
        seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
        const graph::shortest_path_forest near = graph::dijkstra_forest(gs.graph(), seeds);
        for (std::size_t v = 0; v < l0.size(); ++v)
            if (near.distance[v] <= opt.bridge_radius()) {
                reinforcement[v] = 1;
                if (!solid[v]) {
                    solid[v] = 1, ++rep.reinforced_voxels;
                    if (added) (*added)[v] = 1;
                }
            }
    }
    rep.seconds = std::chrono::duration<double>(clock::now() - t0).count();
    report_progress(progress, 1.0, "structure");
    return rep;
}

/// Algorithm 1 after SYNTHESIZE (see the file comment): structural steps and constrained
/// resyntheses of `r` (from syn.synthesize()) until a step inserts nothing or max_iterations steps
/// ran. r.solid ends connected per piece of the mesh; `forced` (optional) gets the reinforcement
/// voxels (every voxel of a dilated bridge, kept solid by the resyntheses) and `added` (optional)
/// those of them that were empty when their bridge was laid (state 3). Throws invalid_input for max_iterations < 1 and what structural_step throws.
template <progress_callback P = no_progress>
structure_report optimize_structure(const synthesizer& syn, synthesis_result& r, const surface_graph& gs, const structure_options& opt,
                                    int max_iterations = 30, std::vector<std::uint8_t>* forced = nullptr, P&& progress = {},
                                    std::vector<std::uint8_t>* added = nullptr) {
    using clock = std::chrono::steady_clock;
    if (max_iterations < 1) throw invalid_input("structure: max_iterations must be >= 1, got " + std::to_string(max_iterations));
    const shell_level& l0 = syn.pyramid().levels[0];
    if (r.solid.size() != l0.size()) throw invalid_input("structure: the synthesis result does not belong to this synthesizer's shell");
    structure_report rep;
    std::vector<std::uint8_t> all_forced(l0.size(), 0), step_forced;
    if (added) added->assign(l0.size(), 0);
    const std::vector<std::uint8_t> allowed(l0.size(), 1);
    const double r_pattern_voxels = opt.r_pattern_mm / l0.geometry.spacing.x;
    for (int it = 1; it <= max_iterations; ++it) {
        const auto ts = clock::now();
        const double base = static_cast<double>(it - 1) / max_iterations;
        auto sub = [&](double f, std::string_view stage) {
            report_progress(progress, base + 0.5 * f / max_iterations, "iteration " + std::to_string(it) + ": " + std::string(stage));
        };
        rep.iterations.push_back(structural_step(gs, l0, r.solid, step_forced, opt, sub, added));
        rep.structure_seconds += std::chrono::duration<double>(clock::now() - ts).count();
        for (std::size_t v = 0; v < l0.size(); ++v) all_forced[v] |= step_forced[v];
        if (rep.iterations.back().done()) {
            rep.converged = true;
            break;
        }
        if (it == max_iterations) break;  // keep the last bridges, no resynthesis after them
        const auto tr = clock::now();
        auto resub = [&](double f, std::string_view stage) {
            report_progress(progress, base + (0.5 + 0.5 * f) / max_iterations, "iteration " + std::to_string(it) + ": " + std::string(stage));
        };
        rep.resyntheses.push_back(syn.resynthesize(r, all_forced, allowed, r_pattern_voxels, static_cast<std::uint64_t>(it), resub));
        rep.resynthesis_seconds += std::chrono::duration<double>(clock::now() - tr).count();
    }
    rep.forced_voxels = static_cast<std::size_t>(std::count(all_forced.begin(), all_forced.end(), std::uint8_t{1}));
    rep.overloaded = !rep.iterations.empty() && rep.iterations.back().max_stress_after_mpa > rep.iterations.back().allowable_stress_mpa;
    if (forced) *forced = std::move(all_forced);
    report_progress(progress, 1.0, "structure");
    return rep;
}

}  // namespace fabsynth::surface_pattern
