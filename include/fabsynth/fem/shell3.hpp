// SPDX-License-Identifier: MIT
#pragma once
/// @file shell3.hpp  Flat 3-node facet shell (Abaqus S3, VTK_TRIANGLE): CST membrane + DKT bending
/// + a small drilling stiffness, 6 DOFs per node.
///
/// Node order: 0, 1, 2 counter-clockwise around the shell normal n = (X1-X0) x (X2-X0) / |...|.
/// Element DOFs per node (global axes): (ux, uy, uz, rx, ry, rz), right-handed rotations [rad].
/// Local frame: e1 along X1-X0, e3 = n, e2 = e3 x e1. Everything is built in the local frame
/// and rotated to global axes with K = T^T K_local T (T = blockdiag(R,...), R rows e1,e2,e3).
///
/// * Membrane: constant-strain triangle, plane stress.
/// * Bending: Discrete Kirchhoff Triangle, Batoz, Bathe & Ho, "A study of three-node triangular
///   plate bending elements", IJNME 15 (1980) 1771-1812, eqs. for H_x, H_y with the side
///   coefficients a_k..e_k; integrated with the 3-point rule (exact: the curvatures are linear).
/// * Drilling: the membrane has no stiffness for the in-plane rotation rz. We add the penalty
///   k_d * sum_i (rz_i - omega)^2 / 2 with omega = (dv/dx - du/dy)/2 the CST's rigid in-plane
///   rotation and k_d = drilling_factor * E * t * A (drilling_factor = 1e-3). Tying rz to omega
///   (instead of a plain spring on rz) keeps rigid rotations free of strain energy, so the element
///   still has exactly 6 zero-energy modes; 1e-3 is small enough not to stiffen the membrane
///   visibly and large enough to keep the global matrix well conditioned.
///
/// Stress: xi = (r, s, zeta) with (r, s) triangle coordinates of (node1, node2) and zeta in
/// [-1, 1] through the thickness (zeta = +1 on the +n face). Stress there is
/// D_ps (eps_membrane + zeta t/2 kappa), rotated to global axes (sigma_33 = 0 locally).
/// centroid() returns the centroid on the top (+n) face (Abaqus SPOS), where bending stress peaks.
#include <Eigen/Core>

#include <array>
#include <cmath>
#include <string>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/fem/element.hpp"
#include "fabsynth/fem/material.hpp"

namespace fabsynth::fem {

/// Material and thickness [mm] of a shell element.
struct shell_section {
    isotropic_material material;
    double thickness = 0;
    void validate() const {
        material.validate();
        if (!(std::isfinite(thickness) && thickness > 0))
            throw invalid_input("shell_section: thickness must be finite and > 0, got " + std::to_string(thickness));
    }
    friend bool operator==(const shell_section&, const shell_section&) = default;
};

struct shell3 {
    static constexpr int num_nodes = 3, dofs_per_node = 6, vtk_type = 5;
    using nodes_t = std::array<vec3, 3>;
    using properties_t = shell_section;
    using matrix_t = Eigen::Matrix<double, 18, 18>;
    using vector_t = Eigen::Matrix<double, 18, 1>;
    static constexpr std::array<int, 3> vtk_order = {0, 1, 2};
    static constexpr double drilling_factor = 1e-3;

    /// Local frame and 2D coordinates of a triangle.
    struct frame {
        Eigen::Matrix3d R;   ///< rows e1, e2, e3 (local = R * global)
        double x[3], y[3];   ///< local coordinates of the nodes (node 0 at the origin)
        double area;         ///< [mm^2]
    };
    static frame local_frame(const nodes_t& X) {
        for (int a = 0; a < 3; ++a)
            if (!all_finite(X[a])) throw invalid_input("shell3: node " + std::to_string(a) + " is not finite");
        const vec3 d1 = X[1] - X[0], d2 = X[2] - X[0];
        const vec3 c = glm::cross(d1, d2);
        const double l2 = std::max({glm::dot(d1, d1), glm::dot(d2, d2), glm::dot(X[2] - X[1], X[2] - X[1])});
        const double a2 = glm::length(c);
        if (!(a2 > 1e-12 * l2)) throw invalid_input("shell3: triangle is degenerate (zero area)");
        const vec3 e1 = d1 / glm::length(d1), e3 = c / a2, e2 = glm::cross(e3, e1);
        frame f{};
        f.R << e1.x, e1.y, e1.z, e2.x, e2.y, e2.z, e3.x, e3.y, e3.z;
        for (int a = 0; a < 3; ++a) {
            const vec3 d = X[a] - X[0];
            f.x[a] = glm::dot(d, e1), f.y[a] = glm::dot(d, e2);
        }
        f.area = 0.5 * a2;
        return f;
    }

