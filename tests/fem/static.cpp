// Linear static solves against independent oracles: mesh patch tests, Timoshenko cantilever,
// Timoshenko & Woinowsky-Krieger plate tables, solver agreement and singular-system detection.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "fabsynth/fem/assembly.hpp"
#include "fabsynth/fem/boundary.hpp"
#include "fabsynth/fem/mesh.hpp"
#include "fabsynth/fem/solve_context.hpp"
#include "fabsynth/fem/stress.hpp"

using namespace fabsynth;
using namespace fabsynth::fem;

namespace {

Eigen::Matrix3d patch_gradient() {
    Eigen::Matrix3d A;
    A << 1e-3, 2e-4, -3e-4, 5e-4, -2e-3, 1e-4, -4e-4, 3e-4, 1.5e-3;
    return A;
}
vec3 patch_field(const vec3& x) {
    const Eigen::Vector3d u = patch_gradient() * Eigen::Vector3d(x.x, x.y, x.z) + Eigen::Vector3d(0.01, -0.02, 0.03);
    return vec3(u(0), u(1), u(2));
}

// 2x2x2 box of size 2 with every node except the corners jiggled (deterministically).
mesh distorted_box(bool wedges) {
    mesh m = make_box_mesh(vec3(0.0), vec3(2.0), ivec3(2), {{1000.0, 0.3}});
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
        const vec3 p = m.nodes[i];
        const bool interior = p.x > 0 && p.x < 2 && p.y > 0 && p.y < 2 && p.z > 0 && p.z < 2;
        const double s = interior ? 0.25 : 0.0;
        m.nodes[i] += s * vec3(std::sin(3.0 * static_cast<double>(i)), std::cos(5.0 * static_cast<double>(i)), std::sin(7.0 * static_cast<double>(i) + 1));
    }
    if (wedges) {  // split every hex into two prisms along the diagonal 0-2 of its bottom face
        std::vector<element> w;
        for (const element& e : m.elements) {
            const auto& n = e.nodes;
            w.push_back(make_element<wedge6>({n[0], n[1], n[2], n[4], n[5], n[6]}));
            w.push_back(make_element<wedge6>({n[0], n[2], n[3], n[4], n[6], n[7]}));
        }
        m.elements = w;
    }
    return m;
}

bool on_boundary(const vec3& p, double lo, double hi) {
    auto b = [&](double v) { return std::abs(v - lo) < 1e-12 || std::abs(v - hi) < 1e-12; };
    return b(p.x) || b(p.y) || b(p.z);
}

// Cantilever [0,L] x [0,W] x [0,H] clamped at x = 0, total shear force P (-z) spread over the
// end face x = L with consistent (bilinear) nodal weights. Returns mean tip uz.
double cantilever_tip(int nh, double L, double W, double H, const isotropic_material& mat, double P) {
    const ivec3 n(10 * nh * static_cast<int>(L / (10 * H)), nh, nh);
    mesh m = make_box_mesh(vec3(0.0), vec3(L, W, H), n, {mat});
    load_case lc;
    const double face = W * H;
    double tip = 0;
    int tip_n = 0;
    for (int k = 0; k <= n.z; ++k)
        for (int j = 0; j <= n.y; ++j) {
            const auto root = static_cast<std::uint32_t>((n.x + 1) * (j + (n.y + 1) * k));
            for (int d = 0; d < 3; ++d) lc.fixed.push_back({root, d});
            const double wy = (j == 0 || j == n.y) ? 0.5 : 1.0, wz = (k == 0 || k == n.z) ? 0.5 : 1.0;
            lc.forces.push_back({root + static_cast<std::uint32_t>(n.x), 2, -P * wy * wz / (n.y * n.z) * face / face});
        }
    const auto r = solve_linear_static(m, lc);
    for (int k = 0; k <= n.z; ++k)
        for (int j = 0; j <= n.y; ++j) tip += r.displacement(static_cast<std::size_t>(n.x + (n.x + 1) * (j + (n.y + 1) * k))).z, ++tip_n;
    return -tip / tip_n;
}

