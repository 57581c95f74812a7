// The solve context: every method (and the automatic choice) agrees with LDL^T on the oracle
// problems, refactorisation after stiffness-scale changes equals a fresh solve, several load
// cases share a factorization, singular systems are named on every path, results do not depend on
// the thread count; the deck writer round-trips; and CalculiX (ccx, an independent solver) gives
// the same displacements on a written deck.
#include <catch2/catch.hpp>

#include <signal.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/fem/inp.hpp"
#include "fabsynth/fem/inp_writer.hpp"
#include "fabsynth/fem/solve_context.hpp"
#include "fabsynth/fem/stress.hpp"
#include "support/ccx.hpp"

using namespace fabsynth;
using namespace fabsynth::fem;

namespace {

constexpr std::array<solver_method, 5> all_methods = {solver_method::ldlt, solver_method::cholmod, solver_method::cg, solver_method::cg_jacobi,
                                                       solver_method::amg};

struct problem {
    mesh m;
    load_case lc;
};

// Cantilever [0, L] x [0, W] x [0, W] (hex8), clamped at x = 0, gravity and a tip shear.
problem cantilever(int nx, int nw, double L = 100, double W = 20) {
    problem p;
    p.m = make_box_mesh(vec3(0.0), vec3(L, W, W), ivec3(nx, nw, nw), {isotropic_material::pla()});
    for (std::size_t i = 0; i < p.m.nodes.size(); ++i) {
        if (p.m.nodes[i].x == 0)
            for (int d = 0; d < 3; ++d) p.lc.fixed.push_back({static_cast<std::uint32_t>(i), d});
        if (p.m.nodes[i].x == L) p.lc.forces.push_back({static_cast<std::uint32_t>(i), 2, -0.5});
    }
    for (std::size_t e = 0; e < p.m.elements.size(); ++e) p.lc.gravity.push_back({static_cast<std::uint32_t>(e), vec3(0, 0, -9810.0)});
    return p;
}

// Square plate a x a (shell3), clamped edges, uniform pressure.
problem clamped_plate(int n, double a = 100, double t = 1) {
    problem p;
    p.m = make_rect_shell_mesh(a, a, n, n, {{1000.0, 0.3, 1e-9}, t});
    for (std::size_t i = 0; i < p.m.nodes.size(); ++i) {
        const vec3 x = p.m.nodes[i];
        if (x.x == 0 || x.y == 0 || x.x == a || x.y == a)
            for (int d = 0; d < 6; ++d) p.lc.fixed.push_back({static_cast<std::uint32_t>(i), d});
    }
    for (std::size_t e = 0; e < p.m.elements.size(); ++e) p.lc.pressures.push_back({static_cast<std::uint32_t>(e), 1e-3});
    return p;
}

double relative(const static_result& a, const static_result& b) { return (a.u - b.u).norm() / b.u.norm(); }

solve_options with(solver_method m) {
    solve_options o;
    o.method = m;
    o.amg.coarse_unknowns = 500;  // several AMG levels even on these small meshes
    return o;
}

}  // namespace

TEST_CASE("every method and the automatic choice agree with LDL^T", "[fem][solvers][context]") {
    for (const problem& p : {cantilever(24, 5), clamped_plate(24)}) {
        const static_result ref = solve_linear_static<ldlt_solver>(p.m, p.lc, {});
        for (solver_method method : all_methods) {
            if (!method_available(method)) continue;
            INFO("method " << method_name(method));
            solve_context ctx(p.m, p.lc, with(method));
            const static_result r = ctx.solve(p.lc);
            CHECK(relative(r, ref) < 1e-8);
            CHECK(r.solver == method_name(method));
            CHECK(ctx.statistics().analyses == 1);
            CHECK(ctx.statistics().factorizations == 1);
            // Reactions balance the loads in every method.
            const Eigen::VectorXd f = assemble_loads(p.m, r.dofs, p.lc);
            for (int d = 0; d < 3; ++d) {
                double fs = 0, rs = 0;
                for (std::size_t i = 0; i < p.m.nodes.size(); ++i)
                    fs += f(static_cast<Eigen::Index>(r.dofs.offset[i]) + d), rs += r.reactions(static_cast<Eigen::Index>(r.dofs.offset[i]) + d);
                CHECK(std::abs(fs + rs) <= 1e-8 * std::max(1.0, std::abs(fs)));
            }
        }
        // Automatic: LDL^T when small; above the limit AMG for solids, a direct method for shells.
        solve_options small;
        CHECK(solve_context(p.m, p.lc, small).statistics().method == "ldlt");
        solve_options large;
        large.direct_limit = 100;
        solve_context ctx(p.m, p.lc, large);
        const bool solid = p.m.elements[0].kind == element_kind::hex8;
        CHECK(ctx.statistics().method == (solid ? "amg" : method_available(solver_method::cholmod) ? "cholmod" : "ldlt"));
        CHECK(relative(ctx.solve(p.lc), ref) < 1e-8);
    }
}

TEST_CASE("SA-AMG hierarchy coarsens and preconditions well", "[fem][amg]") {
    const problem p = cantilever(40, 6);
    solve_context ctx(p.m, p.lc, with(solver_method::amg));
    const static_result r = ctx.solve(p.lc);
    // Mesh-independent convergence is the point of multigrid: a few dozen iterations at most.
    CHECK(r.iterations > 0);
    CHECK(r.iterations < 60);
    CHECK(r.relative_residual < 1e-11);
}

TEST_CASE("refactorisation after changing stiffness scales equals a fresh solve", "[fem][solvers][context][reuse]") {
    for (const problem& p0 : {cantilever(20, 4), clamped_plate(16)}) {
        for (solver_method method : all_methods) {
            if (!method_available(method)) continue;
            for (bool reuse : {true, false}) {
                INFO("method " << method_name(method) << " reuse " << reuse);
                solve_options o = with(method);
                o.reuse_preconditioner = reuse;
                solve_context ctx(p0.m, p0.lc, o);
                (void)ctx.solve(p0.lc);
                // Every 10th element becomes "empty" (rho_min = 1e-3), then a few go back to solid.
                mesh changed = p0.m;
                std::vector<std::size_t> ids;
                std::vector<double> scales;
                for (std::size_t e = 0; e < changed.elements.size(); e += 10) ids.push_back(e), scales.push_back(1e-3);
                ctx.set_stiffness_scales(ids, scales);
                for (std::size_t k = 0; k < ids.size(); k += 3) ctx.set_stiffness_scale(ids[k], 1.0);
                for (std::size_t k = 0; k < ids.size(); ++k) changed.elements[ids[k]].stiffness_scale = k % 3 == 0 ? 1.0 : 1e-3;
                const static_result again = ctx.solve(p0.lc);
                const static_result fresh = solve_linear_static<ldlt_solver>(changed, p0.lc, {});
                CHECK(relative(again, fresh) < 1e-8);
                CHECK(ctx.statistics().analyses == 1);  // the symbolic analysis is never repeated
                if (!reuse) CHECK(ctx.statistics().factorizations == 2);
                for (std::size_t e = 0; e < changed.elements.size(); ++e)
                    REQUIRE(ctx.model().elements[e].stiffness_scale == changed.elements[e].stiffness_scale);
            }
        }
    }
    // Bad scale changes are refused by name.
    const problem p = cantilever(4, 2);
    solve_context ctx(p.m, p.lc);
    CHECK_THROWS_WITH(ctx.set_stiffness_scale(999, 1.0), Catch::Contains("out of range"));
    CHECK_THROWS_WITH(ctx.set_stiffness_scale(0, std::nan("")), Catch::Contains("finite and > 0"));
    CHECK_THROWS_WITH(ctx.set_stiffness_scale(0, 0.0), Catch::Contains("finite and > 0"));
}

