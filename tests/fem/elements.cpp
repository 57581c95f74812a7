// Element-level checks of hex8, wedge6, shell3 and the material against independent oracles:
// compliance of Hooke's law, rigid-body null spaces, exact constant-strain/curvature fields.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "fabsynth/fem/hex8.hpp"
#include "fabsynth/fem/material.hpp"
#include "fabsynth/fem/shell3.hpp"
#include "fabsynth/fem/wedge6.hpp"

using namespace fabsynth;
using namespace fabsynth::fem;

namespace {

hex8::nodes_t distorted_hex() {
    return {vec3(0.1, -0.05, 0.02), vec3(2.1, 0.1, -0.1), vec3(2.3, 1.6, 0.05), vec3(-0.2, 1.4, 0.1),
            vec3(0.05, 0.1, 1.2), vec3(1.9, -0.1, 1.5), vec3(2.2, 1.8, 1.3), vec3(0.1, 1.5, 1.7)};
}
wedge6::nodes_t distorted_wedge() {
    return {vec3(0, 0, 0), vec3(2.1, 0.2, 0.1), vec3(0.3, 1.7, -0.1), vec3(0.1, -0.1, 1.3), vec3(1.8, 0.1, 1.6), vec3(0.4, 2.0, 1.1)};
}

// Number of eigenvalues below tol * largest.
template <class M>
int count_zero_modes(const M& K, double tol = 1e-10) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Eigen::MatrixXd(K), Eigen::EigenvaluesOnly);
    const double lmax = es.eigenvalues().cwiseAbs().maxCoeff();
    int n = 0;
    for (int i = 0; i < es.eigenvalues().size(); ++i) n += std::abs(es.eigenvalues()(i)) < tol * lmax;
    return n;
}

// Linear displacement field u = A x + c and its engineering strain in Voigt order.
Eigen::Matrix3d grad_A() {
    Eigen::Matrix3d A;
    A << 1e-3, 2e-4, -3e-4, 5e-4, -2e-3, 1e-4, -4e-4, 3e-4, 1.5e-3;
    return A;
}
voigt6 strain_of(const Eigen::Matrix3d& A) {
    voigt6 e;
    e << A(0, 0), A(1, 1), A(2, 2), A(1, 2) + A(2, 1), A(0, 2) + A(2, 0), A(0, 1) + A(1, 0);
    return e;
}
template <std::size_t N>
Eigen::Matrix<double, 3 * N, 1> linear_field(const std::array<vec3, N>& X, const Eigen::Matrix3d& A) {
    Eigen::Matrix<double, 3 * N, 1> u;
    for (std::size_t a = 0; a < N; ++a) {
        const Eigen::Vector3d x(X[a].x, X[a].y, X[a].z);
        u.template segment<3>(3 * static_cast<Eigen::Index>(a)) = A * x + Eigen::Vector3d(0.1, -0.2, 0.3);
    }
    return u;
}

}  // namespace

TEST_CASE("isotropic material: Hooke's law and validation", "[fem][material]") {
    const isotropic_material m{2000.0, 0.3};
    const Eigen::Matrix<double, 6, 6> S = m.elasticity().inverse();  // compliance, textbook form
    CHECK(S(0, 0) == Approx(1 / m.E));
    CHECK(S(0, 1) == Approx(-m.nu / m.E));
    CHECK(S(2, 1) == Approx(-m.nu / m.E));
    CHECK(S(3, 3) == Approx(2 * (1 + m.nu) / m.E));  // 1/G with engineering shear
    CHECK(S(5, 5) == Approx(1 / m.shear_modulus()));
    CHECK(m.lame_lambda() == Approx(2000.0 * 0.3 / (1.3 * 0.4)));
    CHECK_THROWS_AS((isotropic_material{-1, 0.3}.validate()), invalid_input);
    CHECK_THROWS_AS((isotropic_material{1, 0.5}.validate()), invalid_input);
    CHECK_THROWS_AS((isotropic_material{std::nan(""), 0.3}.validate()), invalid_input);
    CHECK_NOTHROW(isotropic_material::pla().validate());
    CHECK_NOTHROW(isotropic_material::abs().validate());
}

