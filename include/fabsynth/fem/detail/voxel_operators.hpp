// SPDX-License-Identifier: MIT
#pragma once
/// @file voxel_operators.hpp  Node grids, the matrix-free voxel operator, 27-point block stencils
/// and grid transfers (internal to fem/voxel.hpp).
///
/// Sparse storage: every level keeps only its active nodes (node_set: those that carry stiffness),
/// numbered in box order (x fastest), and vectors hold 3 doubles per active node; the fine level
/// keeps only its solid voxels. The bounding box costs one int32 per node (and per voxel on the
/// fine level) for the lookups. Every operator works node by node (each output node gathers from
/// its neighbours) or by parity classes of voxels, so parallel loops write disjoint data and the
/// result is bit-identical for any thread count.
///
/// DOF states: free (0), fixed by the user (1: displacement 0) or inactive (2: no stiffness, e.g.
/// touched only by void voxels). Operators act as the identity on non-free DOFs, and every vector
/// the solvers produce is 0 there.
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/detail/krylov.hpp"
#include "fabsynth/fem/detail/voxel_element.hpp"

namespace fabsynth::fem::detail {

inline constexpr std::uint8_t dof_free = 0, dof_fixed = 1, dof_inactive = 2;

[[nodiscard]] inline int wrap_index(int i, int n) noexcept {
    i %= n;
    return i < 0 ? i + n : i;
}

/// A box of nodes; periodic grids wrap around in every axis.
struct node_grid {
    ivec3 n{0};
    bool periodic = false;

    [[nodiscard]] std::size_t count() const noexcept {
        return static_cast<std::size_t>(n.x) * static_cast<std::size_t>(n.y) * static_cast<std::size_t>(n.z);
    }
    [[nodiscard]] std::size_t index(int i, int j, int k) const noexcept {
        return static_cast<std::size_t>(i) +
               static_cast<std::size_t>(n.x) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n.y) * static_cast<std::size_t>(k));
    }
    [[nodiscard]] ivec3 coords(std::size_t idx) const noexcept {
        const auto nx = static_cast<std::size_t>(n.x), ny = static_cast<std::size_t>(n.y);
        return {static_cast<int>(idx % nx), static_cast<int>((idx / nx) % ny), static_cast<int>(idx / (nx * ny))};
    }
    /// Index of the node at unwrapped coordinates p, or -1 outside a non-periodic grid.
    [[nodiscard]] std::int64_t at(ivec3 p) const noexcept {
        for (int a = 0; a < 3; ++a) {
            if (periodic) p[a] = wrap_index(p[a], n[a]);
            else if (p[a] < 0 || p[a] >= n[a]) return -1;
        }
        return static_cast<std::int64_t>(index(p.x, p.y, p.z));
    }
};

/// Calls f(a, c, e) for each voxel c (linear index e) that has node p as its local corner a,
/// wrapping periodic axes and skipping voxels outside a non-periodic grid; a ascends 0..7.
template <class F>
void for_each_voxel_around_node(const ivec3& cells, const node_grid& nodes, const ivec3& p, F&& f) {
    for (int a = 0; a < 8; ++a) {
        ivec3 c = p - ivec3(voxel_corner[a][0], voxel_corner[a][1], voxel_corner[a][2]);
        bool inside = true;
        for (int k = 0; k < 3; ++k) {
            if (nodes.periodic) c[k] = wrap_index(c[k], cells[k]);
            else if (c[k] < 0 || c[k] >= cells[k]) inside = false;
        }
        if (!inside) continue;
        const std::size_t e = static_cast<std::size_t>(c.x) +
                              static_cast<std::size_t>(cells.x) * (static_cast<std::size_t>(c.y) + static_cast<std::size_t>(cells.y) * static_cast<std::size_t>(c.z));
        f(a, c, e);
    }
}

/// The active nodes of a node box (those that carry stiffness), numbered compactly in box order.
/// Vectors of a level hold 3 doubles per active node; the box itself costs one int32 per node
/// (the compact number, -1 = inactive), which is what the sparse grids of the surface patterns
/// (5% of their bounding box active) can afford where 0.8 KB per box node could not.
struct node_set {
    node_grid box;
    std::vector<std::int32_t> index;  ///< per box node: compact number or -1
    std::vector<ivec3> pos;           ///< per active node: box coordinates (wrapped on periodic grids)