enum class plate_support { simply_supported, clamped };

// Square shell plate a x a, thickness t, uniform pressure q (pushing -z); centre deflection.
double plate_center(int n, plate_support bc) {
    const double a = 100, t = 1, q = 1e-3;
    mesh m = make_rect_shell_mesh(a, a, n, n, {{1000.0, 0.3}, t});
    load_case lc;
    for (std::size_t e = 0; e < m.elements.size(); ++e) lc.pressures.push_back({static_cast<std::uint32_t>(e), q});
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const auto id = static_cast<std::uint32_t>(i + (n + 1) * j);
            const bool ex = (i == 0 || i == n), ey = (j == 0 || j == n);
            if (!ex && !ey) continue;
            if (bc == plate_support::clamped) {
                for (int d = 0; d < 6; ++d) lc.fixed.push_back({id, d});
            } else {
                lc.fixed.push_back({id, 2});
                // Hard simple support: w = 0 along the edge also kills the rotation about the edge normal.
                if (ex) lc.fixed.push_back({id, 3});
                if (ey) lc.fixed.push_back({id, 4});
            }
        }
    if (bc == plate_support::simply_supported) {  // in-plane rigid motion
        lc.fixed.push_back({0, 0});
        lc.fixed.push_back({0, 1});
        lc.fixed.push_back({static_cast<std::uint32_t>(n), 1});
    }
    const auto r = solve_linear_static(m, lc);
    const auto c = static_cast<std::size_t>(n / 2 + (n + 1) * (n / 2));
    return -r.displacement(c).z;  // pressure along +n pushes towards -z
}

}  // namespace

TEST_CASE("patch test: distorted hex8 and wedge6 meshes reproduce a linear field exactly", "[fem][patch]") {
    for (bool wedges : {false, true}) {
        INFO((wedges ? "wedge6" : "hex8"));
        const mesh m = distorted_box(wedges);
        load_case lc;
        for (std::size_t i = 0; i < m.nodes.size(); ++i)
            if (on_boundary(m.nodes[i], 0, 2)) {
                const vec3 u = patch_field(m.nodes[i]);
                for (int d = 0; d < 3; ++d) lc.fixed.push_back({static_cast<std::uint32_t>(i), d, u[d]});
            }
        const auto r = solve_linear_static(m, lc);
        const vec3 c = m.nodes[13];  // the jiggled centre node
        REQUIRE(!on_boundary(c, 0, 2));
        CHECK(glm::length(r.displacement(13) - patch_field(c)) < 1e-12);
        const voigt6 expect = isotropic_material{1000.0, 0.3}.elasticity() *
                              (voigt6() << 1e-3, -2e-3, 1.5e-3, 1e-4 + 3e-4, -3e-4 - 4e-4, 2e-4 + 5e-4).finished();
        for (const auto& pts : gauss_point_stresses(m, r))
            for (const auto& s : pts) CHECK((s - expect).norm() < 1e-9 * expect.norm());
        // Reactions balance: the free body has no net external force (no loads applied).
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (std::size_t i = 0; i < m.nodes.size(); ++i) sum += r.reactions.segment<3>(static_cast<Eigen::Index>(r.dofs.offset[i]));
        CHECK(sum.norm() < 1e-9);
    }
}