TEST_CASE("hex8: volume, rigid-body modes, constant strain", "[fem][hex8]") {
    const auto X = distorted_hex();
    const isotropic_material m{1000.0, 0.3};
    // A parallelepiped spanned by a, b, c has volume |det| (trilinear map is affine then).
    const vec3 a(2, 0.1, 0), b(0.3, 1.5, 0.1), c(0.2, -0.1, 1.1);
    hex8::nodes_t P;
    for (int i = 0; i < 8; ++i)
        P[i] = 0.5 * (hex8::corners[i][0] + 1) * a + 0.5 * (hex8::corners[i][1] + 1) * b + 0.5 * (hex8::corners[i][2] + 1) * c;
    CHECK(hex8::volume(P) == Approx(std::abs(glm::dot(a, glm::cross(b, c)))));

    const auto K = hex8::stiffness(X, m);
    CHECK((K - K.transpose()).norm() == 0.0);
    CHECK(count_zero_modes(K) == 6);
    // Rigid rotation about an axis: K * u = 0.
    Eigen::Matrix<double, 24, 1> r;
    for (int i = 0; i < 8; ++i) {
        const vec3 u = glm::cross(vec3(0.3, -0.5, 0.8), X[i]);
        r.segment<3>(3 * i) << u.x, u.y, u.z;
    }
    CHECK((K * r).norm() < 1e-10 * K.norm() * r.norm());
    // Constant strain reproduced exactly at any point of a distorted element.
    const auto u = linear_field(X, grad_A());
    for (const vec3 xi : {vec3(0.0), vec3(0.3, -0.7, 0.9), vec3(-1, 1, -1)})
        CHECK((hex8::strain_displacement(X, xi) * u - strain_of(grad_A())).norm() < 1e-14);
    // Body force: nodal loads sum to b * volume.
    const auto f = hex8::body_force(X, vec3(0, 0, -2.0));
    double fz = 0;
    for (int i = 0; i < 8; ++i) fz += f(3 * i + 2);
    CHECK(fz == Approx(-2.0 * hex8::volume(X)));
    // Inverted element (two nodes swapped) is refused.
    auto bad = X;
    std::swap(bad[0], bad[1]);
    CHECK_THROWS_AS(hex8::stiffness(bad, m), invalid_input);
}

TEST_CASE("wedge6: rigid-body modes, constant strain, quadrature exactness", "[fem][wedge6]") {
    const auto X = distorted_wedge();
    const isotropic_material m{1000.0, 0.25};
    const auto K = wedge6::stiffness(X, m);
    CHECK(count_zero_modes(K) == 6);
    const auto u = linear_field(X, grad_A());
    for (const vec3 xi : {wedge6::centroid(), vec3(0.6, 0.2, -0.4), vec3(0, 1, 1)})
        CHECK((wedge6::strain_displacement(X, xi) * u - strain_of(grad_A())).norm() < 1e-14);
    // Right prism (constant Jacobian): the 3x2 rule must equal a much finer rule (exactness).
    const wedge6::nodes_t R = {vec3(0, 0, 0), vec3(2, 0, 0), vec3(0.5, 1.5, 0), vec3(0.2, 0.1, 1), vec3(2.2, 0.1, 1), vec3(0.7, 1.6, 1)};
    // Reference: collapsed (Duffy) 4x4x4 Gauss rule, r = u, s = v (1 - u), exact to high degree.
    const double gp[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    const double gw[4] = {0.3478548451374539, 0.6521451548625461, 0.6521451548625461, 0.3478548451374539};
    Eigen::Matrix<double, 18, 18> Kref = Eigen::Matrix<double, 18, 18>::Zero();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) {
                const double uu = 0.5 * (gp[i] + 1), vv = 0.5 * (gp[j] + 1);
                const vec3 xi(uu, vv * (1 - uu), gp[k]);
                const auto B = wedge6::strain_displacement(R, xi);
                const double w = 0.25 * gw[i] * gw[j] * gw[k] * (1 - uu) * wedge6::jacobian_det(R, xi);
                Kref += B.transpose() * m.elasticity() * B * w;
            }
    CHECK((wedge6::stiffness(R, m) - Kref).norm() < 1e-12 * Kref.norm());
    CHECK(wedge6::volume(R) == Approx(0.5 * 2.0 * 1.5 * 1.0));
    const auto f = wedge6::body_force(X, vec3(1, 0, 0));
    double fx = 0;
    for (int i = 0; i < 6; ++i) fx += f(3 * i);
    CHECK(fx == Approx(wedge6::volume(X)));
}