    [[nodiscard]] std::size_t count() const noexcept { return pos.size(); }
    /// Compact number of the node at unwrapped coordinates p, or -1 (inactive / outside).
    [[nodiscard]] std::int32_t at(const ivec3& p) const noexcept {
        const std::int64_t b = box.at(p);
        return b < 0 ? -1 : index[static_cast<std::size_t>(b)];
    }
    /// The nodes of `box` for which active(box index) holds.
    template <class Pred>
    [[nodiscard]] static node_set select(const node_grid& box, Pred&& active) {
        node_set s;
        s.box = box;
        const std::size_t n = box.count();
        if (n > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
            throw invalid_input("voxel FEM: more than 2^31 nodes");
        s.index.assign(n, -1);
        std::vector<std::uint8_t> on(n, 0);
        parallel_for(0, n, [&](std::size_t b) { on[b] = active(b) ? 1 : 0; }, {.grain = 4096});
        std::size_t m = 0;
        for (std::size_t b = 0; b < n; ++b) m += on[b];
        s.pos.resize(m);
        std::int32_t next = 0;
        for (std::size_t b = 0; b < n; ++b)
            if (on[b]) {
                s.pos[static_cast<std::size_t>(next)] = box.coords(b);
                s.index[b] = next++;
            }
        return s;
    }
};

/// Stiffness of a grid of identical box voxels, each scaled by a per-voxel factor (0 = void),
/// applied without assembling: y_n = sum over the <= 8 solid voxels at node n of s_e K_e[n rows] u_e.
/// Only solid voxels and active nodes (those touching a solid voxel) are stored and visited.
struct voxel_operator {
    ivec3 cells{0};
    node_grid nodes;                         ///< the node box
    const voxel_element* element = nullptr;
    std::vector<std::int32_t> voxel_index;   ///< per box voxel: solid voxel number or -1
    std::vector<double> scale;               ///< per solid voxel (> 0)
    std::vector<std::array<std::int32_t, 8>> corners;  ///< per solid voxel: active node numbers (hex8 order)
    std::array<std::vector<std::int32_t>, 8> color;    ///< solid voxels by parity class (i%2, j%2, k%2), ascending
    bool seam = false;                       ///< periodic with an odd count > 1: classes share nodes across the seam
    node_set active;
    std::vector<std::uint8_t> state;         ///< per active DOF (3 per active node)

    /// Stiffness factor of the voxel at box coordinates c (0 for void).
    [[nodiscard]] double scale_at(const ivec3& c) const noexcept {
        const std::int32_t v = voxel_index[static_cast<std::size_t>(c.x) +
                                           static_cast<std::size_t>(cells.x) * (static_cast<std::size_t>(c.y) + static_cast<std::size_t>(cells.y) * static_cast<std::size_t>(c.z))];
        return v < 0 ? 0.0 : scale[static_cast<std::size_t>(v)];
    }
    /// Calls f(a, v) for the solid voxels v (numbers) at active node n, n being their local corner a.
    template <class F>
    void for_each_voxel_at_node(std::size_t n, F&& f) const {
        for_each_voxel_around_node(cells, nodes, active.pos[n], [&](int a, ivec3, std::size_t e) {
            const std::int32_t v = voxel_index[e];
            if (v >= 0) f(a, static_cast<std::size_t>(v));
        });
    }