    /// CST membrane B (3 x 6) over local (u0,v0,u1,v1,u2,v2): (eps_xx, eps_yy, gamma_xy).
    static Eigen::Matrix<double, 3, 6> membrane_b(const frame& f) {
        const double A2 = 2 * f.area;
        Eigen::Matrix<double, 3, 6> B = Eigen::Matrix<double, 3, 6>::Zero();
        for (int i = 0; i < 3; ++i) {
            const int j = (i + 1) % 3, k = (i + 2) % 3;
            const double bx = (f.y[j] - f.y[k]) / A2, by = (f.x[k] - f.x[j]) / A2;  // dN_i/dx, dN_i/dy
            B(0, 2 * i) = bx;
            B(1, 2 * i + 1) = by;
            B(2, 2 * i) = by, B(2, 2 * i + 1) = bx;
        }
        return B;
    }
    /// In-plane rigid rotation omega = (dv/dx - du/dy)/2 as a row over (u0,v0,...,u2,v2).
    static Eigen::Matrix<double, 1, 6> membrane_rotation(const frame& f) {
        const double A2 = 2 * f.area;
        Eigen::Matrix<double, 1, 6> w;
        for (int i = 0; i < 3; ++i) {
            const int j = (i + 1) % 3, k = (i + 2) % 3;
            w(2 * i) = -0.5 * (f.x[k] - f.x[j]) / A2;
            w(2 * i + 1) = 0.5 * (f.y[j] - f.y[k]) / A2;
        }
        return w;
    }

