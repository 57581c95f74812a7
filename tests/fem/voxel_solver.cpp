#include <catch2/catch.hpp>

#include <fabsynth/fem/voxel.hpp>
#include <fabsynth/voxel/grid.hpp>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <cmath>
#include <cstring>
#include <vector>

using namespace fabsynth;
using fem::isotropic_material;

namespace {

voxel_grid<double> random_grid(ivec3 dims, std::uint64_t seed, double void_fraction) {
    voxel_grid<double> g(dims, vec3(0.0), vec3(0.5, 0.7, 0.6), 0.0);
    for (int k = 0; k < dims.z; ++k)
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i) {
                const double u = hash_uniform(seed, i, j, k);
                g.set({i, j, k}, u < void_fraction ? 0.0 : 0.1 + 0.9 * hash_uniform(seed + 1, i, j, k));
            }
    return g;
}

// Brute-force assembly (triplets, element loop) of the full stiffness matrix: the oracle.
Eigen::SparseMatrix<double> assemble(const voxel_grid<double>& g, const isotropic_material& m, bool periodic) {
    const ivec3 c = g.dims();
    const ivec3 nn = periodic ? c : c + 1;
    auto node = [&](int i, int j, int k) {
        if (periodic) i %= nn.x, j %= nn.y, k %= nn.z;
        return i + nn.x * (j + nn.y * k);
    };
    fem::hex8::nodes_t X;
    const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int a = 0; a < 8; ++a) X[a] = vec3(corner[a][0], corner[a][1], corner[a][2]) * g.spacing();
    const Eigen::Matrix<double, 24, 24> K = fem::hex8::stiffness(X, m);
    std::vector<Eigen::Triplet<double>> t;
    for (int k = 0; k < c.z; ++k)
        for (int j = 0; j < c.y; ++j)
            for (int i = 0; i < c.x; ++i) {
                const double rho = g.get({i, j, k});
                if (rho == 0) continue;
                for (int a = 0; a < 8; ++a)
                    for (int b = 0; b < 8; ++b)
                        for (int p = 0; p < 3; ++p)
                            for (int q = 0; q < 3; ++q)
                                t.emplace_back(3 * node(i + corner[a][0], j + corner[a][1], k + corner[a][2]) + p,
                                               3 * node(i + corner[b][0], j + corner[b][1], k + corner[b][2]) + q, rho * K(3 * a + p, 3 * b + q));
            }
    const int n = 3 * nn.x * nn.y * nn.z;
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    return A;
}

}  // namespace

TEST_CASE("voxel element: rigid modes are free and affine fields give C * volume", "[fem][voxel]") {
    const isotropic_material m{1000.0, 0.3};
    const vec3 h(0.5, 0.7, 0.6);
    const fem::detail::voxel_element el(h, m);
    const double vol = h.x * h.y * h.z;
    const Eigen::Matrix<double, 6, 6> C = m.elasticity();
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            CHECK(el.strain_field[i].dot(el.K * el.strain_field[j]) == Approx(C(i, j) * vol).margin(1e-9 * C(0, 0) * vol));
    Eigen::Matrix<double, 24, 1> t = Eigen::Matrix<double, 24, 1>::Zero();
    for (int a = 0; a < 8; ++a) t(3 * a + 1) = 1.0;
    CHECK((el.K * t).norm() < 1e-9 * el.K.norm());
    // Galerkin children of a uniform 2x2x2 block = the stiffness of the doubled voxel.
    Eigen::Matrix<double, 24, 24> sum = Eigen::Matrix<double, 24, 24>::Zero();
    for (const auto& c : el.child) sum += c;
    const fem::detail::voxel_element big(2.0 * h, m);
    CHECK((sum - big.K).norm() < 1e-10 * big.K.norm());
}

