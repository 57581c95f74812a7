// SPDX-License-Identifier: MIT
#pragma once
/// @file assembly.hpp  Global stiffness assembly into Eigen::SparseMatrix (parallel, deterministic).
///
/// The sparsity pattern is built from node adjacency (every DOF of two nodes sharing an element
/// couples), so the matrix is structurally symmetric and stores both triangles. Element matrices
/// are computed in parallel in fixed-size chunks and scattered serially in element order, so the
/// floating-point sums are bit-identical for any thread count.
///
/// Usage:
///   fabsynth::fem::dof_map dofs(m);
///   Eigen::SparseMatrix<double> K = fabsynth::fem::assemble_stiffness(m, dofs);   // dofs.total^2
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "fabsynth/core/huge_pages.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/fem/mesh.hpp"

namespace fabsynth::fem {

namespace detail {

/// Node adjacency: for node i, sorted neighbour nodes (including i) and the row offset of each
/// neighbour's first DOF inside any column of node i.
struct node_graph {
    std::vector<std::vector<std::uint32_t>> nbr;
    std::vector<std::vector<std::size_t>> row_start;
};

inline node_graph build_node_graph(const mesh& m, const dof_map& dofs) {
    const std::size_t nn = m.nodes.size();
    // Incident elements per node (CSR).
    std::vector<std::size_t> start(nn + 1, 0);
    for (const element& e : m.elements)
        for (int a = 0; a < num_nodes(e.kind); ++a) ++start[e.nodes[a] + 1];
    for (std::size_t i = 0; i < nn; ++i) start[i + 1] += start[i];
    std::vector<std::uint32_t> inc(start.back());
    {
        std::vector<std::size_t> fill(start.begin(), start.end() - 1);
        for (std::size_t e = 0; e < m.elements.size(); ++e)
            for (int a = 0; a < num_nodes(m.elements[e].kind); ++a) inc[fill[m.elements[e].nodes[a]]++] = static_cast<std::uint32_t>(e);
    }
    node_graph g;
    g.nbr.resize(nn);
    g.row_start.resize(nn);
    parallel_for(0, nn, [&](std::size_t i) {
        auto& nb = g.nbr[i];
        for (std::size_t k = start[i]; k < start[i + 1]; ++k) {
            const element& e = m.elements[inc[k]];
            for (int a = 0; a < num_nodes(e.kind); ++a) nb.push_back(e.nodes[a]);
        }
        std::sort(nb.begin(), nb.end());
        nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
        auto& rs = g.row_start[i];
        rs.resize(nb.size());
        std::size_t r = 0;
        for (std::size_t k = 0; k < nb.size(); ++k) rs[k] = r, r += dofs.count[nb[k]];
    }, {.grain = 256});
    return g;
}

/// Empty-valued matrix with the full symmetric pattern of the mesh.
inline Eigen::SparseMatrix<double> pattern_matrix(const dof_map& dofs, const node_graph& g) {
    using SpMat = Eigen::SparseMatrix<double>;
    using Index = SpMat::StorageIndex;
    const std::size_t nn = g.nbr.size();
    SpMat K(static_cast<Eigen::Index>(dofs.total), static_cast<Eigen::Index>(dofs.total));
    std::size_t nnz = 0;
    for (std::size_t i = 0; i < nn; ++i) {
        std::size_t col_len = 0;
        for (std::uint32_t j : g.nbr[i]) col_len += dofs.count[j];
        nnz += col_len * dofs.count[i];
    }
    K.resizeNonZeros(static_cast<Eigen::Index>(nnz));
    advise_huge_pages(K.innerIndexPtr(), nnz * sizeof(Index));  // first touched just below
    advise_huge_pages(K.valuePtr(), nnz * sizeof(double));
    Index* outer = K.outerIndexPtr();
    Index* inner = K.innerIndexPtr();
    std::size_t pos = 0;
    for (std::size_t i = 0; i < nn; ++i)
        for (int k = 0; k < dofs.count[i]; ++k) {
            outer[dofs.offset[i] + static_cast<std::size_t>(k)] = static_cast<Index>(pos);
            for (std::uint32_t j : g.nbr[i])
                for (int r = 0; r < dofs.count[j]; ++r) inner[pos++] = static_cast<Index>(dofs.offset[j] + static_cast<std::size_t>(r));
        }
    outer[dofs.total] = static_cast<Index>(pos);
    std::fill(K.valuePtr(), K.valuePtr() + nnz, 0.0);
    return K;
}

/// scale x the stiffness of element e of type E. An element that cannot be integrated
/// (inverted, degenerate, non-finite) is named in the error by its label and its nodes' labels
/// (the deck's numbers for a deck, else 0-based indices).
template <finite_element E>
typename E::matrix_t scaled_element_stiffness(const mesh& m, std::size_t e, double scale) {
    try {
        return scale * E::stiffness(m.element_nodes<E>(e), m.properties<E>(e));
    } catch (const invalid_input& x) {
        std::string nodes;
        for (int a = 0; a < E::num_nodes; ++a) nodes += (a ? " " : "") + std::to_string(m.node_label(m.elements[e].nodes[static_cast<std::size_t>(a)]));
        constexpr std::string_view prefix = "fabsynth: ";
        std::string_view what = x.what();
        if (what.starts_with(prefix)) what.remove_prefix(prefix.size());
        throw invalid_input("element " + std::to_string(m.element_label(e)) + " (nodes " + nodes + "): " + std::string(what));
    }
}

/// Scaled stiffness of element e of type E.
template <finite_element E>
typename E::matrix_t element_stiffness(const mesh& m, std::size_t e) {
    return scaled_element_stiffness<E>(m, e, m.elements[e].stiffness_scale);
}

}  // namespace detail

/// Assembles the global stiffness matrix [N/mm] (dofs.total x dofs.total, both triangles stored,
/// compressed column-major). Throws invalid_input for an invalid mesh or inverted elements.
[[nodiscard]] inline Eigen::SparseMatrix<double> assemble_stiffness(const mesh& m, const dof_map& dofs) {
    m.validate();
    const detail::node_graph g = detail::build_node_graph(m, dofs);
    Eigen::SparseMatrix<double> K = detail::pattern_matrix(dofs, g);
    double* val = K.valuePtr();
    const auto* outer = K.outerIndexPtr();

    constexpr std::size_t chunk = 2048;  // bounds the buffer of element matrices
    const std::size_t ne = m.elements.size();
    auto run_kind = [&]<class E>(std::type_identity<E>) {
        constexpr int n = E::num_nodes, d = E::dofs_per_node;
        std::vector<std::size_t> ids;
        for (std::size_t e = 0; e < ne; ++e)
            if (visit_kind(m.elements[e].kind, []<class F>(std::type_identity<F>) { return std::is_same_v<F, E>; })) ids.push_back(e);
        std::vector<typename E::matrix_t> Ke(std::min(chunk, ids.size()));
        for (std::size_t c0 = 0; c0 < ids.size(); c0 += chunk) {
            const std::size_t c1 = std::min(ids.size(), c0 + chunk);
            parallel_for(c0, c1, [&](std::size_t k) { Ke[k - c0] = detail::element_stiffness<E>(m, ids[k]); }, {.grain = 16});
            for (std::size_t k = c0; k < c1; ++k) {
                const element& el = m.elements[ids[k]];
                const auto& Kl = Ke[k - c0];
                for (int b = 0; b < n; ++b) {
                    const std::uint32_t nb = el.nodes[b];
                    const auto& nbr = g.nbr[nb];
                    for (int a = 0; a < n; ++a) {
                        const std::uint32_t na = el.nodes[a];
                        const std::size_t p = static_cast<std::size_t>(std::lower_bound(nbr.begin(), nbr.end(), na) - nbr.begin());
                        const std::size_t rs = g.row_start[nb][p];
                        for (int j = 0; j < d; ++j) {
                            double* col = val + outer[dofs.offset[nb] + static_cast<std::size_t>(j)] + rs;
                            for (int i = 0; i < d; ++i) col[i] += Kl(d * a + i, d * b + j);
                        }
                    }
                }
            }
        }
    };
    run_kind(std::type_identity<hex8>{});
    run_kind(std::type_identity<wedge6>{});
    run_kind(std::type_identity<shell3>{});
    return K;
}

}  // namespace fabsynth::fem
