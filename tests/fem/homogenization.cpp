#include <catch2/catch.hpp>

#include <fabsynth/fem/homogenization.hpp>
#include <fabsynth/voxel/grid.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstring>
#include <vector>

using namespace fabsynth;
using fem::isotropic_material;
using fem::matrix6;

namespace {

double rel_err(const matrix6& a, const matrix6& b) { return (a - b).norm() / b.norm(); }

// Exact effective tensor of a laminate with layer normal z (continuity of in-plane strain and of
// normal stress); phases given by their tensors and volume fractions.
matrix6 laminate_z(const std::vector<matrix6>& C, const std::vector<double>& f) {
    const int n[3] = {2, 3, 4}, p[3] = {0, 1, 5};
    auto sub = [](const matrix6& M, const int* r, const int* c) {
        Eigen::Matrix3d S;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) S(i, j) = M(r[i], c[j]);
        return S;
    };
    Eigen::Matrix3d inv_nn = Eigen::Matrix3d::Zero(), pn_inv = Eigen::Matrix3d::Zero(), inv_np = Eigen::Matrix3d::Zero(),
                    schur = Eigen::Matrix3d::Zero();
    for (std::size_t k = 0; k < C.size(); ++k) {
        const Eigen::Matrix3d Cnn_inv = sub(C[k], n, n).inverse();
        inv_nn += f[k] * Cnn_inv;
        pn_inv += f[k] * sub(C[k], p, n) * Cnn_inv;
        inv_np += f[k] * Cnn_inv * sub(C[k], n, p);
        schur += f[k] * (sub(C[k], p, p) - sub(C[k], p, n) * Cnn_inv * sub(C[k], n, p));
    }
    const Eigen::Matrix3d Cnn = inv_nn.inverse();
    const Eigen::Matrix3d Cpn = pn_inv * Cnn;
    const Eigen::Matrix3d Cpp = schur + pn_inv * Cnn * inv_np;
    matrix6 R = matrix6::Zero();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            R(n[i], n[j]) = Cnn(i, j);
            R(p[i], n[j]) = R(n[j], p[i]) = Cpn(i, j);
            R(p[i], p[j]) = Cpp(i, j);
        }
    return R;
}

// Simple cubic lattice: three orthogonal square struts of width w voxels through the cell centre.
voxel_grid<double> cubic_lattice(int n, int w) {
    voxel_grid<double> g({n, n, n}, vec3(0.0), 1.0 / n, 0.0);
    const int lo = (n - w) / 2, hi = lo + w;
    auto in = [&](int i) { return i >= lo && i < hi; };
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                if ((in(i) && in(j)) || (in(j) && in(k)) || (in(i) && in(k))) g.set({i, j, k}, 1.0);
    return g;
}

}  // namespace

TEST_CASE("homogenization of a full solid block returns the base tensor", "[fem][homogenization]") {
    const isotropic_material m{200.0, 0.3};
    voxel_grid<double> g({6, 4, 8}, vec3(0.0), vec3(0.3, 0.5, 0.2), 1.0);
    for (auto s : {fem::voxel_solver::multigrid, fem::voxel_solver::jacobi, fem::voxel_solver::direct}) {
        fem::homogenization_options opt;
        opt.solver.solver = s;
        const auto r = fem::homogenize(g, m, opt);
        CHECK(rel_err(r.C, m.elasticity()) < 1e-10);
        CHECK(r.volume_fraction == 1.0);
        const auto fit = fem::fit_isotropic(r.C, m.E);
        CHECK(fit.E == Approx(200.0).epsilon(1e-10));
        CHECK(fit.nu == Approx(0.3).epsilon(1e-10));
        CHECK(fit.relative_residual < 1e-10);
    }
}