TEST_CASE("matrix-free voxel operator equals the assembled stiffness matrix", "[fem][voxel]") {
    const isotropic_material m{200.0, 0.3};
    for (bool periodic : {false, true}) {
        const auto g = random_grid({5, 4, 6}, 7, 0.3);
        const Eigen::SparseMatrix<double> A = assemble(g, m, periodic);
        const fem::detail::voxel_element el(g.spacing(), m);
        const fem::detail::node_grid box{periodic ? g.dims() : g.dims() + 1, periodic};
        const std::vector<std::uint8_t> box_state(3 * box.count(), fem::detail::dof_free);
        const fem::detail::voxel_operator op = fem::detail::make_voxel_operator(g.dims(), periodic, fem::detail::voxel_factors(g, {}, g.dims()), el, box_state);
        // Only nodes that touch a solid voxel are stored: exactly the nonzero rows of A.
        std::size_t nonzero_rows = 0;
        for (std::size_t b = 0; b < box.count(); ++b) nonzero_rows += A.col(static_cast<Eigen::Index>(3 * b)).norm() > 0;
        CHECK(op.active.count() == nonzero_rows);
        if (!periodic) CHECK(op.active.count() < box.count());
        std::vector<double> xb(3 * box.count()), x(3 * op.active.count()), y(x.size());
        for (std::size_t i = 0; i < xb.size(); ++i) xb[i] = hash_uniform(3, i) - 0.5;
        for (std::size_t n = 0; n < op.active.count(); ++n) {
            const ivec3 p = op.active.pos[n];
            for (int d = 0; d < 3; ++d) x[3 * n + d] = xb[3 * box.index(p.x, p.y, p.z) + d];
        }
        op.apply(x, y);
        const Eigen::VectorXd ref = A * Eigen::Map<const Eigen::VectorXd>(xb.data(), static_cast<Eigen::Index>(xb.size()));
        const auto err_of = [&](const std::vector<double>& v) {
            double err = 0;
            for (std::size_t n = 0; n < op.active.count(); ++n) {
                const ivec3 p = op.active.pos[n];
                for (int d = 0; d < 3; ++d)
                    err = std::max(err, std::abs(ref(static_cast<Eigen::Index>(3 * box.index(p.x, p.y, p.z) + d)) - v[3 * n + d]));
            }
            return err;
        };
        CHECK(err_of(y) < 1e-10 * ref.cwiseAbs().maxCoeff());
        // The level-0 stencil assembled from voxel rows matches too.
        fem::detail::stencil_operator st = fem::detail::assemble_stencil(op.cells, op.active, [&](std::size_t e, int a, bool& any) {
            any = op.voxel_index[e] >= 0;
            const double sc = any ? op.scale[static_cast<std::size_t>(op.voxel_index[e])] : 0.0;
            return Eigen::Matrix<double, 3, 24>(sc * el.rows[a]);
        });
        st.state = op.state;
        std::vector<double> y2(x.size());
        st.apply(x, y2);
        CHECK(err_of(y2) < 1e-10 * ref.cwiseAbs().maxCoeff());
    }
}

TEST_CASE("uniaxial tension of a voxel bar is exact (sigma L / E, lateral -nu sigma / E)", "[fem][voxel]") {
    // A homogeneous strain field is reproduced exactly by trilinear hexes with consistent loads.
    const ivec3 d(12, 6, 5);
    const double h = 0.5, sigma = 3.0;
    const isotropic_material m{1500.0, 0.35};
    voxel_grid<double> g(d, vec3(0.0), h, 1.0);
    fem::voxel_boundary_conditions bc(d);
    for (int k = 0; k <= d.z; ++k)
        for (int j = 0; j <= d.y; ++j) {
            bc.fix(0, j, k, 1);  // x roller on the left face
            const double w = (j == 0 || j == d.y ? 0.5 : 1.0) * (k == 0 || k == d.z ? 0.5 : 1.0);
            bc.add_force(d.x, j, k, {sigma * h * h * w, 0, 0});
        }
    bc.fix(0, 0, 0, 7);
    bc.fix(0, d.y, 0, 4);  // stops rotation about x
    bc.fix(0, 0, d.z, 2);  // stops rotation about y / z together with the rollers
    for (auto solver : {fem::voxel_solver::multigrid, fem::voxel_solver::jacobi, fem::voxel_solver::direct}) {
        fem::voxel_solver_options opt;
        opt.solver = solver;
        opt.tolerance = 1e-11;
        opt.coarsest_dofs = 50;  // force several levels on this small grid
        const auto sol = fem::solve_voxel_elasticity(g, m, bc, opt);
        const double L = d.x * h;
        const vec3 u = sol.displacement(d.x, d.y, d.z);
        CHECK(u.x == Approx(sigma * L / m.E).epsilon(1e-8));
        CHECK(u.y == Approx(-m.nu * sigma / m.E * d.y * h).epsilon(1e-7));
        CHECK(u.z == Approx(-m.nu * sigma / m.E * d.z * h).epsilon(1e-7));
        if (solver == fem::voxel_solver::multigrid) CHECK(sol.stats.levels >= 2);
    }
}