    /// DKT curvature matrix (3 x 9) over local (w0, tx0, ty0, w1, ...) at triangle coordinates
    /// (xi, eta) = (L1, L2): rows (beta_x,x, beta_y,y, beta_x,y + beta_y,x), beta = -grad w.
    static Eigen::Matrix<double, 3, 9> bending_b(const frame& f, double xi, double eta) {
        // Side k = 4, 5, 6 joins nodes (i, j) = (2,3), (3,1), (1,2) in Batoz' 1-based numbering.
        double a[3], b[3], c[3], d[3], e[3];
        const int si[3] = {1, 2, 0}, sj[3] = {2, 0, 1};
        for (int k = 0; k < 3; ++k) {
            const double xij = f.x[si[k]] - f.x[sj[k]], yij = f.y[si[k]] - f.y[sj[k]];
            const double l2 = xij * xij + yij * yij;
            a[k] = -xij / l2;
            b[k] = 0.75 * xij * yij / l2;
            c[k] = (0.25 * xij * xij - 0.5 * yij * yij) / l2;
            d[k] = -yij / l2;
            e[k] = (0.25 * yij * yij - 0.5 * xij * xij) / l2;
        }
        const double L = 1 - xi - eta;
        // Derivatives of the 6 quadratic shape functions (corners 1-3, mid-sides 4: 23, 5: 31, 6: 12).
        const double Nx[6] = {1 - 4 * L, 4 * xi - 1, 0, 4 * eta, -4 * eta, 4 * L - 4 * xi};
        const double Ne[6] = {1 - 4 * L, 0, 4 * eta - 1, 4 * xi, 4 * L - 4 * eta, -4 * xi};
        auto H = [&](const double* N, Eigen::Matrix<double, 1, 9>& hx, Eigen::Matrix<double, 1, 9>& hy) {
            const double N1 = N[0], N2 = N[1], N3 = N[2], N4 = N[3], N5 = N[4], N6 = N[5];
            const double a4 = a[0], a5 = a[1], a6 = a[2], b4 = b[0], b5 = b[1], b6 = b[2];
            const double c4 = c[0], c5 = c[1], c6 = c[2], d4 = d[0], d5 = d[1], d6 = d[2];
            const double e4 = e[0], e5 = e[1], e6 = e[2];
            hx << 1.5 * (a6 * N6 - a5 * N5), b5 * N5 + b6 * N6, N1 - c5 * N5 - c6 * N6,  //
                1.5 * (a4 * N4 - a6 * N6), b6 * N6 + b4 * N4, N2 - c6 * N6 - c4 * N4,    //
                1.5 * (a5 * N5 - a4 * N4), b4 * N4 + b5 * N5, N3 - c4 * N4 - c5 * N5;
            hy << 1.5 * (d6 * N6 - d5 * N5), -N1 + e5 * N5 + e6 * N6, -b5 * N5 - b6 * N6,  //
                1.5 * (d4 * N4 - d6 * N6), -N2 + e6 * N6 + e4 * N4, -b6 * N6 - b4 * N4,    //
                1.5 * (d5 * N5 - d4 * N4), -N3 + e4 * N4 + e5 * N5, -b4 * N4 - b5 * N5;
        };
        Eigen::Matrix<double, 1, 9> hx_xi, hy_xi, hx_eta, hy_eta;
        H(Nx, hx_xi, hy_xi);
        H(Ne, hx_eta, hy_eta);
        const double x31 = f.x[2] - f.x[0], x12 = f.x[0] - f.x[1], y31 = f.y[2] - f.y[0], y12 = f.y[0] - f.y[1];
        const double A2 = 2 * f.area;
        Eigen::Matrix<double, 3, 9> B;
        B.row(0) = (y31 * hx_xi + y12 * hx_eta) / A2;
        B.row(1) = (-x31 * hy_xi - x12 * hy_eta) / A2;
        B.row(2) = (-x31 * hx_xi - x12 * hx_eta + y31 * hy_xi + y12 * hy_eta) / A2;
        return B;
    }

    /// 18 x 18 rotation T mapping global element DOFs to local ones.
    static matrix_t transformation(const frame& f) {
        matrix_t T = matrix_t::Zero();
        for (int b = 0; b < 6; ++b) T.block<3, 3>(3 * b, 3 * b) = f.R;
        return T;
    }

    /// Stiffness in the local frame, local DOFs (u, v, w, tx, ty, tz) per node.
    static matrix_t local_stiffness(const frame& f, const shell_section& s) {
        const isotropic_material& m = s.material;
        const double t = s.thickness;
        matrix_t K = matrix_t::Zero();
        // Membrane.
        const Eigen::Matrix<double, 3, 6> Bm = membrane_b(f);
        const Eigen::Matrix<double, 6, 6> Km = Bm.transpose() * m.plane_stress() * Bm * (t * f.area);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                for (int p = 0; p < 2; ++p)
                    for (int q = 0; q < 2; ++q) K(6 * i + p, 6 * j + q) += Km(2 * i + p, 2 * j + q);
        // Bending: D_b = t^3/12 * plane-stress matrix; 3-point rule at (1/6,1/6),(2/3,1/6),(1/6,2/3).
        const Eigen::Matrix3d Db = m.plane_stress() * (t * t * t / 12);
        const double pts[3][2] = {{1.0 / 6, 1.0 / 6}, {2.0 / 3, 1.0 / 6}, {1.0 / 6, 2.0 / 3}};
        Eigen::Matrix<double, 9, 9> Kb = Eigen::Matrix<double, 9, 9>::Zero();
        for (const auto& p : pts) {
            const Eigen::Matrix<double, 3, 9> Bb = bending_b(f, p[0], p[1]);
            Kb.noalias() += Bb.transpose() * Db * Bb * (f.area / 3);
        }
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                for (int p = 0; p < 3; ++p)
                    for (int q = 0; q < 3; ++q) K(6 * i + 2 + p, 6 * j + 2 + q) += Kb(3 * i + p, 3 * j + q);
        // Drilling: k_d sum_i (tz_i - omega)^2 / 2 (see file comment).
        const Eigen::Matrix<double, 1, 6> w = membrane_rotation(f);
        const double kd = drilling_factor * m.E * t * f.area;
        for (int i = 0; i < 3; ++i) {
            Eigen::Matrix<double, 1, 18> g = Eigen::Matrix<double, 1, 18>::Zero();
            g(6 * i + 5) = 1;
            for (int a = 0; a < 3; ++a) g(6 * a) -= w(2 * a), g(6 * a + 1) -= w(2 * a + 1);
            K.noalias() += kd * g.transpose() * g;
        }
        return K;
    }