TEST_CASE("homogenization of a two-phase laminate matches the exact laminate formula", "[fem][homogenization]") {
    const isotropic_material m{1000.0, 0.25};
    const int n = 8;
    // Layers normal to z: 3 of density 1, 5 of density 0.2 (stiffness factor = density).
    voxel_grid<double> g({4, 6, n}, vec3(0.0), vec3(1.0, 0.5, 0.25), 0.0);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < 6; ++j)
            for (int i = 0; i < 4; ++i) g.set({i, j, k}, k < 3 ? 1.0 : 0.2);
    const matrix6 ref = laminate_z({m.elasticity(), 0.2 * m.elasticity()}, {3.0 / n, 5.0 / n});
    for (auto s : {fem::voxel_solver::multigrid, fem::voxel_solver::direct}) {
        fem::homogenization_options opt;
        opt.solver.solver = s;
        opt.solver.tolerance = 1e-10;
        const auto r = fem::homogenize(g, m, opt);
        CHECK(rel_err(r.C, ref) < 1e-9);
        CHECK(r.volume_fraction == Approx((3 + 5 * 0.2) / n));
    }
    // SIMP penalty 3 with a density floor: layers of density 0.1 behave as min_density^3.
    fem::homogenization_options opt;
    opt.law = {.penalty = 3.0, .min_density = 0.5};
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < 6; ++j)
            for (int i = 0; i < 4; ++i) g.set({i, j, k}, k < 3 ? 1.0 : 0.1);
    const matrix6 ref3 = laminate_z({m.elasticity(), 0.125 * m.elasticity()}, {3.0 / n, 5.0 / n});
    CHECK(rel_err(fem::homogenize(g, m, opt).C, ref3) < 1e-8);
}

TEST_CASE("simple cubic lattice: cubic symmetry, energy bounds, solvers agree, thread-independent", "[fem][homogenization]") {
    const isotropic_material m{1.0, 0.3};
    const auto g = cubic_lattice(16, 4);
    fem::homogenization_options opt;
    opt.solver.tolerance = 1e-10;
    opt.solver.coarsest_dofs = 200;
    const auto r = fem::homogenize(g, m, opt);
    const matrix6& C = r.C;
    CHECK(r.stats[0].levels >= 3);
    // 3 struts of 4x4 in 16^3: 3*16*16 - 2*64... = (3*4*4*16 - 2*4*4*4) / 16^3
    CHECK(r.volume_fraction == Approx((3.0 * 16 * 16 - 2 * 64) / 4096.0));
    const double s = C.norm();
    CHECK(std::abs(C(0, 0) - C(1, 1)) < 1e-8 * s);
    CHECK(std::abs(C(0, 0) - C(2, 2)) < 1e-8 * s);
    CHECK(std::abs(C(0, 1) - C(0, 2)) < 1e-8 * s);
    CHECK(std::abs(C(0, 1) - C(1, 2)) < 1e-8 * s);
    CHECK(std::abs(C(3, 3) - C(4, 4)) < 1e-8 * s);
    CHECK(std::abs(C(3, 3) - C(5, 5)) < 1e-8 * s);
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            if ((i < 3) != (j < 3) || (i >= 3 && j >= 3 && i != j)) CHECK(std::abs(C(i, j)) < 1e-8 * s);
    // Voigt bound (affine trial field): <C> - C^H is positive semidefinite, and C^H is PSD.
    const matrix6 voigt = r.volume_fraction * m.elasticity();
    CHECK(Eigen::SelfAdjointEigenSolver<matrix6>(voigt - C).eigenvalues().minCoeff() > -1e-10 * s);
    CHECK(Eigen::SelfAdjointEigenSolver<matrix6>(C).eigenvalues().minCoeff() > 0);
    // Struts are stiff along their axes but the lattice is soft in shear.
    CHECK(C(3, 3) < 0.1 * C(0, 0));
    // Independent solver paths agree.
    opt.solver.solver = fem::voxel_solver::direct;
    CHECK(rel_err(fem::homogenize(g, m, opt).C, C) < 1e-8);
    opt.solver.solver = fem::voxel_solver::multigrid;
    set_num_threads(1);
    const auto a = fem::homogenize(g, m, opt);
    set_num_threads(2);
    const auto b = fem::homogenize(g, m, opt);
    set_num_threads(0);
    CHECK(std::memcmp(a.C.data(), b.C.data(), sizeof(double) * 36) == 0);
}

TEST_CASE("floating islands are removed without changing the result", "[fem][homogenization]") {
    const isotropic_material m{10.0, 0.3};
    auto g = cubic_lattice(12, 4);
    const auto base = fem::homogenize(g, m);
    CHECK(base.removed_fraction == 0.0);
    // A 2x2x2 block in a void corner region, not touching the lattice by any face.
    for (int k = 1; k < 3; ++k)
        for (int j = 1; j < 3; ++j)
            for (int i = 1; i < 3; ++i) g.set({i, j, k}, 1.0);
    const auto r = fem::homogenize(g, m);
    CHECK(r.removed_fraction == Approx(8.0 / 1728.0));
    CHECK(rel_err(r.C, base.C) < 1e-7);
    voxel_grid<double> islands({6, 6, 6}, vec3(0.0), 1.0, 0.0);
    islands.set({2, 2, 2}, 1.0);
    CHECK_THROWS_AS(fem::homogenize(islands, m), no_solution);
}