    /// y = A x (identity on non-free DOFs). Voxel by voxel (one 24x24 product each) in 8 passes,
    /// one per parity class: voxels of one class share no node, so each pass runs in parallel
    /// without races and every node sums its voxels in the same order for any thread count.
    /// (Periodic axes with an odd voxel count > 1 break the class property across the seam;
    /// those grids run single-threaded.)
    void apply(const std::vector<double>& x, std::vector<double>& y) const {
        parallel_for(0, y.size(), [&](std::size_t i) { y[i] = 0.0; }, {.grain = 16384});
        const unsigned threads = seam ? 1u : 0u;
        for (const std::vector<std::int32_t>& cls : color) {
            parallel_for(0, cls.size(), [&](std::size_t i) {
                const auto v = static_cast<std::size_t>(cls[i]);
                const std::array<std::int32_t, 8>& vn = corners[v];
                Eigen::Matrix<double, 24, 1> ue, fe;
                for (int b = 0; b < 8; ++b)
                    for (int d = 0; d < 3; ++d) ue(3 * b + d) = x[3 * static_cast<std::size_t>(vn[static_cast<std::size_t>(b)]) + static_cast<std::size_t>(d)];
                fe.noalias() = element->K * ue;
                const double s = scale[v];
                for (int b = 0; b < 8; ++b)
                    for (int d = 0; d < 3; ++d) y[3 * static_cast<std::size_t>(vn[static_cast<std::size_t>(b)]) + static_cast<std::size_t>(d)] += s * fe(3 * b + d);
            }, {.grain = 256, .threads = threads});
        }
        parallel_for(0, y.size(), [&](std::size_t i) {
            if (state[i] != dof_free) y[i] = x[i];
        }, {.grain = 16384});
    }
    /// Diagonal of A (1 on non-free DOFs).
    [[nodiscard]] std::vector<double> diagonal() const {
        std::vector<double> diag(3 * active.count(), 0.0);
        parallel_for(0, active.count(), [&](std::size_t n) {
            for_each_voxel_at_node(n, [&](int a, std::size_t v) {
                for (int d = 0; d < 3; ++d) diag[3 * n + static_cast<std::size_t>(d)] += scale[v] * element->K(3 * a + d, 3 * a + d);
            });
            for (int d = 0; d < 3; ++d)
                if (state[3 * n + static_cast<std::size_t>(d)] != dof_free) diag[3 * n + static_cast<std::size_t>(d)] = 1.0;
        }, {.grain = 256});
        return diag;
    }
};

/// The operator of a voxel grid of `cells` voxels with stiffness factors `box_scale` (per box
/// voxel, x-fastest, 0 = void) and the element `el` (which must outlive it). Node box: cells + 1
/// nodes per axis, or cells on periodic grids. `box_state` (3 per box node: free / fixed) gives
/// the user's fixed DOFs; nodes without a solid voxel are dropped. O(solid voxels + box nodes).
[[nodiscard]] inline voxel_operator make_voxel_operator(const ivec3& cells, bool periodic, const std::vector<double>& box_scale, const voxel_element& el,
                                                        const std::vector<std::uint8_t>& box_state) {
    voxel_operator op;
    op.cells = cells;
    op.nodes = {periodic ? cells : cells + 1, periodic};
    op.element = &el;
    const std::size_t nv = box_scale.size();
    if (nv > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) throw invalid_input("voxel FEM: more than 2^31 voxels");
    op.voxel_index.assign(nv, -1);
    std::int32_t solid = 0;
    for (std::size_t e = 0; e < nv; ++e)
        if (box_scale[e] != 0.0) op.voxel_index[e] = solid++;
    op.scale.resize(static_cast<std::size_t>(solid));
    std::vector<ivec3> pos(static_cast<std::size_t>(solid));  // per solid voxel: its box coordinates
    const node_grid vox{cells, false};
    for (std::size_t e = 0; e < nv; ++e)
        if (const std::int32_t v = op.voxel_index[e]; v >= 0) {
            op.scale[static_cast<std::size_t>(v)] = box_scale[e];
            pos[static_cast<std::size_t>(v)] = vox.coords(e);
        }
    op.active = node_set::select(op.nodes, [&](std::size_t b) {
        bool any = false;
        for_each_voxel_around_node(cells, op.nodes, op.nodes.coords(b), [&](int, ivec3, std::size_t e) { any = any || box_scale[e] != 0.0; });
        return any;
    });
    op.corners.resize(op.scale.size());
    parallel_for(0, op.scale.size(), [&](std::size_t v) {
        const ivec3 c = pos[v];
        for (int b = 0; b < 8; ++b)
            op.corners[v][static_cast<std::size_t>(b)] = op.active.at(c + ivec3(voxel_corner[static_cast<std::size_t>(b)][0], voxel_corner[static_cast<std::size_t>(b)][1],
                                                                                voxel_corner[static_cast<std::size_t>(b)][2]));
    }, {.grain = 4096});
    for (std::size_t v = 0; v < op.scale.size(); ++v) {
        const ivec3 c = pos[v];
        op.color[static_cast<std::size_t>((c.x & 1) | ((c.y & 1) << 1) | ((c.z & 1) << 2))].push_back(static_cast<std::int32_t>(v));
    }
    for (int a = 0; a < 3; ++a) op.seam = op.seam || (periodic && cells[a] % 2 == 1 && cells[a] > 1);
    op.state.assign(3 * op.active.count(), dof_free);
    for (std::size_t n = 0; n < op.active.count(); ++n) {
        const ivec3 p = op.active.pos[n];
        const std::size_t b = op.nodes.index(p.x, p.y, p.z);
        for (int d = 0; d < 3; ++d) op.state[3 * n + static_cast<std::size_t>(d)] = box_state[3 * b + static_cast<std::size_t>(d)] == dof_fixed ? dof_fixed : dof_free;
    }
    return op;
}

/// Slot of neighbour offset o in {-1,0,1}^3 within a 27-point stencil.
[[nodiscard]] constexpr int stencil_slot(int ox, int oy, int oz) noexcept { return (ox + 1) + 3 * (oy + 1) + 9 * (oz + 1); }

/// Assembled operator in 27-point block-stencil form over the active nodes of a level: per node,
/// 27 row-major 3x3 blocks coupling it to the nodes at offsets {-1,0,1}^3 (243 doubles) and the
/// numbers of those neighbours (-1 = inactive or outside). On periodic grids with fewer than 3
/// nodes along an axis several slots name the same node; their blocks simply add up.
struct stencil_operator {
    node_set nodes;
    std::vector<std::int32_t> nbr;  ///< 27 per node
    std::vector<double> S;          ///< 243 per node
    std::vector<std::uint8_t> state;

