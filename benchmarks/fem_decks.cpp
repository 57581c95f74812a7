// fem_solve against CalculiX (ccx, Debian calculix-ccx) on the same decks, in the same run, as
// separate processes: wall time, peak resident memory (getrusage of the child) and the largest
// displacement difference to ccx relative to max |u|. Decks: C3D8 cantilevers of 2.5 mm elements
// (nx x ny x nz), PLA, gravity, clamped at x = 0, written by fem::write_inp.
// In-process: the solve context's refactorisation after changing 1% of the element scales vs a
// fresh solve, and the shell3 path on a 57 k-vertex, 114 k-triangle vase (340 k DOFs).
#include <benchmark/benchmark.h>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "fabsynth/fem/inp_writer.hpp"
#include "fabsynth/fem/solve_context.hpp"
#include "fabsynth/fem/stress.hpp"

namespace fem = fabsynth::fem;
namespace fs = std::filesystem;

namespace {

fs::path work_dir() {
    const fs::path d = fs::temp_directory_path() / "fabsynth_bench_fem_decks";
    fs::create_directories(d);
    return d;
}

fem::mesh cantilever_mesh(int nx, int ny, int nz) {
    const double h = 2.5;
    return fem::make_box_mesh(fabsynth::vec3(0.0), fabsynth::vec3(nx * h, ny * h, nz * h), fabsynth::ivec3(nx, ny, nz), {fem::isotropic_material::pla()});
}
fem::load_case cantilever_loads(const fem::mesh& m) {
    fem::load_case lc;
    for (std::size_t i = 0; i < m.nodes.size(); ++i)
        if (m.nodes[i].x == 0)
            for (int k = 0; k < 3; ++k) lc.fixed.push_back({static_cast<std::uint32_t>(i), k, 0.0});
    for (std::size_t e = 0; e < m.elements.size(); ++e) lc.gravity.push_back({static_cast<std::uint32_t>(e), {0, 0, -9810.0}});
    return lc;
}

std::string deck_name(int nx, int ny, int nz) {
    std::string name = "c";  // appended, not "c" + std::string&&: GCC 12 warns falsely (-Wrestrict) on that
    for (const int n : {nx, ny, nz}) {
        if (name.size() > 1) name += 'x';
        name += std::to_string(n);
    }
    return name;
}

fs::path deck(int nx, int ny, int nz) {
    const fs::path p = work_dir() / (deck_name(nx, ny, nz) + ".inp");
    if (!fs::exists(p)) {
        const fem::mesh m = cantilever_mesh(nx, ny, nz);
        std::ofstream(p) << fem::write_inp(m, cantilever_loads(m), {.heading = "cantilever", .print_displacements = true});
    }
    return p;
}

struct run_result {
    double seconds = 0;
    double peak_mb = 0;
    int status = -1;
};

// Runs argv in dir as a child process; wall time and the child's peak RSS.
run_result run(const std::vector<std::string>& argv, const fs::path& dir) {
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        if (chdir(dir.c_str()) != 0) _exit(127);
        std::vector<char*> args;
        for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        const int devnull = ::open("/dev/null", 1);
        if (devnull >= 0) dup2(devnull, 1), dup2(devnull, 2);
        execvp(args[0], args.data());
        _exit(127);
    }
    int status = 0;
    rusage ru{};
    wait4(pid, &status, 0, &ru);
    run_result r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.peak_mb = static_cast<double>(ru.ru_maxrss) / 1024.0;
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

using displacements = std::map<long, std::array<double, 3>>;
displacements read_ccx(const fs::path& dat) {
    std::ifstream in(dat);
    displacements u;
    std::string line;
    bool block = false;
    while (std::getline(in, line)) {
        if (line.find("displacements") != std::string::npos) { block = true; continue; }
        std::istringstream s(line);
        long n;
        std::array<double, 3> v;
        if (block && s >> n >> v[0] >> v[1] >> v[2]) u[n] = v;
    }
    return u;
}
displacements read_fem_solve(const fs::path& csv) {
    std::ifstream in(csv);
    displacements u;
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
        for (char& c : line) if (c == ',') c = ' ';
        std::istringstream s(line);
        long n;
        std::array<double, 3> v;
        if (s >> n >> v[0] >> v[1] >> v[2]) u[n] = v;
    }
    return u;
}
double max_relative_difference(const displacements& a, const displacements& b) {
    double umax = 0, err = 0;
    for (const auto& [n, v] : a) {
        const auto it = b.find(n);
        if (it == b.end()) return INFINITY;
        umax = std::max(umax, std::hypot(v[0], v[1], v[2]));
        for (int k = 0; k < 3; ++k) err = std::max(err, std::abs(v[k] - it->second[k]));
    }
    return umax > 0 ? err / umax : err;
}