TEST_CASE("several load cases per factorization, prescribed values per solve", "[fem][solvers][context]") {
    const problem p = cantilever(12, 3);
    for (solver_method method : {solver_method::ldlt, solver_method::amg}) {
        INFO("method " << method_name(method));
        solve_context ctx(p.m, p.lc, with(method));
        load_case sideways = p.lc, settled = p.lc;
        sideways.gravity.clear();
        for (auto& f : sideways.forces) f.dof = 1;
        for (auto& fx : settled.fixed) fx.value = fx.dof == 2 ? -0.01 : 0.0;  // the clamp sinks 0.01 mm
        const std::vector<load_case> cases = {p.lc, sideways, settled};
        const std::vector<static_result> rs = ctx.solve(cases);
        REQUIRE(rs.size() == 3);
        CHECK(ctx.statistics().factorizations == 1);
        for (std::size_t k = 0; k < cases.size(); ++k) CHECK(relative(rs[k], solve_linear_static<ldlt_solver>(p.m, cases[k], {})) < 1e-8);
        // A load case cannot move the supports.
        load_case other = p.lc;
        other.fixed.pop_back();
        CHECK_THROWS_WITH(ctx.solve(other), Catch::Contains("differ from the context's"));
    }
}

TEST_CASE("singular systems are named on every solver path", "[fem][solvers][context][singular]") {
    mesh m = make_box_mesh(vec3(0.0), vec3(8, 2, 2), ivec3(4, 1, 1), {{1000.0, 0.3}});
    load_case pins;  // pins on one line: the bar can spin about it
    for (std::uint32_t i : {0u, 1u})
        for (int d = 0; d < 3; ++d) pins.fixed.push_back({i, d});
    pins.forces.push_back({static_cast<std::uint32_t>(m.nodes.size() - 1), 1, 1.0});
    load_case none = pins;
    none.fixed.clear();
    for (solver_method method : all_methods) {
        if (!method_available(method)) continue;
        INFO("method " << method_name(method));
        solve_options o = with(method);
        CHECK_THROWS_WITH(solve_linear_static(m, none, o), Catch::Contains("has no support"));
        CHECK_THROWS_WITH(solve_linear_static(m, pins, o), Catch::Contains("rotation about an axis"));
        o.check_supports = false;  // then the factorization or CG itself must notice
        o.max_iterations = 500;
        CHECK_THROWS_WITH(solve_linear_static(m, pins, o), Catch::Contains("singular"));
    }
}

TEST_CASE("solve context results do not depend on the thread count", "[fem][solvers][context]") {
    const problem p = cantilever(24, 4);
    for (solver_method method : {solver_method::ldlt, solver_method::amg, solver_method::cholmod}) {
        if (!method_available(method)) continue;
        set_num_threads(1);
        const static_result one = solve_linear_static(p.m, p.lc, with(method));
        set_num_threads(0);
        const static_result all = solve_linear_static(p.m, p.lc, with(method));
        CHECK((one.u - all.u).norm() == 0.0);
    }
}

namespace {
void ignore_signal(int) {}
}  // namespace

// METIS (inside the LDL^T ordering and CHOLMOD's analysis) swaps in its own SIGABRT/SIGTERM
// handlers and used to give the caller's back as one-shot handlers (SA_RESETHAND), so a tool's
// cleanup-on-SIGTERM handler was reset by a second signal: the dispositions must come back whole.
TEST_CASE("a solve leaves the caller's SIGTERM and SIGABRT handlers as they were", "[fem][solvers][context][signals]") {
    const problem p = cantilever(12, 3);
    struct sigaction mine {}, old_term {}, old_abrt {};
    mine.sa_handler = ignore_signal;
    mine.sa_flags = SA_RESTART;
    sigemptyset(&mine.sa_mask);
    ::sigaction(SIGTERM, &mine, &old_term);
    ::sigaction(SIGABRT, &mine, &old_abrt);
    for (solver_method method : {solver_method::ldlt, solver_method::cholmod}) {
        if (!method_available(method)) continue;
        INFO("method " << method_name(method));
        solve_options o = with(method);
        (void)solve_linear_static(p.m, p.lc, o);
        for (int sig : {SIGTERM, SIGABRT}) {
            struct sigaction now {};
            ::sigaction(sig, nullptr, &now);
            CHECK(now.sa_handler == &ignore_signal);
            CHECK((now.sa_flags & (SA_RESETHAND | SA_NODEFER)) == 0);
        }
    }
    ::sigaction(SIGTERM, &old_term, nullptr);
    ::sigaction(SIGABRT, &old_abrt, nullptr);
}