    [[nodiscard]] double* block(std::size_t node, int slot) noexcept { return S.data() + 243 * node + 9 * static_cast<std::size_t>(slot); }
    [[nodiscard]] const double* block(std::size_t node, int slot) const noexcept {
        return S.data() + 243 * node + 9 * static_cast<std::size_t>(slot);
    }
    /// Allocates zero blocks, free states and the neighbour table for `active`.
    void reset(node_set active) {
        nodes = std::move(active);
        const std::size_t n = nodes.count();
        S.assign(243 * n, 0.0);
        state.assign(3 * n, dof_free);
        nbr.resize(27 * n);
        parallel_for(0, n, [&](std::size_t i) {
            const ivec3 p = nodes.pos[i];
            for (int slot = 0; slot < 27; ++slot) nbr[27 * i + static_cast<std::size_t>(slot)] = nodes.at(p + ivec3(slot % 3 - 1, (slot / 3) % 3 - 1, slot / 9 - 1));
        }, {.grain = 1024});
    }

    void apply(const std::vector<double>& x, std::vector<double>& y) const {
        parallel_for(0, nodes.count(), [&](std::size_t n) {
            double acc[3] = {0, 0, 0};
            const double* B = block(n, 0);
            const std::int32_t* nb = nbr.data() + 27 * n;
            for (int slot = 0; slot < 27; ++slot, B += 9) {
                if (nb[slot] < 0) continue;
                const double* xm = x.data() + 3 * static_cast<std::size_t>(nb[slot]);
                for (int r = 0; r < 3; ++r) acc[r] += B[3 * r] * xm[0] + B[3 * r + 1] * xm[1] + B[3 * r + 2] * xm[2];
            }
            for (int d = 0; d < 3; ++d) {
                const std::size_t dof = 3 * n + static_cast<std::size_t>(d);
                y[dof] = state[dof] == dof_free ? acc[d] : x[dof];
            }
        }, {.grain = 512});
    }
    [[nodiscard]] std::vector<double> diagonal() const {
        std::vector<double> diag(3 * nodes.count(), 1.0);
        for (std::size_t n = 0; n < nodes.count(); ++n)
            for (int d = 0; d < 3; ++d)
                if (state[3 * n + static_cast<std::size_t>(d)] == dof_free) diag[3 * n + static_cast<std::size_t>(d)] = block(n, 13)[4 * d];
        return diag;
    }
    /// Marks DOFs with no stiffness (diagonal <= tiny * largest) inactive, then turns every
    /// non-free DOF's row and column into the identity.
    void apply_mask() {
        double dmax = 0;
        for (std::size_t n = 0; n < nodes.count(); ++n)
            for (int d = 0; d < 3; ++d) dmax = std::max(dmax, block(n, 13)[4 * d]);
        for (std::size_t n = 0; n < nodes.count(); ++n)
            for (int d = 0; d < 3; ++d) {
                auto& s = state[3 * n + static_cast<std::size_t>(d)];
                // Relative 1e-13: a DOF whose stiffness is that small carries nothing (round-off).
                if (s == dof_free && !(block(n, 13)[4 * d] > 1e-13 * dmax)) s = dof_inactive;
            }
        parallel_for(0, nodes.count(), [&](std::size_t n) {
            for (int slot = 0; slot < 27; ++slot) {
                const std::int32_t m = nbr[27 * n + static_cast<std::size_t>(slot)];
                double* B = block(n, slot);
                if (m < 0) {
                    std::fill(B, B + 9, 0.0);
                    continue;
                }
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c)
                        if (state[3 * n + static_cast<std::size_t>(r)] != dof_free || state[3 * static_cast<std::size_t>(m) + static_cast<std::size_t>(c)] != dof_free)
                            B[3 * r + c] = 0.0;
            }
            for (int d = 0; d < 3; ++d)
                if (state[3 * n + static_cast<std::size_t>(d)] != dof_free) block(n, 13)[4 * d] = 1.0;
        }, {.grain = 256});
    }
};