std::map<std::string, displacements>& ccx_results() {
    static std::map<std::string, displacements> r;
    return r;
}

void BM_calculix(benchmark::State& state) {
    const int nx = static_cast<int>(state.range(0)), ny = static_cast<int>(state.range(1)), nz = static_cast<int>(state.range(2));
    const fs::path p = deck(nx, ny, nz);
    const std::string stem = deck_name(nx, ny, nz);
    run_result r;
    for (auto _ : state) {
        r = run({"ccx", "-i", stem}, work_dir());
        state.SetIterationTime(r.seconds);
    }
    if (r.status != 0) {
        state.SkipWithError("ccx not found or failed (Debian calculix-ccx)");
        return;
    }
    ccx_results()[stem] = read_ccx(work_dir() / (stem + ".dat"));
    state.counters["peak_MB"] = r.peak_mb;
    state.counters["dofs"] = 3.0 * (nx + 1) * (ny + 1) * (nz + 1);
}

void BM_fem_solve(benchmark::State& state, const char* solver) {
    const int nx = static_cast<int>(state.range(0)), ny = static_cast<int>(state.range(1)), nz = static_cast<int>(state.range(2));
    const fs::path p = deck(nx, ny, nz);
    const std::string stem = deck_name(nx, ny, nz);
    const fs::path out = work_dir() / (stem + "_" + solver);
    run_result r;
    for (auto _ : state) {
        r = run({FABSYNTH_FEM_SOLVE, p.string(), "-o", out.string(), "--solver", solver, "--quiet"}, work_dir());
        state.SetIterationTime(r.seconds);
    }
    if (r.status != 0) {
        state.SkipWithError("fem_solve failed");
        return;
    }
    state.counters["peak_MB"] = r.peak_mb;
    if (const auto it = ccx_results().find(stem); it != ccx_results().end())
        state.counters["max_rel_diff_vs_ccx"] = max_relative_difference(read_fem_solve(out / "displacements.csv"), it->second);
}

// Refactorisation with an unchanged pattern: 1% of the elements (every 100th) get a new scale
// (alternately 1e-3 and back to 1, as the structural loop of structurally-sound-patterns.md
// sec. 5.2 does), then a solve; compared with a fresh context on the changed mesh.
void BM_refactor(benchmark::State& state, fem::solver_method method, bool reuse) {
    fem::mesh m = cantilever_mesh(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), static_cast<int>(state.range(2)));
    const fem::load_case lc = cantilever_loads(m);
    fem::solve_options opt;
    opt.method = method;
    opt.reuse_preconditioner = reuse;
    fem::solve_context ctx(m, lc, opt);
    (void)ctx.solve(lc);
    std::vector<std::size_t> ids;
    for (std::size_t e = 0; e < m.elements.size(); e += 100) ids.push_back(e);
    int round = 0;
    for (auto _ : state) {
        const std::vector<double> scales(ids.size(), ++round % 2 ? 1e-3 : 1.0);
        ctx.set_stiffness_scales(ids, scales);
        const fem::static_result r = ctx.solve(lc);
        benchmark::DoNotOptimize(r.u.data());
    }
    state.counters["cg_iterations"] = static_cast<double>(ctx.statistics().last_iterations);
    state.counters["factorizations"] = ctx.statistics().factorizations;
}
void BM_fresh(benchmark::State& state, fem::solver_method method) {
    fem::mesh m = cantilever_mesh(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), static_cast<int>(state.range(2)));
    for (std::size_t e = 0; e < m.elements.size(); e += 100) m.elements[e].stiffness_scale = 1e-3;
    const fem::load_case lc = cantilever_loads(m);
    fem::solve_options opt;
    opt.method = method;
    for (auto _ : state) {
        fem::solve_context ctx(m, lc, opt);
        const fem::static_result r = ctx.solve(lc);
        benchmark::DoNotOptimize(r.u.data());
    }
}