TEST_CASE("nodal von Mises averages the element stresses at each node", "[fem][stress]") {
    // A bar in uniaxial tension: every node sees sigma = F / A, so every nodal value is F / A.
    mesh m = make_box_mesh(vec3(0.0), vec3(10, 2, 2), ivec3(5, 1, 1), {{1000.0, 0.3}});
    load_case lc;
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
        const vec3 x = m.nodes[i];
        if (x.x == 0) {
            lc.fixed.push_back({static_cast<std::uint32_t>(i), 0});
            if (x.y == 0) lc.fixed.push_back({static_cast<std::uint32_t>(i), 1});
            if (x.z == 0) lc.fixed.push_back({static_cast<std::uint32_t>(i), 2});
        }
        if (x.x == 10) lc.forces.push_back({static_cast<std::uint32_t>(i), 0, 1.0});  // 4 N on 4 mm^2
    }
    const static_result r = solve_linear_static(m, lc);
    for (double v : nodal_von_mises(m, r)) CHECK(v == Approx(1.0).epsilon(1e-9));
    // Clamped plate: the largest nodal stress sits at the middle of an edge (bending), as in the
    // plate tables (Timoshenko & Woinowsky-Krieger: edge moment 0.0513 q a^2 > centre 0.0231 q a^2).
    const problem p = clamped_plate(16);
    const static_result rp = solve_linear_static(p.m, p.lc);
    const std::vector<double> vm = nodal_von_mises(p.m, rp);
    const std::size_t centre = 8 + 17 * 8, edge_mid = 8;
    CHECK(vm[edge_mid] > vm[centre]);
}

TEST_CASE("write_inp round-trips through parse_inp", "[fem][inp]") {
    problem p = cantilever(6, 2);
    p.m.elements[3].stiffness_scale = 1e-3;
    p.lc.fixed[0].value = 1e-4;
    const inp_deck d = parse_inp(write_inp(p.m, p.lc), "written.inp");
    REQUIRE(d.model.nodes.size() == p.m.nodes.size());
    REQUIRE(d.model.elements.size() == p.m.elements.size());
    for (std::size_t i = 0; i < p.m.nodes.size(); ++i) REQUIRE(d.model.nodes[i] == p.m.nodes[i]);
    const static_result a = solve_linear_static<ldlt_solver>(p.m, p.lc, {});
    const static_result b = solve_linear_static<ldlt_solver>(d.model, d.loads, {});
    CHECK(relative(b, a) < 1e-12);
    mesh bad = p.m;
    bad.node_ids.assign(bad.nodes.size(), 0);
    CHECK_THROWS_WITH(write_inp(bad, p.lc), Catch::Contains("not positive"));
}

TEST_CASE("CalculiX gives the same displacements on the written deck", "[fem][ccx][oracle]") {
    if (!test::have_ccx()) {
        WARN("ccx (Debian calculix-ccx) not found: CalculiX oracle skipped");
        return;
    }
    // A distorted cantilever (interior nodes moved) so that the comparison exercises the
    // isoparametric mapping, with gravity, a tip shear and a prescribed settlement.
    problem p = cantilever(16, 4, 80, 16);
    for (std::size_t i = 0; i < p.m.nodes.size(); ++i) {
        vec3& x = p.m.nodes[i];
        if (x.x > 0 && x.x < 80 && x.y > 0 && x.y < 16 && x.z > 0 && x.z < 16)
            x += 0.8 * vec3(std::sin(3.0 * static_cast<double>(i)), std::cos(5.0 * static_cast<double>(i)), std::sin(7.0 * static_cast<double>(i)));
    }
    p.lc.fixed[5].value = -0.002;
    const std::filesystem::path dir = std::filesystem::path(FABSYNTH_TEST_TMP) / "ccx";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "deck.inp") << write_inp(p.m, p.lc, {.heading = "fabsynth oracle", .print_displacements = true});
    const std::string cmd = "cd '" + dir.string() + "' && ccx -i deck > ccx.log 2>&1";
    REQUIRE(std::system(cmd.c_str()) == 0);
    const auto ccx = test::read_ccx_displacements(dir / "deck.dat");
    REQUIRE(ccx.size() == p.m.nodes.size());
    for (solver_method method : {solver_method::automatic, solver_method::amg, solver_method::ldlt}) {
        INFO("method " << method_name(method));
        const static_result r = solve_linear_static(p.m, p.lc, with(method));
        double umax = 0, err = 0;
        for (std::size_t i = 0; i < p.m.nodes.size(); ++i) {
            const vec3 u = r.displacement(i);
            const auto& c = ccx.at(static_cast<long>(i) + 1);
            umax = std::max(umax, glm::length(u));
            for (int k = 0; k < 3; ++k) err = std::max(err, std::abs(u[k] - c[static_cast<std::size_t>(k)]));
        }
        INFO("max |u| " << umax << " mm, max difference " << err << " mm");
        CHECK(err < 1e-6 * umax);  // ccx prints 7 significant digits
    }
}