/// Assembles the stencil over the active nodes `active` of a voxel grid of `cells` voxels whose
/// voxel matrices are given by rows(e, a, any) = the 3 x 24 rows of box voxel e's matrix belonging
/// to its local node a (any = false for a void voxel). Node-wise, so deterministic.
template <class Rows>
stencil_operator assemble_stencil(const ivec3& cells, node_set active, Rows&& rows) {
    stencil_operator op;
    op.reset(std::move(active));
    parallel_for(0, op.nodes.count(), [&](std::size_t n) {
        for_each_voxel_around_node(cells, op.nodes.box, op.nodes.pos[n], [&](int a, ivec3, std::size_t e) {
            const ivec3 off(voxel_corner[a][0], voxel_corner[a][1], voxel_corner[a][2]);
            bool any = false;
            const Eigen::Matrix<double, 3, 24> R = rows(e, a, any);
            if (!any) return;
            for (int b = 0; b < 8; ++b) {
                // Unwrapped offset from node p to corner b of the voxel.
                const int slot = stencil_slot(voxel_corner[b][0] - off.x, voxel_corner[b][1] - off.y, voxel_corner[b][2] - off.z);
                double* B = op.block(n, slot);
                for (int r = 0; r < 3; ++r)
                    for (int cc = 0; cc < 3; ++cc) B[3 * r + cc] += R(r, 3 * b + cc);
            }
        });
    }, {.grain = 128});
    return op;
}

/// Coarse parents of a fine node along one axis: count, wrapped coarse indices, weights.
struct parents1d {
    int count = 0;
    int c[2] = {0, 0};
    double w[2] = {0, 0};
};

/// Grid transfer along one axis. Coarse node I sits on fine node 2I; a fine node between two
/// coarse ones takes half of each. Non-periodic axes have nf = 2 nc - 1 nodes. Periodic axes have
/// nc = ceil(nf / 2) coarse nodes; when nf is odd the interval that closes the period (fine
/// nf-1 -> fine 0) has no fine node inside, so odd periodic grids still coarsen (15 -> 8 -> 4).
struct axis_transfer {
    int nf = 0, nc = 0;
    bool periodic = false;
    std::vector<parents1d> up;     ///< per fine node
    std::vector<std::array<int, 3>> child;      ///< per coarse node: fine children
    std::vector<std::array<double, 3>> child_w; ///< and their weights
    std::vector<int> nchild;

    axis_transfer() = default;
    axis_transfer(int fine_nodes, bool per) : nf(fine_nodes), periodic(per) {
        nc = periodic ? (nf + 1) / 2 : (nf - 1) / 2 + 1;
        up.resize(static_cast<std::size_t>(nf));
        child.assign(static_cast<std::size_t>(nc), {0, 0, 0});
        child_w.assign(static_cast<std::size_t>(nc), {0, 0, 0});
        nchild.assign(static_cast<std::size_t>(nc), 0);
        for (int p = 0; p < nf; ++p) {
            parents1d& q = up[static_cast<std::size_t>(p)];
            if (p % 2 == 0) q = {1, {p / 2, 0}, {1.0, 0.0}};
            else q = {2, {(p - 1) / 2, ((p + 1) / 2) % nc}, {0.5, 0.5}};
            for (int a = 0; a < q.count; ++a) {
                const auto I = static_cast<std::size_t>(q.c[a]);
                const int k = nchild[I]++;
                child[I][static_cast<std::size_t>(k)] = p;
                child_w[I][static_cast<std::size_t>(k)] = q.w[a];
            }
        }
    }
    /// Stencil offset (-1, 0, +1) from coarse node I to coarse node J (neighbours by construction).
    [[nodiscard]] int offset(int I, int J) const noexcept {
        int d = J - I;
        if (periodic) d = wrap_index(d, nc);
        if (d == 0) return 0;
        if (d == 1) return 1;
        return -1;  // d == -1, or nc - 1 on a periodic axis
    }
};

