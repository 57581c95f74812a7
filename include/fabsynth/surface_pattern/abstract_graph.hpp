// SPDX-License-Identifier: MIT
#pragma once
/// @file abstract_graph.hpp  The surface voxel graph G_surface and the abstract pattern graph
/// G_abstract = (S, F) of structurally-sound-patterns.md §5.1 (GENERATESURFACEGRAPH,
/// GENERATEABSTRACTGRAPH, Algorithm 5 CONNECTSAMPLES), with the queries the reinforcement of §5.2
/// needs (components under solid edges, geodesics through solid edges for §5.2.2).
///
/// Usage:
///   const auto& l0 = pyramid.levels[0];
///   auto gs = fabsynth::surface_pattern::build_surface_graph(l0);            // once per shell
///   auto ag = fabsynth::surface_pattern::build_abstract_graph(gs, l0, solid, {.target_samples = 1000});
///   for (const auto& f : ag.edges) use(f.a, f.b, f.solid, f.path, f.length_mm);
///   auto cc = fabsynth::surface_pattern::solid_components(ag);               // cc.count pieces
///   auto sg = fabsynth::surface_pattern::solid_edge_graph(ag);               // many geodesic queries
///   double d = fabsynth::graph::geodesic(sg, a, b).length;                   // = geodesic_in_solid(ag, a, b).length
///
/// G_surface: vertex i = shell voxel i of the level (voxels sorted by grid index), edges between
/// 26-neighbours weighted by the centre distance in mm (graph/from_voxels.hpp), and its connected
/// components (the pieces of the mesh). G_solid is G_surface restricted to the solid voxels.
///
/// build_abstract_graph:
/// 1. Samples S: Poisson-disk samples of the solid voxel centres (sampling/poisson_disk.hpp
///    poisson_disk_count, priorities hash64(seed, voxel index)), the radius searched until the
///    count is within relative_tolerance of target_samples (clamped to the number of solid
///    voxels), or the closest count found in max_evaluations radii. Voxel centres lie on a lattice
///    (distances sqrt(k) h), so the count is a step function of the radius: with a radius of only
///    a few voxels (few solid voxels per sample) it can miss the target by more than the tolerance
///    (e.g. 139 -> 133 -> 115 -> 95 for radii 2.5-3.2 voxels); at the paper's scale (1000 samples
///    at 256^3) the steps are a few percent. Euclidean disks can leave a
///    small solid component without a sample, and it would then vanish from the graph: every
///    26-connected component of solid voxels (component of G_solid) without a sample gets its first
///    voxel (smallest index) as an extra sample. Those extra samples may lie closer than the radius
///    to other samples. S is sorted by voxel index; sample k is tree k of the forests below.
/// 2. Algorithm 5 steps 1-2: the shortest-path forest from S in G_solid (graph/shortest_paths.hpp,
///    its documented tie rule); every pair of trees joined by an edge of G_solid gives one solid
///    abstract edge (graph/forest_adjacency.hpp). Since every solid component holds a sample, the
///    trees cover all solid voxels and the samples under solid edges have exactly the components of
///    the solid voxels.
/// 3. Steps 3-4: the forest extended through G_surface (solid voxels keep their trees); every pair
///    of trees joined by an edge of G_surface and not already joined by a solid edge gives one empty
///    abstract edge.
/// One edge per tree pair: of all graph edges x-y joining trees a < b, the one minimising
/// dist(x) + w(x, y) + dist(y) (the root-to-root path length), ties to the smaller x, then the
/// smaller y (forest_adjacency's rule). The edge's path is root(a) ... x y ... root(b), every
/// consecutive pair a G_surface edge; length_mm = dist(x) + w + dist(y), the sum of the path's edge
/// weights (each tree distance summed from its root along the path). Solid edges' paths contain
/// only solid voxels; the touching edge x-y of an empty edge has at least one empty endpoint (a
/// solid-solid contact between the trees would have made the pair solid). Edges: all solid edges
/// sorted by (a, b), then all empty edges sorted by (a, b). Edges never cross components of G_surface (no graph edge does). A component of
/// G_surface without any solid voxel gets no sample and no edge (the pattern has nothing there to
/// reinforce; the surface piece simply stays empty). With no solid voxel at all the graph is empty.
///
/// Everything is deterministic and identical for any thread count (the building blocks are).
/// Cost: G_surface O(V log V + 26 V); the abstract graph O(k V log S) for the k Poisson radii tried,
/// plus two Dijkstra passes O(E log V) and the recorded paths; memory O(V + E_surface).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/core/union_find.hpp"
#include "fabsynth/graph/components.hpp"
#include "fabsynth/graph/csr_graph.hpp"
#include "fabsynth/graph/forest_adjacency.hpp"
#include "fabsynth/graph/from_voxels.hpp"
#include "fabsynth/graph/shortest_paths.hpp"
#include "fabsynth/sampling/poisson_disk.hpp"
#include "fabsynth/surface_pattern/shell.hpp"

