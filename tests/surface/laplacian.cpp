// surface/laplacian.hpp: symmetry and zero row sums, linear precision on a planar
// triangulation (a harmonic function that is linear is reproduced exactly), the maximum principle
// on the bunny, components without constraints, and bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/surface/laplacian.hpp"
#include "fabsynth/io/mesh.hpp"
#include "support/sphere_mesh.hpp"

namespace laplacian_test {

using fabsynth::triangle_mesh;
using fabsynth::vec3;

TEST_CASE("cotan Laplacian: symmetric, rows sum to zero, the textbook weights on a right-triangle grid", "[geometry][laplacian]") {
    const triangle_mesh m = fabsynth::test::plane_grid(4, 1.0, 1, 0.0);
    const Eigen::SparseMatrix<double> L = fabsynth::cotan_laplacian(m);
    const Eigen::MatrixXd D(L);
    CHECK((D - D.transpose()).cwiseAbs().maxCoeff() < 1e-15);
    CHECK(D.rowwise().sum().cwiseAbs().maxCoeff() < 1e-12);
    // interior vertex (2, 2) = 12: on this split (diagonals (i, j) -> (i + 1, j + 1)) the axis edges
    // have weight 1 (two 45-degree angles, cot 1, halved and summed) and the diagonals 0 (right angles)
    CHECK(D(12, 13) == Approx(1.0));
    CHECK(D(12, 17) == Approx(1.0));
    CHECK(D(12, 18) == Approx(0.0).margin(1e-15));
    CHECK(D(12, 12) == Approx(-4.0));
}

/// A jittered triangular lattice (rows offset by half a step, nearly equilateral triangles, so
/// every cotangent weight is positive and nothing is clamped), vertex (i, j) at j (n + 1) + i.
inline triangle_mesh lattice(int n, std::uint64_t seed) {
    triangle_mesh m;
    fabsynth::counter_rng rng(seed);
    const double h = std::sqrt(3.0) / 2;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.vertices.emplace_back(i + 0.5 * (j % 2) + rng.uniform(-0.05, 0.05), j * h + rng.uniform(-0.05, 0.05), 0.0);
    auto id = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            if (j % 2 == 0) {
                m.faces.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
                m.faces.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
            } else {
                m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
                m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            }
        }
    return m;
}

TEST_CASE("harmonic interpolation: linear precision on a jittered planar lattice", "[geometry][laplacian]") {
    const int n = 20;
    const triangle_mesh m = lattice(n, 7);
    const Eigen::SparseMatrix<double> L = fabsynth::cotan_laplacian(m);
    for (Eigen::Index c = 0; c < L.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(L, c); it; ++it)
            if (it.row() != it.col()) REQUIRE(it.value() > 0);  // nothing clamped: the precision claim applies
    std::vector<std::uint32_t> fixed;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            if (i == 0 || j == 0 || i == n || j == n) fixed.push_back(static_cast<std::uint32_t>(j * (n + 1) + i));
    auto f = [](vec3 p) { return 3.0 * p.x - 2.0 * p.y + 0.5; };
    Eigen::MatrixXd at(static_cast<Eigen::Index>(fixed.size()), 1);
    for (std::size_t k = 0; k < fixed.size(); ++k) at(static_cast<Eigen::Index>(k), 0) = f(m.vertices[fixed[k]]);
    const Eigen::MatrixXd x = fabsynth::harmonic_interpolation(m, fixed, at);
    double worst = 0;
    for (std::size_t v = 0; v < m.num_vertices(); ++v) worst = std::max(worst, std::abs(x(static_cast<Eigen::Index>(v), 0) - f(m.vertices[v])));
    CHECK(worst < 1e-9);
}

TEST_CASE("harmonic interpolation: maximum principle on the bunny, undetermined components", "[geometry][laplacian]") {
    const triangle_mesh m = fabsynth::io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj");
    const std::vector<std::uint32_t> fixed{0, 100, 2000, 3000};
    Eigen::MatrixXd at(4, 1);
    at << 0.0, 1.0, 0.25, 0.75;
    const Eigen::MatrixXd x = fabsynth::harmonic_interpolation(m, fixed, at);
    CHECK(x.minCoeff() >= -1e-12);
    CHECK(x.maxCoeff() <= 1.0 + 1e-12);
    CHECK(x(100, 0) == 1.0);
    // two disjoint spheres, constraints on the first only
    triangle_mesh two = fabsynth::test::sphere_mesh(1.0, 2);
    const auto nv = static_cast<std::uint32_t>(two.vertices.size());
    const triangle_mesh b = two;
    for (const vec3& p : b.vertices) two.vertices.push_back(p + vec3(5, 0, 0));
    for (const auto& f : b.faces) two.faces.push_back({f[0] + nv, f[1] + nv, f[2] + nv});
    const std::vector<std::uint32_t> one{0};
    Eigen::MatrixXd v1(1, 2);
    v1 << 2.0, -1.0;
    const Eigen::MatrixXd y = fabsynth::harmonic_interpolation(two, one, v1);
    CHECK(y(static_cast<Eigen::Index>(nv - 1), 0) == Approx(2.0));  // constant on the anchored sphere
    CHECK(y(static_cast<Eigen::Index>(nv - 1), 1) == Approx(-1.0));
    CHECK(std::isnan(y(static_cast<Eigen::Index>(nv), 0)));
    CHECK(fabsynth::undetermined_vertices(two, one).size() == nv);
}

TEST_CASE("harmonic interpolation: bad input is named", "[geometry][laplacian]") {
    const triangle_mesh m = fabsynth::test::plane_grid(3, 1.0, 1, 0.0);
    using fabsynth::invalid_input;
    Eigen::MatrixXd one(1, 1);
    one << 1.0;
    const std::vector<std::uint32_t> out_of_range{99}, twice{1, 1}, ok{1};
    CHECK_THROWS_AS(fabsynth::harmonic_interpolation(m, out_of_range, one), invalid_input);
    Eigen::MatrixXd two(2, 1);
    two << 1.0, 2.0;
    CHECK_THROWS_AS(fabsynth::harmonic_interpolation(m, twice, two), invalid_input);
    CHECK_THROWS_AS(fabsynth::harmonic_interpolation(m, ok, two), invalid_input);
    one(0, 0) = NAN;
    CHECK_THROWS_AS(fabsynth::harmonic_interpolation(m, ok, one), invalid_input);
    triangle_mesh bad = m;
    bad.vertices[2].x = NAN;
    CHECK_THROWS_AS(fabsynth::cotan_laplacian(bad), invalid_input);
    bad = m;
    bad.faces[0][2] = 1000;
    CHECK_THROWS_AS(fabsynth::cotan_laplacian(bad), invalid_input);
}

}  // namespace laplacian_test
