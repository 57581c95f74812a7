// SPDX-License-Identifier: MIT
#pragma once
/// @file voxel_element.hpp  Reference matrices of a regular voxel (internal to fem/voxel.hpp).
///
/// Every voxel of a regular grid is the same box, so its hex8 stiffness is computed once (by
/// fem::hex8, no element code is duplicated here) and scaled by the voxel's stiffness factor.
/// This header adds the pieces the voxel solvers need on top: the element matrix split into
/// per-node 3 x 24 row blocks (for node-wise gathers), the 8 two-grid Galerkin "child" matrices
/// P_c^T K P_c of a 2x2x2 voxel block, and the element load of a unit macroscopic strain.
#include <Eigen/Core>

#include <array>

#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/hex8.hpp"
#include "fabsynth/fem/material.hpp"

namespace fabsynth::fem::detail {

/// Offset (0/1 per axis) of hex8 local node a inside its voxel (VTK_HEXAHEDRON order).
inline constexpr std::array<std::array<int, 3>, 8> voxel_corner = {
    {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};

/// Local hex8 node index of the corner with offsets (x, y, z) in {0, 1}^3.
[[nodiscard]] constexpr int voxel_local_node(int x, int y, int z) noexcept {
    constexpr std::array<int, 4> ring = {0, 1, 3, 2};  // (x,y) = (0,0),(1,0),(0,1),(1,1) -> 0,1,3,2
    return ring[static_cast<std::size_t>(x + 2 * y)] + 4 * z;
}

/// Reference matrices of one box voxel of size h (mm) made of material m (unit stiffness factor).
struct voxel_element {
    using mat24 = Eigen::Matrix<double, 24, 24>;
    using vec24 = Eigen::Matrix<double, 24, 1>;
    using rows_t = Eigen::Matrix<double, 3, 24>;

    vec3 h{1.0};
    mat24 K = mat24::Zero();                  ///< hex8 stiffness [N/mm]
    std::array<rows_t, 8> rows{};             ///< rows[a] = K.middleRows(3a, 3)
    std::array<mat24, 8> child{};             ///< child[c] = P_c^T K P_c (c = voxel_local_node of the child offset)
    std::array<vec24, 6> strain_field{};      ///< nodal displacements of unit macro-strain i (Voigt, engineering shear)

    voxel_element() = default;
    voxel_element(const vec3& size, const isotropic_material& m) : h(size) {
        hex8::nodes_t X{};
        for (int a = 0; a < 8; ++a)
            X[static_cast<std::size_t>(a)] = vec3(voxel_corner[a][0], voxel_corner[a][1], voxel_corner[a][2]) * h;
        K = hex8::stiffness(X, m);
        for (int a = 0; a < 8; ++a) rows[static_cast<std::size_t>(a)] = K.middleRows(3 * a, 3);
        for (int c = 0; c < 8; ++c) {
            const mat24 P = prolongation(voxel_corner[c]);
            child[static_cast<std::size_t>(c)] = P.transpose() * K * P;
        }
        // u(x) = eps x with eps the symmetric tensor of engineering Voigt strain e_i; evaluated at
        // the nodes relative to the voxel corner (a constant shift is a rigid translation).
        for (int i = 0; i < 6; ++i) {
            Eigen::Matrix3d eps = Eigen::Matrix3d::Zero();
            if (i < 3) {
                eps(i, i) = 1;
            } else {
                const int p = i == 3 ? 1 : 0, q = i == 5 ? 1 : 2;  // yz, xz, xy
                eps(p, q) = eps(q, p) = 0.5;
            }
            for (int a = 0; a < 8; ++a) {
                const Eigen::Vector3d x(voxel_corner[a][0] * h.x, voxel_corner[a][1] * h.y, voxel_corner[a][2] * h.z);
                strain_field[static_cast<std::size_t>(i)].segment<3>(3 * a) = eps * x;
            }
        }
    }

    /// Trilinear interpolation from the 8 corner nodes of a 2x2x2 voxel block to the 8 nodes of
    /// its child at offset `c` (each 0/1): fine dof 3q+i = sum_p w_pq * coarse dof 3p+i.
    static mat24 prolongation(const std::array<int, 3>& c) {
        mat24 P = mat24::Zero();
        for (int q = 0; q < 8; ++q) {
            double t[3];
            for (int k = 0; k < 3; ++k) t[k] = 0.5 * (c[static_cast<std::size_t>(k)] + voxel_corner[q][k]);
            for (int p = 0; p < 8; ++p) {
                double w = 1;
                for (int k = 0; k < 3; ++k) w *= voxel_corner[p][k] ? t[k] : 1 - t[k];
                for (int i = 0; i < 3; ++i) P(3 * q + i, 3 * p + i) = w;
            }
        }
        return P;
    }
};

}  // namespace fabsynth::fem::detail