TEST_CASE("multigrid, Jacobi-CG and direct agree on a porous cantilever; bit-identical across threads", "[fem][voxel]") {
    auto g = random_grid({16, 8, 8}, 11, 0.25);
    for (int k = 0; k < 8; ++k)
        for (int j = 0; j < 8; ++j) g.set({0, j, k}, 1.0), g.set({1, j, k}, 1.0);
    for (int i = 0; i < 16; ++i)  // a solid spine keeps everything attached
        for (int k = 3; k < 5; ++k)
            for (int j = 3; j < 5; ++j) g.set({i, j, k}, 1.0);
    // Remove parts that only hang on edges/corners: make every voxel face-adjacent to the spine by
    // filling the row between it and the spine.
    for (int k = 0; k < 8; ++k)
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 16; ++i)
                if (g.get({i, j, k}) > 0) {
                    for (int jj = std::min(j, 3); jj <= std::max(j, 4); ++jj)
                        if (g.get({i, jj, k}) == 0) g.set({i, jj, k}, 0.5);
                    for (int kk = std::min(k, 3); kk <= std::max(k, 4); ++kk)
                        if (g.get({i, 3, kk}) == 0) g.set({i, 3, kk}, 0.5);
                }
    fem::voxel_boundary_conditions bc(g.dims());
    for (int k = 0; k <= 8; ++k)
        for (int j = 0; j <= 8; ++j) bc.fix(0, j, k);
    bc.add_force(16, 4, 4, {0, 0.3, -1.0});
    const isotropic_material m = isotropic_material::pla();
    fem::voxel_solver_options opt;
    opt.tolerance = 1e-10;
    opt.coarsest_dofs = 100;
    opt.solver = fem::voxel_solver::direct;
    const auto ref = fem::solve_voxel_elasticity(g, m, bc, opt);
    const double scale = glm::length(ref.displacement(16, 4, 4));
    REQUIRE(scale > 0);
    for (auto solver : {fem::voxel_solver::multigrid, fem::voxel_solver::jacobi}) {
        opt.solver = solver;
        const auto s = fem::solve_voxel_elasticity(g, m, bc, opt);
        double err = 0;
        REQUIRE(s.node == ref.node);
        for (std::size_t n = 0; n < s.u.size(); ++n) err = std::max(err, glm::length(s.u[n] - ref.u[n]));
        CHECK(err < 1e-7 * scale);
        CHECK(s.compliance == Approx(ref.compliance).epsilon(1e-9));
    }
    opt.solver = fem::voxel_solver::multigrid;
    set_num_threads(1);
    const auto a = fem::solve_voxel_elasticity(g, m, bc, opt);
    set_num_threads(2);
    const auto b = fem::solve_voxel_elasticity(g, m, bc, opt);
    set_num_threads(0);
    REQUIRE(a.u.size() == b.u.size());
    CHECK(std::memcmp(a.u.data(), b.u.data(), a.u.size() * sizeof(vec3)) == 0);
    CHECK(a.stats.iterations == b.stats.iterations);
}