TEST_CASE("hex8 cantilever converges to Timoshenko beam theory", "[fem][cantilever]") {
    const double L = 100, W = 10, H = 10, P = 10;
    const isotropic_material mat{1000.0, 0.0};  // nu = 0: no anticlastic end effects in the 3D model
    const double I = W * H * H * H / 12, A = W * H, kappa = 5.0 / 6;  // Timoshenko / Cowper shear factor at nu = 0
    const double exact = P * L * L * L / (3 * mat.E * I) + P * L / (kappa * mat.shear_modulus() * A);
    const double d1 = cantilever_tip(1, L, W, H, mat, P), d2 = cantilever_tip(2, L, W, H, mat, P), d4 = cantilever_tip(4, L, W, H, mat, P);
    INFO("tip deflections " << d1 << " " << d2 << " " << d4 << " exact " << exact);
    // Full integration: stiff (locking) from below, O(h^2): each halving cuts the error towards 4x
    // (measured 33% -> 11% -> 3.1%), and Richardson extrapolation lands on Timoshenko's value.
    const double e1 = exact - d1, e2 = exact - d2, e4 = exact - d4;
    CHECK(e1 > e2);
    CHECK(e2 > e4);
    CHECK(e4 > 0);
    CHECK(e1 / e2 > 2.5);
    CHECK(e2 / e4 > 3.3);
    CHECK(e4 / exact < 0.035);
    CHECK(std::abs(d4 + (d4 - d2) / 3 - exact) / exact < 0.01);
}

TEST_CASE("DKT shell plate matches Timoshenko & Woinowsky-Krieger tables", "[fem][shell][plate]") {
    const double a = 100, t = 1, q = 1e-3, E = 1000, nu = 0.3;
    const double D = E * t * t * t / (12 * (1 - nu * nu));
    for (auto bc : {plate_support::simply_supported, plate_support::clamped}) {
        const double alpha = bc == plate_support::simply_supported ? 0.00406 : 0.00126;
        const double exact = alpha * q * a * a * a * a / D;
        const double w8 = plate_center(8, bc), w16 = plate_center(16, bc), w32 = plate_center(32, bc);
        INFO("centre deflections " << w8 << " " << w16 << " " << w32 << " table " << exact);
        CHECK(std::abs(w32 - exact) / exact < 0.01);
        CHECK(std::abs(w32 - w16) < std::abs(w16 - w8) / 3.0);  // O(h^2)
    }
}

TEST_CASE("solver policies agree", "[fem][solvers]") {
    mesh m = make_box_mesh(vec3(0.0), vec3(40, 8, 8), ivec3(10, 3, 3), {isotropic_material::pla()});
    m.elements[5].stiffness_scale = 1e-3;  // a soft element as in the paper's rho_min
    load_case lc;
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
        if (m.nodes[i].x == 0)
            for (int d = 0; d < 3; ++d) lc.fixed.push_back({static_cast<std::uint32_t>(i), d});
        if (m.nodes[i].x == 40) lc.forces.push_back({static_cast<std::uint32_t>(i), 2, -1.0});
    }
    for (std::size_t e = 0; e < m.elements.size(); ++e) lc.gravity.push_back({static_cast<std::uint32_t>(e), vec3(0, 0, -9810.0)});
    const auto ref = solve_linear_static(m, lc);
    auto rel = [&](const static_result& r) { return (r.u - ref.u).norm() / ref.u.norm(); };
    CHECK(rel(solve_linear_static<cg_ichol_solver>(m, lc)) < 1e-8);
    CHECK(rel(solve_linear_static<cg_jacobi_solver>(m, lc)) < 1e-8);
#if defined(FABSYNTH_HAS_CHOLMOD)
    CHECK(rel(solve_linear_static<cholmod_solver>(m, lc)) < 1e-8);
#endif
    // Equilibrium: reactions balance the applied loads (gravity + tip forces).
    const Eigen::VectorXd f = assemble_loads(m, ref.dofs, lc);
    double fz = 0, rz = 0;
    for (std::size_t i = 0; i < m.nodes.size(); ++i) fz += f(static_cast<Eigen::Index>(ref.dofs.offset[i] + 2)), rz += ref.reactions(static_cast<Eigen::Index>(ref.dofs.offset[i] + 2));
    const double weight = isotropic_material::pla().density * 9810.0 * 40 * 8 * 8;
    CHECK(fz == Approx(-16 - weight));
    CHECK(rz == Approx(16 + weight));
    // Thread count does not change a single bit.
    set_num_threads(1);
    const auto one = solve_linear_static(m, lc);
    set_num_threads(0);
    CHECK((one.u - ref.u).norm() == 0.0);
}