TEST_CASE("shell3: rigid-body modes, DKT constant curvature, membrane patch", "[fem][shell3]") {
    const shell_section s{{1000.0, 0.3}, 0.5};
    const shell3::nodes_t X = {vec3(0.1, 0.2, 0.3), vec3(2.0, 0.5, -0.2), vec3(0.7, 1.9, 0.6)};
    const auto K = shell3::stiffness(X, s);
    CHECK(count_zero_modes(K) == 6);
    // Rigid rotation: translations theta x X, rotation dofs theta.
    const vec3 th(0.2, -0.4, 0.7);
    Eigen::Matrix<double, 18, 1> r;
    for (int i = 0; i < 3; ++i) {
        const vec3 u = glm::cross(th, X[i]);
        r.segment<6>(6 * i) << u.x, u.y, u.z, th.x, th.y, th.z;
    }
    CHECK((K * r).norm() < 1e-10 * K.norm() * r.norm());

    // DKT passes the constant-curvature patch test: w = a x^2 + b xy + c y^2 in the local plane,
    // nodal tx = w,y and ty = -w,x, gives beta = -grad w, so curvatures (-2a, -2c, -2b) everywhere.
    const auto f = shell3::local_frame(X);
    const double a = 0.3, b = -0.7, c = 0.45;
    Eigen::Matrix<double, 9, 1> ub;
    for (int i = 0; i < 3; ++i) {
        const double x = f.x[i], y = f.y[i];
        ub.segment<3>(3 * i) << a * x * x + b * x * y + c * y * y, b * x + 2 * c * y, -(2 * a * x + b * y);
    }
    for (const auto& p : {std::array<double, 2>{0.2, 0.3}, {0.0, 0.0}, {0.5, 0.5}, {0.1, 0.8}}) {
        const Eigen::Vector3d k = shell3::bending_b(f, p[0], p[1]) * ub;
        CHECK(k(0) == Approx(-2 * a).margin(1e-12));
        CHECK(k(1) == Approx(-2 * c).margin(1e-12));
        CHECK(k(2) == Approx(-2 * b).margin(1e-12));
    }
    // Membrane patch: in-plane uniaxial strain e along e1 gives sigma = E/(1-nu^2) e along e1.
    Eigen::Matrix<double, 18, 1> ue = Eigen::Matrix<double, 18, 1>::Zero();
    const double eps = 1e-3;
    for (int i = 0; i < 3; ++i) {
        const vec3 e1(f.R(0, 0), f.R(0, 1), f.R(0, 2));
        const vec3 u = eps * f.x[i] * e1;
        ue.segment<3>(6 * i) << u.x, u.y, u.z;
        // rz = in-plane rigid rotation = 0 for pure stretch
    }
    const voigt6 sg = shell3::stress(X, s, ue, shell3::centroid());
    Eigen::Matrix3d S;
    S << sg(0), sg(5), sg(4), sg(5), sg(1), sg(3), sg(4), sg(3), sg(2);
    const Eigen::Vector3d e1 = f.R.row(0).transpose(), e2 = f.R.row(1).transpose();
    CHECK(e1.dot(S * e1) == Approx(s.material.E / (1 - 0.09) * eps));
    CHECK(e2.dot(S * e2) == Approx(s.material.E * 0.3 / (1 - 0.09) * eps));
    // Pressure resultant = -p A n.
    const auto pl = shell3::pressure_load(X, 2.0);
    Eigen::Vector3d F = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) F += pl.segment<3>(6 * i);
    CHECK((F + 2.0 * f.area * f.R.row(2).transpose()).norm() < 1e-12);
    CHECK_THROWS_AS(shell3::stiffness({X[0], X[1], X[0] + 2.0 * (X[1] - X[0])}, s), invalid_input);
}