namespace fabsynth::surface_pattern {

/// G_surface: 26-neighbour graph of the shell voxels of one level (vertex i = shell voxel i),
/// Euclidean weights in mm; built once per shell.
struct surface_graph {
    graph::voxel_graph voxels;          ///< graph, voxel coordinates and linear indices per vertex
    graph::graph_components components; ///< connected components of G_surface (the mesh's pieces)

    [[nodiscard]] std::size_t size() const noexcept { return voxels.size(); }
    [[nodiscard]] const graph::csr_graph<>& graph() const noexcept { return voxels.graph; }
};

/// G_surface of a shell level (normally level 0). Throws invalid_input for an empty level or
/// voxels that are not strictly sorted by grid index (not a shell_level built by this module).
[[nodiscard]] inline surface_graph build_surface_graph(const shell_level& l0) {
    if (l0.voxels.empty()) throw invalid_input("surface graph: the shell level has no voxel");
    surface_graph g;
    g.voxels = graph::from_voxels(l0.geometry, l0.voxels);
    for (std::size_t i = 0; i < l0.size(); ++i)
        if (g.voxels.voxels[i] != l0.voxels[i])
            throw invalid_input("surface graph: shell voxel " + std::to_string(i) + " is out of grid-index order");
    g.components = graph::connected_components(g.voxels.graph);
    return g;
}

/// Options of build_abstract_graph.
struct abstract_options {
    std::size_t target_samples = 1000;  ///< wanted |S| (paper: 1000; §5.1 "between 500 and 1000"), >= 1
    std::uint64_t seed = 1;             ///< Poisson-disk priorities hash64(seed, voxel index)
    double relative_tolerance = 0.05;   ///< radius search stops when |count - target| <= tolerance * target
    int max_evaluations = 40;           ///< Poisson radii tried at most (one greedy pass each), >= 1
};

/// One abstract edge f in F.
struct abstract_edge {
    std::uint32_t a = 0, b = 0;       ///< indices into abstract_graph::samples, a < b
    bool solid = false;               ///< rho(f): true = the trees touched through solid voxels (step 2), false = through G_surface (step 4)
    std::vector<std::uint32_t> path;  ///< shell-voxel indices from samples[a] to samples[b] inclusive (root-to-root through the touching edge)
    double length_mm = 0;             ///< sum of the path's edge weights (mm)
};

/// G_abstract = (S, F) with rho.
struct abstract_graph {
    std::vector<std::uint32_t> samples;    ///< S: shell-voxel indices of the abstract vertices (solid voxels), increasing
    std::vector<abstract_edge> edges;      ///< F: solid edges by (a, b), then empty edges by (a, b)
    std::vector<int> surface_component;    ///< per sample: its component of G_surface
    double sample_radius_mm = 0;           ///< the Poisson radius found by the search (0 if no solid voxel)
    std::size_t extra_samples = 0;         ///< samples added for solid components the disks missed (the last step of sampling)