/// Transfers of all three axes between a fine node grid and its coarse grid.
struct grid_transfer {
    std::array<axis_transfer, 3> axis;
    node_grid fine, coarse;

    grid_transfer() = default;
    explicit grid_transfer(const node_grid& f) : fine(f) {
        coarse.periodic = f.periodic;
        for (int a = 0; a < 3; ++a) {
            axis[static_cast<std::size_t>(a)] = axis_transfer(f.n[a], f.periodic);
            coarse.n[a] = axis[static_cast<std::size_t>(a)].nc;
        }
    }
};

/// The coarse nodes that carry stiffness: those with an active fine child (every other coarse
/// node's row of P^T A P is zero).
[[nodiscard]] inline node_set coarse_nodes(const grid_transfer& t, const node_set& fine) {
    return node_set::select(t.coarse, [&](std::size_t b) {
        const ivec3 P = t.coarse.coords(b);
        const auto X = static_cast<std::size_t>(P.x), Y = static_cast<std::size_t>(P.y), Z = static_cast<std::size_t>(P.z);
        for (int g = 0; g < t.axis[2].nchild[Z]; ++g)
            for (int bb = 0; bb < t.axis[1].nchild[Y]; ++bb)
                for (int a = 0; a < t.axis[0].nchild[X]; ++a)
                    if (fine.at({t.axis[0].child[X][static_cast<std::size_t>(a)], t.axis[1].child[Y][static_cast<std::size_t>(bb)],
                                 t.axis[2].child[Z][static_cast<std::size_t>(g)]}) >= 0)
                        return true;
        return false;
    });
}

/// Trilinear prolongation: fine = P coarse over the active nodes (non-free fine DOFs set to 0).
inline void prolongate(const grid_transfer& t, const node_set& fine, const node_set& coarse, const std::vector<double>& xc,
                       const std::vector<std::uint8_t>& fstate, std::vector<double>& xf) {
    parallel_for(0, fine.count(), [&](std::size_t n) {
        const ivec3 p = fine.pos[n];
        const parents1d& px = t.axis[0].up[static_cast<std::size_t>(p.x)];
        const parents1d& py = t.axis[1].up[static_cast<std::size_t>(p.y)];
        const parents1d& pz = t.axis[2].up[static_cast<std::size_t>(p.z)];
        double acc[3] = {0, 0, 0};
        for (int a = 0; a < px.count; ++a)
            for (int b = 0; b < py.count; ++b)
                for (int g = 0; g < pz.count; ++g) {
                    const std::int32_t m = coarse.at({px.c[a], py.c[b], pz.c[g]});
                    if (m < 0) continue;  // cannot happen: a parent of an active node is active
                    const double w = px.w[a] * py.w[b] * pz.w[g];
                    for (int d = 0; d < 3; ++d) acc[d] += w * xc[3 * static_cast<std::size_t>(m) + static_cast<std::size_t>(d)];
                }
        for (int d = 0; d < 3; ++d) {
            const std::size_t dof = 3 * n + static_cast<std::size_t>(d);
            xf[dof] = fstate[dof] == dof_free ? acc[d] : 0.0;
        }
    }, {.grain = 512});
}

