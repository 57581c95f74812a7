// Voxel FEM benchmarks: a clamped solid cube cantilever at n^3 voxels (multigrid-CG), and the
// periodic homogenization (six load cases) of a 60^3 gyroid-sheet foam sample.
// Counters: dofs, CG iterations, multigrid levels, peak resident memory of the process [MB]
// (getrusage; the homogenization runs first and the cantilevers in increasing size, so the peak
// belongs to the current case). The CPU column is the CPU time of all threads of the process
// (MeasureProcessCPUTime): on a shared machine wall time is inflated by other load, and
// CPU time / threads is the wall time an idle machine would show at perfect scaling.
#include <benchmark/benchmark.h>

#include <fabsynth/fem/homogenization.hpp>
#include <fabsynth/fem/voxel.hpp>
#include <fabsynth/voxel/grid.hpp>

#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <numbers>

using namespace fabsynth;

namespace {

double peak_rss_mb() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

void BM_homogenize_gyroid(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    // Gyroid sheet |sin x cos y + sin y cos z + sin z cos x| < 0.5 with one period per cell:
    // a connected porous sample (~30% solid) that can be generated deterministically.
    voxel_grid<double> g({n, n, n}, vec3(0.0), 1.0 / n, 0.0);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double x = 2 * std::numbers::pi * (i + 0.5) / n, y = 2 * std::numbers::pi * (j + 0.5) / n,
                             z = 2 * std::numbers::pi * (k + 0.5) / n;
                const double v = std::sin(x) * std::cos(y) + std::sin(y) * std::cos(z) + std::sin(z) * std::cos(x);
                g.set({i, j, k}, std::abs(v) < 0.5 ? 1.0 : 0.0);
            }
    fem::homogenization_result r;
    for (auto _ : state) {
        r = fem::homogenize(g, {1.0, 0.3});
        benchmark::DoNotOptimize(r.C.data());  // (DoNotOptimize on a double lvalue may clobber it with GCC 12)
    }
    int it = 0;
    for (const auto& s : r.stats) it += s.iterations;
    state.counters["dofs"] = static_cast<double>(r.stats[0].dofs);
    state.counters["iterations_total"] = it;
    state.counters["levels"] = r.stats[0].levels;
    state.counters["volume_fraction"] = r.volume_fraction;
    char label[96];
    std::snprintf(label, sizeof label, "C11=%.5g C12=%.5g C44=%.5g (E=1, nu=0.3)", r.C(0, 0), r.C(0, 1), r.C(3, 3));
    state.SetLabel(label);
    state.counters["peak_rss_MB"] = peak_rss_mb();
}
BENCHMARK(BM_homogenize_gyroid)->Arg(60)->Unit(benchmark::kSecond)->Iterations(1)->MeasureProcessCPUTime()->UseRealTime();

void BM_voxel_cantilever(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    const double h = 1.0;
    voxel_grid<double> g({n, n, n}, vec3(0.0), h, 1.0);
    fem::voxel_boundary_conditions bc(g.dims());
    const double total = 100.0;  // N, downward, spread over the free end face (consistent weights)
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j) {
            bc.fix(0, j, k);
            const double w = (j == 0 || j == n ? 0.5 : 1.0) * (k == 0 || k == n ? 0.5 : 1.0);
            bc.add_force(n, j, k, {0, 0, -total * w / (double(n) * n)});
        }
    fem::voxel_solver_options opt;
    opt.tolerance = 1e-8;
    fem::voxel_solution sol;
    for (auto _ : state) {
        sol = fem::solve_voxel_elasticity(g, fem::isotropic_material::pla(), bc, opt);
        benchmark::DoNotOptimize(sol.u.data());
    }
    state.counters["dofs"] = static_cast<double>(sol.stats.dofs);
    state.counters["iterations"] = sol.stats.iterations;
    state.counters["levels"] = sol.stats.levels;
    state.counters["setup_s"] = sol.stats.setup_seconds;
    state.counters["solve_s"] = sol.stats.solve_seconds;
    state.counters["peak_rss_MB"] = peak_rss_mb();
}
BENCHMARK(BM_voxel_cantilever)->Arg(32)->Arg(64)->Arg(96)->Unit(benchmark::kSecond)->Iterations(1)->MeasureProcessCPUTime()->UseRealTime();

// A thin hollow sphere (outer radius 0.48 n voxels, 3 voxels thick, 100 mm across), standing on
// its bottom 5% (clamped), under its own weight (ABS, gravity -z): the sparse case of the surface
// pattern validation (the bunny shell at 256^3 is 644 k voxels in a 17 M voxel box; this one at
// 256^3 is ~580 k voxels, 3.5% of its box). Run it alone (--benchmark_filter=shell) for its own
// peak_rss_MB.
void BM_voxel_shell(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    const double h = 100.0 / n, R = 0.48 * n, c = 0.5 * n;
    voxel_grid<double> g({n, n, n}, vec3(0.0), h, 0.0);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double r = std::sqrt((i + 0.5 - c) * (i + 0.5 - c) + (j + 0.5 - c) * (j + 0.5 - c) + (k + 0.5 - c) * (k + 0.5 - c));
                if (r <= R && r > R - 3.0) g.set({i, j, k}, 1.0);
            }
    fem::voxel_boundary_conditions bc(g.dims());
    const double weight = 1040.0 * 9.81 * 1e-9 * h * h * h / 8.0;  // N per voxel corner
    std::size_t voxels = 0;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                if (g.get({i, j, k}) == 0.0) continue;
                ++voxels;
                for (int a = 0; a < 8; ++a) {
                    const int x = i + fem::detail::voxel_corner[a][0], y = j + fem::detail::voxel_corner[a][1], z = k + fem::detail::voxel_corner[a][2];
                    if (k < n / 20) bc.fix(x, y, z);
                    bc.add_force(x, y, z, {0, 0, -weight});
                }
            }
    fem::voxel_solver_options opt;
    opt.tolerance = 1e-8;
    fem::voxel_solution sol;
    for (auto _ : state) {
        sol = fem::solve_voxel_elasticity(g, fem::isotropic_material{2000.0, 0.35}, bc, opt);
        benchmark::DoNotOptimize(sol.u.data());
    }
    state.counters["voxels"] = static_cast<double>(voxels);
    state.counters["dofs"] = static_cast<double>(sol.stats.dofs);
    state.counters["iterations"] = sol.stats.iterations;
    state.counters["levels"] = sol.stats.levels;
    state.counters["setup_s"] = sol.stats.setup_seconds;
    state.counters["solve_s"] = sol.stats.solve_seconds;
    state.counters["compliance"] = sol.compliance;
    state.counters["peak_rss_MB"] = peak_rss_mb();
}
BENCHMARK(BM_voxel_shell)->Arg(128)->Arg(256)->Unit(benchmark::kSecond)->Iterations(1)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace
