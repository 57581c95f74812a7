// SPDX-License-Identifier: MIT
#pragma once
/// @file voxel_operators.hpp  Node grids, the matrix-free voxel operator, 27-point block stencils
/// and grid transfers (internal to fem/voxel.hpp).
///
/// Vectors hold 3 doubles per node, x-fastest node order. Every operator works node by node
/// (each output node gathers from its neighbours), so parallel loops write disjoint data and the
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
#include <vector>

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

/// Stiffness of a grid of identical box voxels, each scaled by a per-voxel factor (0 = void),
/// applied without assembling: y_n = sum over the <= 8 voxels at node n of s_e K_e[n rows] u_e.
struct voxel_operator {
    ivec3 cells{0};
    node_grid nodes;
    std::vector<double> scale;          ///< per voxel, x-fastest; 0 = void
    const voxel_element* element = nullptr;
    std::vector<std::uint8_t> state;    ///< per DOF

    /// for_each_voxel_around_node restricted to solid voxels (scale != 0).
    template <class F>
    void for_each_voxel_at_node(ivec3 p, F&& f) const {
        for_each_voxel_around_node(cells, nodes, p, [&](int a, ivec3 c, std::size_t e) {
            if (scale[e] != 0.0) f(a, c, e);
        });
    }
    /// Node indices of the 8 corners of voxel c.
    [[nodiscard]] std::array<std::size_t, 8> voxel_nodes(ivec3 c) const noexcept {
        int X[2], Y[2], Z[2];
        X[0] = c.x, Y[0] = c.y, Z[0] = c.z;
        X[1] = c.x + 1, Y[1] = c.y + 1, Z[1] = c.z + 1;
        if (nodes.periodic) X[1] %= nodes.n.x, Y[1] %= nodes.n.y, Z[1] %= nodes.n.z;
        std::array<std::size_t, 8> r{};
        for (int b = 0; b < 8; ++b)
            r[static_cast<std::size_t>(b)] = nodes.index(X[voxel_corner[b][0]], Y[voxel_corner[b][1]], Z[voxel_corner[b][2]]);
        return r;
    }

    /// y = A x (identity on non-free DOFs). Voxel by voxel (one 24x24 product each) in 8 passes,
    /// one per parity class (i%2, j%2, k%2): voxels of one class share no node, so each pass runs
    /// in parallel without races and every node sums its voxels in the same order for any thread
    /// count. (Periodic axes with an odd voxel count > 1 break the class property across the
    /// seam; those grids run single-threaded.)
    void apply(const std::vector<double>& x, std::vector<double>& y) const {
        parallel_for(0, y.size(), [&](std::size_t i) { y[i] = 0.0; }, {.grain = 16384});
        bool seam = false;
        for (int a = 0; a < 3; ++a) seam = seam || (nodes.periodic && cells[a] % 2 == 1 && cells[a] > 1);
        const unsigned threads = seam ? 1u : 0u;
        for (int color = 0; color < 8; ++color) {
            const int cx = color & 1, cy = (color >> 1) & 1, cz = color >> 2;
            const int ny = (cells.y - cy + 1) / 2, nz = (cells.z - cz + 1) / 2;
            if (ny <= 0 || nz <= 0) continue;
            parallel_for(0, static_cast<std::size_t>(ny) * static_cast<std::size_t>(nz), [&](std::size_t row) {
                const int j = cy + 2 * static_cast<int>(row % static_cast<std::size_t>(ny));
                const int k = cz + 2 * static_cast<int>(row / static_cast<std::size_t>(ny));
                Eigen::Matrix<double, 24, 1> ue, fe;
                for (int i = cx; i < cells.x; i += 2) {
                    const std::size_t e = static_cast<std::size_t>(i) +
                                          static_cast<std::size_t>(cells.x) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(cells.y) * static_cast<std::size_t>(k));
                    if (scale[e] == 0.0) continue;
                    const auto vn = voxel_nodes({i, j, k});
                    for (int b = 0; b < 8; ++b)
                        for (int d = 0; d < 3; ++d) ue(3 * b + d) = x[3 * vn[static_cast<std::size_t>(b)] + static_cast<std::size_t>(d)];
                    fe.noalias() = element->K * ue;
                    for (int b = 0; b < 8; ++b)
                        for (int d = 0; d < 3; ++d) y[3 * vn[static_cast<std::size_t>(b)] + static_cast<std::size_t>(d)] += scale[e] * fe(3 * b + d);
                }
            }, {.grain = 1, .threads = threads});
        }
        parallel_for(0, y.size(), [&](std::size_t i) {
            if (state[i] != dof_free) y[i] = x[i];
        }, {.grain = 16384});
    }
    /// Diagonal of A (1 on non-free DOFs).
    [[nodiscard]] std::vector<double> diagonal() const {
        std::vector<double> diag(3 * nodes.count(), 0.0);
        parallel_for(0, nodes.count(), [&](std::size_t n) {
            const ivec3 p = nodes.coords(n);
            for_each_voxel_at_node(p, [&](int a, ivec3, std::size_t e) {
                for (int d = 0; d < 3; ++d) diag[3 * n + static_cast<std::size_t>(d)] += scale[e] * element->K(3 * a + d, 3 * a + d);
            });
            for (int d = 0; d < 3; ++d)
                if (state[3 * n + static_cast<std::size_t>(d)] != dof_free) diag[3 * n + static_cast<std::size_t>(d)] = 1.0;
        }, {.grain = 256});
        return diag;
    }
};