TEST_CASE("fit_isotropic recovers isotropic tensors and minimises the Frobenius distance", "[fem][homogenization]") {
    const auto f = fem::fit_isotropic(fem::isotropic_tensor(3.5, 0.21));
    CHECK(f.E == Approx(3.5).epsilon(1e-12));
    CHECK(f.nu == Approx(0.21).epsilon(1e-12));
    CHECK(f.residual < 1e-20);
    // A cubic tensor: compare with a brute-force scan over (E, nu).
    matrix6 C = matrix6::Zero();
    C.topLeftCorner<3, 3>().setConstant(0.4);
    for (int i = 0; i < 3; ++i) C(i, i) = 1.3, C(i + 3, i + 3) = 0.2;
    const auto fit = fem::fit_isotropic(C);
    double best = 1e300;
    for (int a = 0; a <= 400; ++a)
        for (int b = 0; b <= 400; ++b) {
            const double E = 0.5 + 1.0 * a / 400, nu = -0.2 + 0.65 * b / 400;
            best = std::min(best, (fem::isotropic_tensor(E, nu) - C).squaredNorm());
        }
    CHECK(fit.residual <= best + 1e-12);
    CHECK(fit.residual > 0.9 * best);
    CHECK(fit.relative_residual == Approx(std::sqrt(fit.residual) / C.norm()));
    // Bound E <= E_max active: the fit sits on the bound.
    const auto clamped = fem::fit_isotropic(fem::isotropic_tensor(5.0, 0.3), 2.0);
    CHECK(clamped.E == Approx(2.0).epsilon(1e-9));
    CHECK(clamped.nu >= -1.0);
    CHECK(clamped.nu <= 0.5);
    CHECK(clamped.residual <= (fem::isotropic_tensor(2.0, 0.3) - fem::isotropic_tensor(5.0, 0.3)).squaredNorm() + 1e-12);
    CHECK_THROWS_AS(fem::fit_isotropic(C, -1.0), invalid_input);
    C(0, 0) = std::nan("");
    CHECK_THROWS_AS(fem::fit_isotropic(C), invalid_input);
}

TEST_CASE("multigrid with odd coarse grids and odd fine grids matches the direct solver", "[fem][homogenization]") {
    const isotropic_material m{5.0, 0.25};
    // Porous random cell with a solid frame of planes so that it connects; 10 -> 5 -> 3 -> 2 nodes.
    auto make = [](ivec3 d) {
        voxel_grid<double> g(d, vec3(0.0), vec3(1.0, 0.8, 1.2), 0.0);
        for (int k = 0; k < d.z; ++k)
            for (int j = 0; j < d.y; ++j)
                for (int i = 0; i < d.x; ++i) {
                    const bool frame = i == 0 || j == 1 || k == 2;
                    g.set({i, j, k}, frame ? 1.0 : (hash_uniform(5, i, j, k) < 0.5 ? 0.0 : 0.3 + 0.7 * hash_uniform(6, i, j, k)));
                }
        return g;
    };
    for (ivec3 d : {ivec3(10, 10, 10), ivec3(9, 7, 5)}) {
        const auto g = make(d);
        fem::homogenization_options opt;
        opt.solver.tolerance = 1e-11;
        opt.solver.solver = fem::voxel_solver::direct;
        const matrix6 ref = fem::homogenize(g, m, opt).C;
        opt.solver.solver = fem::voxel_solver::multigrid;
        opt.solver.coarsest_dofs = 30;
        const auto mg = fem::homogenize(g, m, opt);
        CHECK(rel_err(mg.C, ref) < 1e-8);
        if (d.x == 10) CHECK(mg.stats[0].levels == 4);
        opt.solver.solver = fem::voxel_solver::jacobi;
        CHECK(rel_err(fem::homogenize(g, m, opt).C, ref) < 1e-8);
    }
}