TEST_CASE("large-shell methods converge to the clamped plate table", "[fem][shell][plate][context]") {
    // Timoshenko & Woinowsky-Krieger, Table 35: clamped square plate, w_centre = 0.00126 q a^4 / D.
    const double a = 100, t = 1, q = 1e-3, E = 1000, nu = 0.3;
    const double exact = 0.00126 * q * a * a * a * a / (E * t * t * t / (12 * (1 - nu * nu)));
    solve_options large;
    large.direct_limit = 1000;  // what automatic does above the limit on a shell mesh
    for (solver_method method : {solver_method::automatic, solver_method::amg}) {
        INFO("method " << method_name(method));
        large.method = method;
        double previous_error = INFINITY;
        for (int n : {8, 16, 32}) {
            const problem p = clamped_plate(n, a, t);
            solve_context ctx(p.m, p.lc, large);
            const static_result r = ctx.solve(p.lc);
            const auto centre = static_cast<std::size_t>(n / 2 + (n + 1) * (n / 2));
            const double error = std::abs(-r.displacement(centre).z - exact) / exact;
            INFO("n " << n << " centre deflection " << -r.displacement(centre).z << " table " << exact << " via " << ctx.statistics().method);
            CHECK(error < previous_error);
            if (n == 32) CHECK(error < 0.01);
            previous_error = error;
        }
    }
}

TEST_CASE("the symbolic analysis predicts the direct factor before it is computed", "[fem][solvers][context]") {
    const problem p = cantilever(24, 5);
    solve_context ldlt(p.m, p.lc, with(solver_method::ldlt));
    const solve_statistics before = ldlt.statistics();
    CHECK(before.factorizations == 0);
    REQUIRE(before.predicted_factor_bytes > 0);
    REQUIRE(before.predicted_factor_flops > 0);
    (void)ldlt.solve(p.lc);
    // the numeric factor has exactly the predicted entries (a double and an int index each)
    CHECK(before.predicted_factor_bytes == ldlt.statistics().stored_entries * 12.0);
    // at least one operation per entry and at most (entries per column)^2 per column
    CHECK(before.predicted_factor_flops >= ldlt.statistics().stored_entries);
    CHECK(before.predicted_factor_flops <= ldlt.statistics().stored_entries * static_cast<double>(before.free_dofs));
    if (method_available(solver_method::cholmod)) {
        // CHOLMOD counts the operations of its own (supernodal, own ordering) analysis: the same order
        solve_context cm(p.m, p.lc, with(solver_method::cholmod));
        const double ratio = cm.statistics().predicted_factor_flops / before.predicted_factor_flops;
        CHECK(ratio > 0.5);
        CHECK(ratio < 2.0);
        (void)cm.solve(p.lc);
        CHECK(cm.statistics().predicted_factor_bytes == cm.statistics().stored_entries * 8.0);
    }
    for (solver_method m : {solver_method::cg, solver_method::cg_jacobi, solver_method::amg}) {
        solve_context it(p.m, p.lc, with(m));
        CHECK(it.statistics().predicted_factor_bytes == 0);
        CHECK(it.statistics().predicted_factor_flops == 0);
    }
}