/// Slot of neighbour offset o in {-1,0,1}^3 within a 27-point stencil.
[[nodiscard]] constexpr int stencil_slot(int ox, int oy, int oz) noexcept { return (ox + 1) + 3 * (oy + 1) + 9 * (oz + 1); }

/// Assembled operator in 27-point block-stencil form: per node, 27 row-major 3x3 blocks coupling
/// it to the nodes at offsets {-1,0,1}^3 (243 doubles per node). On periodic grids with fewer
/// than 3 nodes along an axis several slots name the same node; their blocks simply add up.
struct stencil_operator {
    node_grid nodes;
    std::vector<double> S;
    std::vector<std::uint8_t> state;

    [[nodiscard]] double* block(std::size_t node, int slot) noexcept { return S.data() + 243 * node + 9 * static_cast<std::size_t>(slot); }
    [[nodiscard]] const double* block(std::size_t node, int slot) const noexcept {
        return S.data() + 243 * node + 9 * static_cast<std::size_t>(slot);
    }

    void apply(const std::vector<double>& x, std::vector<double>& y) const {
        parallel_for(0, nodes.count(), [&](std::size_t n) {
            const ivec3 p = nodes.coords(n);
            // Neighbour coordinates per axis (-1 = outside a non-periodic grid).
            int nb[3][3];
            for (int a = 0; a < 3; ++a)
                for (int o = -1; o <= 1; ++o) {
                    int q = p[a] + o;
                    if (nodes.periodic) q = q < 0 ? q + nodes.n[a] : (q >= nodes.n[a] ? q - nodes.n[a] : q);
                    else if (q < 0 || q >= nodes.n[a]) q = -1;
                    nb[a][o + 1] = q;
                }
            double acc[3] = {0, 0, 0};
            const double* B = block(n, 0);
            for (int oz = 0; oz < 3; ++oz)
                for (int oy = 0; oy < 3; ++oy)
                    for (int ox = 0; ox < 3; ++ox, B += 9) {
                        if (nb[0][ox] < 0 || nb[1][oy] < 0 || nb[2][oz] < 0) continue;
                        const double* xm = x.data() + 3 * nodes.index(nb[0][ox], nb[1][oy], nb[2][oz]);
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
            const ivec3 p = nodes.coords(n);
            for (int slot = 0; slot < 27; ++slot) {
                const std::int64_t m = nodes.at(p + ivec3(slot % 3 - 1, (slot / 3) % 3 - 1, slot / 9 - 1));
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

/// Assembles the stencil of a voxel grid whose voxel matrices are given by rows(e, a) = the 3 x 24
/// rows of voxel e's matrix belonging to its local node a (node-wise, so deterministic).
template <class Rows>
stencil_operator assemble_stencil(const ivec3& cells, const node_grid& nodes, Rows&& rows) {
    stencil_operator op;
    op.nodes = nodes;
    op.S.assign(243 * nodes.count(), 0.0);
    op.state.assign(3 * nodes.count(), dof_free);
    parallel_for(0, nodes.count(), [&](std::size_t n) {
        for_each_voxel_around_node(cells, nodes, nodes.coords(n), [&](int a, ivec3, std::size_t e) {
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

/// Trilinear prolongation: fine = P coarse (non-free fine DOFs set to 0).
inline void prolongate(const grid_transfer& t, const std::vector<double>& xc, const std::vector<std::uint8_t>& fstate, std::vector<double>& xf) {
    parallel_for(0, t.fine.count(), [&](std::size_t n) {
        const ivec3 p = t.fine.coords(n);
        const parents1d& px = t.axis[0].up[static_cast<std::size_t>(p.x)];
        const parents1d& py = t.axis[1].up[static_cast<std::size_t>(p.y)];
        const parents1d& pz = t.axis[2].up[static_cast<std::size_t>(p.z)];
        double acc[3] = {0, 0, 0};
        for (int a = 0; a < px.count; ++a)
            for (int b = 0; b < py.count; ++b)
                for (int g = 0; g < pz.count; ++g) {
                    const std::size_t m = t.coarse.index(px.c[a], py.c[b], pz.c[g]);
                    const double w = px.w[a] * py.w[b] * pz.w[g];
                    for (int d = 0; d < 3; ++d) acc[d] += w * xc[3 * m + static_cast<std::size_t>(d)];
                }
        for (int d = 0; d < 3; ++d) {
            const std::size_t dof = 3 * n + static_cast<std::size_t>(d);
            xf[dof] = fstate[dof] == dof_free ? acc[d] : 0.0;
        }
    }, {.grain = 512});
}

/// Restriction P^T: coarse = P^T fine (non-free coarse DOFs set to 0).
inline void restrict_to(const grid_transfer& t, const std::vector<double>& rf, const std::vector<std::uint8_t>& cstate, std::vector<double>& rc) {
    parallel_for(0, t.coarse.count(), [&](std::size_t n) {
        const ivec3 P = t.coarse.coords(n);
        const auto X = static_cast<std::size_t>(P.x), Y = static_cast<std::size_t>(P.y), Z = static_cast<std::size_t>(P.z);
        double acc[3] = {0, 0, 0};
        for (int g = 0; g < t.axis[2].nchild[Z]; ++g)
            for (int b = 0; b < t.axis[1].nchild[Y]; ++b)
                for (int a = 0; a < t.axis[0].nchild[X]; ++a) {
                    const std::size_t m = t.fine.index(t.axis[0].child[X][static_cast<std::size_t>(a)], t.axis[1].child[Y][static_cast<std::size_t>(b)],
                                                       t.axis[2].child[Z][static_cast<std::size_t>(g)]);
                    const double w = t.axis[0].child_w[X][static_cast<std::size_t>(a)] * t.axis[1].child_w[Y][static_cast<std::size_t>(b)] *
                                     t.axis[2].child_w[Z][static_cast<std::size_t>(g)];
                    for (int d = 0; d < 3; ++d) acc[d] += w * rf[3 * m + static_cast<std::size_t>(d)];
                }
        for (int d = 0; d < 3; ++d) {
            const std::size_t dof = 3 * n + static_cast<std::size_t>(d);
            rc[dof] = cstate[dof] == dof_free ? acc[d] : 0.0;
        }
    }, {.grain = 512});
}

/// Galerkin coarse stencil P^T (M A M) P of a fine stencil (M = projection on free fine DOFs),
/// coarse node by coarse node (deterministic).
[[nodiscard]] inline stencil_operator galerkin(const stencil_operator& A, const grid_transfer& t) {
    stencil_operator out;
    out.nodes = t.coarse;
    out.S.assign(243 * t.coarse.count(), 0.0);
    out.state.assign(3 * t.coarse.count(), dof_free);
    const node_grid& f = A.nodes;
    parallel_for(0, t.coarse.count(), [&](std::size_t n) {
        const ivec3 P = t.coarse.coords(n);
        const auto X = static_cast<std::size_t>(P.x), Y = static_cast<std::size_t>(P.y), Z = static_cast<std::size_t>(P.z);
        for (int g = 0; g < t.axis[2].nchild[Z]; ++g)
            for (int b = 0; b < t.axis[1].nchild[Y]; ++b)
                for (int a = 0; a < t.axis[0].nchild[X]; ++a) {
                    const ivec3 p(t.axis[0].child[X][static_cast<std::size_t>(a)], t.axis[1].child[Y][static_cast<std::size_t>(b)],
                                  t.axis[2].child[Z][static_cast<std::size_t>(g)]);
                    const double wp = t.axis[0].child_w[X][static_cast<std::size_t>(a)] * t.axis[1].child_w[Y][static_cast<std::size_t>(b)] *
                                      t.axis[2].child_w[Z][static_cast<std::size_t>(g)];
                    const std::size_t pf = f.index(p.x, p.y, p.z);
                    for (int slot = 0; slot < 27; ++slot) {
                        const std::int64_t jf = f.at(p + ivec3(slot % 3 - 1, (slot / 3) % 3 - 1, slot / 9 - 1));
                        if (jf < 0) continue;
                        const double* B = A.block(pf, slot);
                        double Bm[9];
                        bool any = false;
                        for (int r = 0; r < 3; ++r)
                            for (int cc = 0; cc < 3; ++cc) {
                                const double v = A.state[3 * pf + static_cast<std::size_t>(r)] == dof_free ? B[3 * r + cc] : 0.0;
                                Bm[3 * r + cc] = v;
                                any = any || v != 0.0;
                            }
                        if (!any) continue;
                        const ivec3 j = f.coords(static_cast<std::size_t>(jf));
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