TEST_CASE("a thin shell in a large empty box: the sparse multigrid equals a brute-force assembly and LDL^T", "[fem][voxel]") {
    // A hollow sphere 2 voxels thick in a 24^3 box (about 15% of the box solid), standing on its
    // bottom voxels, under a body load: the sparse case of the surface-pattern validation. The
    // oracle is the element-by-element assembly above, restricted to the free DOFs and factored.
    const int n = 24;
    voxel_grid<double> g({n, n, n}, vec3(0.0), vec3(0.5, 0.5, 0.5), 0.0);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double r = std::sqrt((i + 0.5 - 12) * (i + 0.5 - 12) + (j + 0.5 - 12) * (j + 0.5 - 12) + (k + 0.5 - 12) * (k + 0.5 - 12));
                if (r <= 11.0 && r > 9.0) g.set({i, j, k}, 1.0);
            }
    fem::voxel_boundary_conditions bc(g.dims());
    std::size_t solid = 0;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                if (g.get({i, j, k}) == 0) continue;
                ++solid;
                for (const auto& c : fem::detail::voxel_corner) {
                    if (k < 3) bc.fix(i + c[0], j + c[1], k + c[2]);
                    bc.add_force(i + c[0], j + c[1], k + c[2], {0.01, 0.0, -0.02});
                }
            }
    REQUIRE(solid < static_cast<std::size_t>(n * n * n) / 5);
    const isotropic_material m{2000.0, 0.35};
    const Eigen::SparseMatrix<double> A = assemble(g, m, false);
    std::vector<std::uint8_t> fixed(static_cast<std::size_t>(A.rows() / 3), 0);
    std::vector<vec3> force(fixed.size(), vec3(0.0));
    for (const auto& c : bc.nodes()) fixed[c.node] = c.fixed, force[c.node] = c.force;
    std::vector<int> free_index(A.rows(), -1);
    int nf = 0;
    for (Eigen::Index d = 0; d < A.rows(); ++d)
        if (!(fixed[static_cast<std::size_t>(d / 3)] & (1u << (d % 3))) && A.col(d).norm() > 0) free_index[static_cast<std::size_t>(d)] = nf++;
    std::vector<Eigen::Triplet<double>> t;
    for (int c = 0; c < A.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it)
            if (free_index[it.row()] >= 0 && free_index[it.col()] >= 0) t.emplace_back(free_index[it.row()], free_index[it.col()], it.value());
    Eigen::SparseMatrix<double> K(nf, nf);
    K.setFromTriplets(t.begin(), t.end());
    Eigen::VectorXd f(nf);
    for (Eigen::Index d = 0; d < A.rows(); ++d)
        if (free_index[static_cast<std::size_t>(d)] >= 0) f(free_index[static_cast<std::size_t>(d)]) = force[static_cast<std::size_t>(d / 3)][d % 3];
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(K);
    REQUIRE(ldlt.info() == Eigen::Success);
    const Eigen::VectorXd u_ref = ldlt.solve(f);
    const double scale = u_ref.cwiseAbs().maxCoeff();
    REQUIRE(scale > 0);

    fem::voxel_solver_options opt;
    opt.tolerance = 1e-10;
    opt.coarsest_dofs = 200;  // several sparse levels
    const auto sol = fem::solve_voxel_elasticity(g, m, bc, opt);
    CHECK(sol.stats.levels >= 3);
    CHECK(sol.stats.dofs == static_cast<std::size_t>(nf));
    double err = 0;
    for (Eigen::Index d = 0; d < A.rows(); ++d) {
        const double u = sol.displacement(static_cast<std::size_t>(d / 3))[d % 3];
        const int fi = free_index[static_cast<std::size_t>(d)];
        err = std::max(err, std::abs(u - (fi >= 0 ? u_ref(fi) : 0.0)));
    }
    CHECK(err < 1e-7 * scale);
    CHECK(sol.compliance == Approx(f.dot(u_ref)).epsilon(1e-8));
}