    /// 18 x 18 stiffness in global axes [N/mm, N, N mm].
    static matrix_t stiffness(const nodes_t& X, const shell_section& s) {
        s.validate();
        const frame f = local_frame(X);
        const matrix_t T = transformation(f);
        const matrix_t K = T.transpose() * local_stiffness(f, s) * T;
        return 0.5 * (K + K.transpose());
    }
    /// Nodal loads [N] of a uniform force per volume b [N/mm^3]: b t A / 3 per node (exact for the
    /// linear membrane interpolation; no moments).
    static vector_t body_force(const nodes_t& X, const shell_section& s, const vec3& b) {
        const frame f = local_frame(X);
        vector_t r = vector_t::Zero();
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < 3; ++i) r(6 * a + i) = b[i] * s.thickness * f.area / 3;
        return r;
    }
    /// Nodal loads [N] of a uniform pressure p [MPa]. Abaqus convention: positive pressure acts
    /// against the normal, force = -p n A / 3 per node (the usual lumping for DKT; no moments).
    static vector_t pressure_load(const nodes_t& X, double p) {
        const frame f = local_frame(X);
        vector_t r = vector_t::Zero();
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < 3; ++i) r(6 * a + i) = -p * f.R(2, i) * f.area / 3;
        return r;
    }
    /// Cauchy stress [MPa] in global axes at xi = (r, s, zeta) (see file comment).
    static voigt6 stress(const nodes_t& X, const shell_section& s, const vector_t& ue, const vec3& xi) {
        const frame f = local_frame(X);
        const vector_t ul = transformation(f) * ue;
        Eigen::Matrix<double, 6, 1> um;
        Eigen::Matrix<double, 9, 1> ub;
        for (int a = 0; a < 3; ++a) {
            um(2 * a) = ul(6 * a), um(2 * a + 1) = ul(6 * a + 1);
            for (int p = 0; p < 3; ++p) ub(3 * a + p) = ul(6 * a + 2 + p);
        }
        const Eigen::Vector3d eps = membrane_b(f) * um + (xi.z * s.thickness / 2) * (bending_b(f, xi.x, xi.y) * ub);
        const Eigen::Vector3d sl = s.material.plane_stress() * eps;  // (sxx, syy, sxy) local
        Eigen::Matrix3d S;
        S << sl(0), sl(2), 0, sl(2), sl(1), 0, 0, 0, 0;
        const Eigen::Matrix3d G = f.R.transpose() * S * f.R;
        voigt6 v;
        v << G(0, 0), G(1, 1), G(2, 2), G(1, 2), G(0, 2), G(0, 1);
        return v;
    }
    static constexpr vec3 centroid() { return vec3(1.0 / 3, 1.0 / 3, 1.0); }
    /// The 3 in-plane points on the bottom (zeta = -1) then top (zeta = +1) face.
    static std::array<vec3, 6> stress_points() {
        std::array<vec3, 6> r{};
        const double pts[3][2] = {{1.0 / 6, 1.0 / 6}, {2.0 / 3, 1.0 / 6}, {1.0 / 6, 2.0 / 3}};
        for (int k = 0; k < 2; ++k)
            for (int i = 0; i < 3; ++i) r[3 * k + i] = vec3(pts[i][0], pts[i][1], k ? 1.0 : -1.0);
        return r;
    }
    static double volume(const nodes_t& X, const shell_section& s) { return local_frame(X).area * s.thickness; }
};

static_assert(finite_element<shell3>);

}  // namespace fabsynth::fem