// An open vase (surface of revolution, the paper's vase and lamp shapes): nt x nz vertices,
// 240 x 238 = 57 120 vertices and 113 760 triangles = 342 720 DOFs; PLA, 1 mm thick; bottom ring
// clamped; gravity and 0.01 MPa inner pressure.
struct shell_problem {
    fem::mesh m;
    fem::load_case lc;
};
shell_problem vase(int nt, int nz) {
    shell_problem p;
    p.m.sections.push_back({fem::isotropic_material::pla(), 1.0});
    const double height = 200;
    for (int k = 0; k < nz; ++k) {
        const double z = height * k / (nz - 1), radius = 50 + 20 * std::sin(z / height * 1.5 * std::numbers::pi);
        for (int i = 0; i < nt; ++i) {
            const double a = 2 * std::numbers::pi * i / nt;
            p.m.nodes.emplace_back(radius * std::cos(a), radius * std::sin(a), z);
        }
    }
    auto id = [&](int i, int k) { return static_cast<std::uint32_t>(i % nt + nt * k); };
    for (int k = 0; k + 1 < nz; ++k)
        for (int i = 0; i < nt; ++i) {  // outward normals
            p.m.elements.push_back(fem::make_element<fem::shell3>({id(i, k), id(i + 1, k), id(i + 1, k + 1)}));
            p.m.elements.push_back(fem::make_element<fem::shell3>({id(i, k), id(i + 1, k + 1), id(i, k + 1)}));
        }
    for (int i = 0; i < nt; ++i)
        for (int d = 0; d < 6; ++d) p.lc.fixed.push_back({id(i, 0), d});
    for (std::size_t e = 0; e < p.m.elements.size(); ++e) {
        p.lc.gravity.push_back({static_cast<std::uint32_t>(e), {0, 0, -9810.0}});
        p.lc.pressures.push_back({static_cast<std::uint32_t>(e), -0.01});  // positive against the normal: -0.01 pushes outward
    }
    return p;
}

void BM_shell_vase(benchmark::State& state, fem::solver_method method) {
    const shell_problem p = vase(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    fem::solve_options opt;
    opt.method = method;
    double vm_max = 0;
    std::string chosen;
    for (auto _ : state) {
        fem::solve_context ctx(p.m, p.lc, opt);
        const fem::static_result r = ctx.solve(p.lc);
        const std::vector<double> vm = fem::nodal_von_mises(p.m, r);
        vm_max = *std::max_element(vm.begin(), vm.end());
        chosen = ctx.statistics().method;
    }
    state.counters["dofs"] = 6.0 * static_cast<double>(p.m.nodes.size());
    state.counters["max_nodal_von_mises_MPa"] = vm_max;
    state.SetLabel(chosen);
}

}  // namespace

// Cantilever decks: ccx first, so the fem_solve rows can report their difference to it.
#define FABSYNTH_DECKS(b) b->Args({40, 16, 16})->Args({64, 24, 24})->Args({96, 32, 32})
FABSYNTH_DECKS(BENCHMARK(BM_calculix))->UseManualTime()->Iterations(1)->Unit(benchmark::kSecond);
FABSYNTH_DECKS(BENCHMARK_CAPTURE(BM_fem_solve, auto, "auto"))->UseManualTime()->Iterations(1)->Unit(benchmark::kSecond);
FABSYNTH_DECKS(BENCHMARK_CAPTURE(BM_fem_solve, amg, "amg"))->UseManualTime()->Iterations(1)->Unit(benchmark::kSecond);
FABSYNTH_DECKS(BENCHMARK_CAPTURE(BM_fem_solve, cg, "cg"))->UseManualTime()->Iterations(1)->Unit(benchmark::kSecond);
FABSYNTH_DECKS(BENCHMARK_CAPTURE(BM_fem_solve, cg_jacobi, "cg-jacobi"))->UseManualTime()->Iterations(1)->Unit(benchmark::kSecond);
#if defined(FABSYNTH_HAS_CHOLMOD)
FABSYNTH_DECKS(BENCHMARK_CAPTURE(BM_fem_solve, cholmod, "cholmod"))->UseManualTime()->Iterations(1)->Unit(benchmark::kSecond);
#endif
// SimplicialLDLT is not supernodal: minutes at 64 x 24 x 24, so only the smallest deck.
BENCHMARK_CAPTURE(BM_fem_solve, ldlt, "ldlt")->Args({40, 16, 16})->UseManualTime()->Iterations(1)->Unit(benchmark::kSecond);

BENCHMARK_CAPTURE(BM_refactor, amg_reuse, fem::solver_method::amg, true)->Args({64, 24, 24})->Iterations(4)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_refactor, amg_rebuild, fem::solver_method::amg, false)->Args({64, 24, 24})->Iterations(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_fresh, amg, fem::solver_method::amg)->Args({64, 24, 24})->Iterations(2)->Unit(benchmark::kMillisecond);
#if defined(FABSYNTH_HAS_CHOLMOD)
BENCHMARK_CAPTURE(BM_refactor, cholmod_reuse, fem::solver_method::cholmod, true)->Args({64, 24, 24})->Iterations(4)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_refactor, cholmod_refactorize, fem::solver_method::cholmod, false)->Args({64, 24, 24})->Iterations(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_fresh, cholmod, fem::solver_method::cholmod)->Args({64, 24, 24})->Iterations(2)->Unit(benchmark::kMillisecond);
#endif

BENCHMARK_CAPTURE(BM_shell_vase, auto, fem::solver_method::automatic)->Args({240, 238})->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_shell_vase, amg, fem::solver_method::amg)->Args({240, 238})->Iterations(1)->Unit(benchmark::kSecond);