    [[nodiscard]] std::size_t num_solid_edges() const noexcept {
        return static_cast<std::size_t>(std::count_if(edges.begin(), edges.end(), [](const abstract_edge& e) { return e.solid; }));
    }
};

namespace detail {

/// The solid samples in G_surface's vertex ids, one per solid component at least (see the file comment).
[[nodiscard]] inline std::vector<graph::vertex_id> abstract_samples(const surface_graph& g, const shell_level& l0,
                                                                   std::span<const std::uint8_t> solid, std::size_t solid_count,
                                                                   const abstract_options& opt, abstract_graph& out) {
    std::vector<vec3> centres(l0.size());
    for (std::size_t i = 0; i < l0.size(); ++i) centres[i] = l0.center(i);
    const auto found = sampling::poisson_disk_count(centres, std::min(opt.target_samples, solid_count),
                                                    {.seed = opt.seed,
                                                     .mask = solid,
                                                     .relative_tolerance = opt.relative_tolerance,
                                                     .max_evaluations = opt.max_evaluations});
    out.sample_radius_mm = found.radius;
    std::vector<graph::vertex_id> s(found.indices.begin(), found.indices.end());
    // Every component of G_solid keeps a sample: add the first voxel of each one the disks missed.
    const graph::graph_components cc = graph::connected_components(g.graph(), solid);
    std::vector<std::uint8_t> has(cc.count, 0);
    for (const graph::vertex_id v : s) has[cc.label[v]] = 1;
    for (std::size_t v = 0; v < l0.size(); ++v)
        if (solid[v] && !has[cc.label[v]]) {
            has[cc.label[v]] = 1;
            s.push_back(static_cast<graph::vertex_id>(v));
            ++out.extra_samples;
        }
    std::sort(s.begin(), s.end());
    return s;
}

inline void add_edges(abstract_graph& out, std::vector<graph::tree_adjacency>& adj, bool solid) {
    for (graph::tree_adjacency& t : adj) {
        abstract_edge e;
        e.a = t.tree_u, e.b = t.tree_v, e.solid = solid;
        e.path.assign(t.path.begin(), t.path.end());
        e.length_mm = t.length;
        out.edges.push_back(std::move(e));
    }
}

}  // namespace detail

/// G_abstract of a solid/empty pattern on the shell (see the file comment).
/// @param g      build_surface_graph(l0)
/// @param l0     the shell level the pattern lives on (level 0)
/// @param solid  one flag per shell voxel, 0 = empty, 1 = solid
/// Throws invalid_input if g does not belong to l0, solid has the wrong size or a flag other than
/// 0/1, target_samples is 0, relative_tolerance is negative or not finite, or max_evaluations < 1.
[[nodiscard]] inline abstract_graph build_abstract_graph(const surface_graph& g, const shell_level& l0, std::span<const std::uint8_t> solid,
                                                         const abstract_options& opt = {}) {
    if (g.size() != l0.size() || g.voxels.geometry != l0.geometry || (l0.size() > 0 && g.voxels.voxels.back() != l0.voxels.back()))
        throw invalid_input("abstract graph: the surface graph (" + std::to_string(g.size()) + " vertices) was not built from this shell level (" +
                            std::to_string(l0.size()) + " voxels)");
    if (solid.size() != l0.size())
        throw invalid_input("abstract graph: " + std::to_string(solid.size()) + " solid flags for " + std::to_string(l0.size()) + " shell voxels");
    if (opt.target_samples == 0) throw invalid_input("abstract graph: target_samples must be >= 1");
    if (!(std::isfinite(opt.relative_tolerance) && opt.relative_tolerance >= 0))
        throw invalid_input("abstract graph: relative_tolerance must be finite and >= 0");
    if (opt.max_evaluations < 1) throw invalid_input("abstract graph: max_evaluations must be >= 1");
    std::size_t solid_count = 0;
    for (std::size_t i = 0; i < solid.size(); ++i) {
        if (solid[i] > 1)
            throw invalid_input("abstract graph: solid flag " + std::to_string(i) + " is " + std::to_string(solid[i]) + ", expected 0 or 1");
        solid_count += solid[i];
    }
    abstract_graph out;
    if (solid_count == 0) return out;
    const std::vector<graph::vertex_id> samples = detail::abstract_samples(g, l0, solid, solid_count, opt, out);
    out.samples.assign(samples.begin(), samples.end());
    out.surface_component.resize(samples.size());
    for (std::size_t k = 0; k < samples.size(); ++k) out.surface_component[k] = static_cast<int>(g.components.label[samples[k]]);
    // Algorithm 5: steps 1-2 in G_solid, steps 3-4 in G_surface.
    const graph::shortest_path_forest in_solid = graph::dijkstra_forest(g.graph(), samples, solid);
    std::vector<graph::tree_adjacency> solid_adj = graph::forest_adjacency(g.graph(), in_solid, solid);
    const graph::shortest_path_forest in_surface = graph::extend_forest(g.graph(), in_solid);
    std::vector<graph::tree_adjacency> empty_adj = graph::forest_adjacency(g.graph(), in_surface, {}, {.skip = solid_adj});
    out.edges.reserve(solid_adj.size() + empty_adj.size());
    detail::add_edges(out, solid_adj, true);
    detail::add_edges(out, empty_adj, false);
    return out;
}

namespace detail {

/// Per-edge state: the override if given (one flag per edge), else the edge's own.
[[nodiscard]] inline bool edge_is_solid(const abstract_graph& ag, std::span<const std::uint8_t> edge_solid, std::size_t e) noexcept {
    return edge_solid.empty() ? ag.edges[e].solid : edge_solid[e] != 0;
}

inline void check_edge_flags(const abstract_graph& ag, std::span<const std::uint8_t> edge_solid, const char* who) {
    if (!edge_solid.empty() && edge_solid.size() != ag.edges.size())
        throw invalid_input(std::string(who) + ": " + std::to_string(edge_solid.size()) + " edge flags for " + std::to_string(ag.edges.size()) +
                            " abstract edges");
}

}  // namespace detail

/// Components of the samples under solid edges only (§5.2: the pattern's pieces as the abstract
/// graph sees them). label[k] is the component of sample k, numbered in the order of their smallest
/// sample index. `edge_solid` optionally overrides the edge states (one flag per edge, != 0 =
/// solid), e.g. during the reinforcement; empty = the edges' own `solid`. Throws invalid_input for
/// a flag span of the wrong size.
[[nodiscard]] inline graph::graph_components solid_components(const abstract_graph& ag, std::span<const std::uint8_t> edge_solid = {}) {
    detail::check_edge_flags(ag, edge_solid, "solid_components");
    const std::size_t n = ag.samples.size();
    union_find uf(n);
    for (std::size_t e = 0; e < ag.edges.size(); ++e)
        if (detail::edge_is_solid(ag, edge_solid, e)) uf.unite(ag.edges[e].a, ag.edges[e].b);
    graph::graph_components r;
    r.label.assign(n, graph::no_vertex);
    for (std::size_t k = 0; k < n; ++k) {
        const auto root = static_cast<std::size_t>(uf.find(static_cast<std::uint32_t>(k)));  // the set's smallest index: labelled first
        if (root == k) r.label[k] = static_cast<graph::vertex_id>(r.count++), r.sizes.push_back(0);
        else r.label[k] = r.label[root];
        ++r.sizes[r.label[k]];
    }
    return r;
}

/// The abstract graph's solid edges as a CSR graph on the samples (vertex k = sample k), weights
/// length_mm, payload = index of the abstract edge. `edge_solid` as for solid_components. Build it
/// once for many §5.2.2 queries (graph::geodesic, graph::dijkstra_forest on it).
[[nodiscard]] inline graph::csr_graph<std::uint32_t> solid_edge_graph(const abstract_graph& ag, std::span<const std::uint8_t> edge_solid = {}) {
    detail::check_edge_flags(ag, edge_solid, "solid_edge_graph");
    std::vector<graph::edge_record<std::uint32_t>> edges;
    for (std::size_t e = 0; e < ag.edges.size(); ++e)
        if (detail::edge_is_solid(ag, edge_solid, e))
            edges.push_back({ag.edges[e].a, ag.edges[e].b, ag.edges[e].length_mm, static_cast<std::uint32_t>(e)});
    return graph::build_csr(ag.samples.size(), edges);
}

/// §5.2.2 geodesic criterion: the shortest path between samples a and b through solid abstract
/// edges weighted by length_mm (vertices = sample indices from a to b); length +inf and no vertices
/// if they are not connected by solid edges. `edge_solid` as for solid_components. Builds the solid
/// graph each call: for many queries use solid_edge_graph once and graph::geodesic. Throws
/// invalid_input for a sample index out of range.
[[nodiscard]] inline graph::geodesic_path geodesic_in_solid(const abstract_graph& ag, std::uint32_t a, std::uint32_t b,
                                                            std::span<const std::uint8_t> edge_solid = {}) {
    return graph::geodesic(solid_edge_graph(ag, edge_solid), a, b);
}

}  // namespace fabsynth::surface_pattern