TEST_CASE("multigrid stops coarsening where coarse nodes would tie separate fins together", "[fem][voxel]") {
    // A comb: a base plate and thin fins (2 voxels thick, 4 voxels apart) standing on it, clamped
    // under the base, loaded sideways at the fin tips. Coarse nodes two levels down span several
    // fins that only the base joins; the solver stops coarsening before that and converges in
    // far fewer iterations, to the same answer.
    const ivec3 d(48, 24, 24);
    voxel_grid<double> g(d, vec3(0.0), 0.5, 0.0);
    for (int k = 0; k < d.z; ++k)
        for (int j = 0; j < d.y; ++j)
            for (int i = 0; i < d.x; ++i)
                if (k < 2 || i % 6 < 2) g.set({i, j, k}, 1.0);
    fem::voxel_boundary_conditions bc(d);
    for (int j = 0; j <= d.y; ++j)
        for (int i = 0; i <= d.x; ++i) bc.fix(i, j, 0);
    for (int i = 0; i < d.x; i += 6)
        for (int j = 0; j <= d.y; ++j) bc.add_force(i, j, d.z, {0.0, 0.01, 0.0});
    fem::voxel_solver_options opt;
    opt.coarsest_dofs = 500;
    opt.max_split_coarse_dofs = 20000;  // the whole comb (~80 k DOFs) is not solved directly
    opt.tolerance = 1e-9;
    const auto stop = fem::solve_voxel_elasticity(g, isotropic_material{1000.0, 0.3}, bc, opt);
    opt.max_split_fraction = 1.0;  // coarsen as far as the grid allows
    const auto deep = fem::solve_voxel_elasticity(g, isotropic_material{1000.0, 0.3}, bc, opt);
    INFO("levels " << stop.stats.levels << " / " << deep.stats.levels << ", iterations " << stop.stats.iterations << " / " << deep.stats.iterations);
    CHECK(stop.stats.levels > 1);
    CHECK(stop.stats.levels < deep.stats.levels);
    CHECK(2 * stop.stats.iterations < deep.stats.iterations);
    CHECK(stop.compliance == Approx(deep.compliance).epsilon(1e-7));
    // a solid block splits nowhere: every level the grid allows
    const auto solid = fem::detail::separation_levels(d, [](const ivec3&) { return true; }, 5, 0.05, 1000000);
    CHECK(solid == 5);
    CHECK(fem::detail::separation_levels(d, [&](const ivec3& p) { return g.get(p) > 0; }, 5, 0.05, 1000000) <= 2);
}

TEST_CASE("voxel FEM rejects bad input and unsupported parts", "[fem][voxel]") {
    const isotropic_material m{100.0, 0.3};
    voxel_grid<double> g({4, 4, 4}, vec3(0.0), 1.0, 1.0);
    fem::voxel_boundary_conditions bc(g.dims());
    for (int k = 0; k <= 4; ++k)
        for (int j = 0; j <= 4; ++j) bc.fix(0, j, k);
    g.set({3, 3, 3}, 1.5);
    CHECK_THROWS_AS(fem::solve_voxel_elasticity(g, m, bc), invalid_input);
    g.set({3, 3, 3}, std::nan(""));
    CHECK_THROWS_AS(fem::solve_voxel_elasticity(g, m, bc), invalid_input);
    // A voxel hanging on a single edge is an unsupported part.
    voxel_grid<double> h({4, 4, 4}, vec3(0.0), 1.0, 0.0);
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 2; ++i) h.set({i, j, k}, 1.0);
    h.set({2, 0, 2}, 1.0);
    CHECK_THROWS_AS(fem::solve_voxel_elasticity(h, m, bc), solver_error);
    CHECK_THROWS_AS(bc.fix(5, 0, 0), invalid_input);  // nodes run 0..4
    CHECK_THROWS_AS(bc.add_force(0, -1, 0, vec3(1.0)), invalid_input);
    fem::voxel_boundary_conditions wrong({3, 4, 4});
    CHECK_THROWS_AS(fem::solve_voxel_elasticity(h, m, wrong), invalid_input);
    fem::voxel_solver_options bad;
    bad.tolerance = 0;
    CHECK_THROWS_AS(fem::solve_voxel_elasticity(g, m, bc, bad), invalid_input);
    CHECK_THROWS_AS(fem::parse_voxel_solver("magic"), invalid_input);
}