/// Restriction P^T: coarse = P^T fine over the active nodes (non-free coarse DOFs set to 0).
inline void restrict_to(const grid_transfer& t, const node_set& fine, const node_set& coarse, const std::vector<double>& rf,
                        const std::vector<std::uint8_t>& cstate, std::vector<double>& rc) {
    parallel_for(0, coarse.count(), [&](std::size_t n) {
        const ivec3 P = coarse.pos[n];
        const auto X = static_cast<std::size_t>(P.x), Y = static_cast<std::size_t>(P.y), Z = static_cast<std::size_t>(P.z);
        double acc[3] = {0, 0, 0};
        for (int g = 0; g < t.axis[2].nchild[Z]; ++g)
            for (int b = 0; b < t.axis[1].nchild[Y]; ++b)
                for (int a = 0; a < t.axis[0].nchild[X]; ++a) {
                    const std::int32_t m = fine.at({t.axis[0].child[X][static_cast<std::size_t>(a)], t.axis[1].child[Y][static_cast<std::size_t>(b)],
                                                    t.axis[2].child[Z][static_cast<std::size_t>(g)]});
                    if (m < 0) continue;
                    const double w = t.axis[0].child_w[X][static_cast<std::size_t>(a)] * t.axis[1].child_w[Y][static_cast<std::size_t>(b)] *
                                     t.axis[2].child_w[Z][static_cast<std::size_t>(g)];
                    for (int d = 0; d < 3; ++d) acc[d] += w * rf[3 * static_cast<std::size_t>(m) + static_cast<std::size_t>(d)];
                }
        for (int d = 0; d < 3; ++d) {
            const std::size_t dof = 3 * n + static_cast<std::size_t>(d);
            rc[dof] = cstate[dof] == dof_free ? acc[d] : 0.0;
        }
    }, {.grain = 512});
}

/// Galerkin coarse stencil P^T (M A M) P of a fine stencil (M = projection on free fine DOFs)
/// over the active coarse nodes (coarse_nodes), coarse node by coarse node (deterministic).
[[nodiscard]] inline stencil_operator galerkin(const stencil_operator& A, const grid_transfer& t, node_set coarse) {
    stencil_operator out;
    out.reset(std::move(coarse));
    parallel_for(0, out.nodes.count(), [&](std::size_t n) {
        const ivec3 P = out.nodes.pos[n];
        const auto X = static_cast<std::size_t>(P.x), Y = static_cast<std::size_t>(P.y), Z = static_cast<std::size_t>(P.z);
        for (int g = 0; g < t.axis[2].nchild[Z]; ++g)
            for (int b = 0; b < t.axis[1].nchild[Y]; ++b)
                for (int a = 0; a < t.axis[0].nchild[X]; ++a) {
                    const ivec3 p(t.axis[0].child[X][static_cast<std::size_t>(a)], t.axis[1].child[Y][static_cast<std::size_t>(b)],
                                  t.axis[2].child[Z][static_cast<std::size_t>(g)]);
                    const std::int32_t pf = A.nodes.at(p);
                    if (pf < 0) continue;
                    const double wp = t.axis[0].child_w[X][static_cast<std::size_t>(a)] * t.axis[1].child_w[Y][static_cast<std::size_t>(b)] *
                                      t.axis[2].child_w[Z][static_cast<std::size_t>(g)];
                    const auto pfs = static_cast<std::size_t>(pf);
                    for (int slot = 0; slot < 27; ++slot) {
                        const std::int32_t jf = A.nbr[27 * pfs + static_cast<std::size_t>(slot)];
                        if (jf < 0) continue;
                        const double* B = A.block(pfs, slot);
                        double Bm[9];
                        bool any = false;
                        for (int r = 0; r < 3; ++r)
                            for (int cc = 0; cc < 3; ++cc) {
                                const double v = A.state[3 * pfs + static_cast<std::size_t>(r)] == dof_free ? B[3 * r + cc] : 0.0;
                                Bm[3 * r + cc] = v;
                                any = any || v != 0.0;
                            }
                        if (!any) continue;
                        const ivec3 j = A.nodes.pos[static_cast<std::size_t>(jf)];
                        const parents1d& qx = t.axis[0].up[static_cast<std::size_t>(j.x)];
                        const parents1d& qy = t.axis[1].up[static_cast<std::size_t>(j.y)];
                        const parents1d& qz = t.axis[2].up[static_cast<std::size_t>(j.z)];
                        for (int u = 0; u < qx.count; ++u)
                            for (int v = 0; v < qy.count; ++v)
                                for (int w = 0; w < qz.count; ++w) {
                                    const double wt = wp * qx.w[u] * qy.w[v] * qz.w[w];
                                    double* O = out.block(n, stencil_slot(t.axis[0].offset(P.x, qx.c[u]), t.axis[1].offset(P.y, qy.c[v]),
                                                                          t.axis[2].offset(P.z, qz.c[w])));
                                    for (int e = 0; e < 9; ++e) O[e] += wt * Bm[e];
                                }
                    }
                }
    }, {.grain = 32});
    return out;
}

}  // namespace fabsynth::fem::detail