TEST_CASE("singular systems raise solver_error naming the cause", "[fem][solvers][singular]") {
    mesh m = make_box_mesh(vec3(0.0), vec3(4, 2, 2), ivec3(2, 1, 1), {{1000.0, 0.3}});
    load_case lc;
    lc.forces.push_back({5, 2, -1.0});
    // 1. no supports at all
    CHECK_THROWS_WITH(solve_linear_static(m, lc), Catch::Contains("has no support"));
    CHECK_THROWS_AS(solve_linear_static<cg_jacobi_solver>(m, lc), solver_error);
    // 2. a second, disconnected block without support
    mesh two = m;
    const auto off = static_cast<std::uint32_t>(two.nodes.size());
    for (std::size_t i = 0; i < m.nodes.size(); ++i) two.nodes.push_back(m.nodes[i] + vec3(10, 0, 0));
    element e = m.elements[0];
    for (auto& n : e.nodes) n += off;
    two.elements.push_back(e);
    load_case lc2 = lc;
    for (std::uint32_t i = 0; i < off; ++i)
        if (m.nodes[i].x == 0)
            for (int d = 0; d < 3; ++d) lc2.fixed.push_back({i, d});
    CHECK_NOTHROW(solve_linear_static(m, lc2));
    CHECK_THROWS_WITH(solve_linear_static(two, lc2), Catch::Contains("part 2 of 2") && Catch::Contains("no support"));
    // 3. supports on one line: 6 fixed DOFs but free to rotate about the line
    load_case lc3 = lc;
    for (std::uint32_t i : {0u, 1u})
        for (int d = 0; d < 3; ++d) lc3.fixed.push_back({i, d});
    CHECK_THROWS_WITH(solve_linear_static(m, lc3), Catch::Contains("rotation about an axis"));
    // 4. without the support check, LDLT's pivot test catches the mechanism
    solve_options unchecked;
    unchecked.check_supports = false;
    CHECK_THROWS_WITH(solve_linear_static(m, lc3, unchecked), Catch::Contains("pivot"));
    // 5. bad input
    load_case lc4 = lc2;
    lc4.forces.push_back({0, 4, 1.0});  // rotation dof on a solid node
    CHECK_THROWS_AS(solve_linear_static(m, lc4), invalid_input);
    mesh bad = m;
    bad.elements[0].stiffness_scale = std::nan("");
    CHECK_THROWS_AS(solve_linear_static(bad, lc2), invalid_input);
}

TEST_CASE("an inverted element is named by its label and its nodes' labels", "[fem][assembly]") {
    mesh m = make_box_mesh(vec3(0.0), vec3(4, 2, 2), ivec3(2, 1, 1), {{1000.0, 0.3}});
    // swap the bottom and top faces of element 1: it is inside out
    auto& nodes = m.elements[1].nodes;
    for (int a = 0; a < 4; ++a) std::swap(nodes[a], nodes[a + 4]);
    const std::array<std::uint32_t, 8> inverted = nodes;
    CHECK_THROWS_WITH(assemble_stiffness(m, dof_map(m)), Catch::StartsWith("fabsynth: element 1 (nodes ") && Catch::Contains("inverted"));
    // with the labels of a deck
    m.element_ids = {101, 102};
    m.node_ids.resize(m.nodes.size());
    for (std::size_t i = 0; i < m.nodes.size(); ++i) m.node_ids[i] = static_cast<std::int64_t>(1000 + i);
    std::string nodes_text;
    for (std::uint32_t n : inverted) nodes_text += (nodes_text.empty() ? "" : " ") + std::to_string(1000 + n);
    CHECK_THROWS_WITH(assemble_stiffness(m, dof_map(m)), Catch::StartsWith("fabsynth: element 102 (nodes " + nodes_text + "): "));
}
