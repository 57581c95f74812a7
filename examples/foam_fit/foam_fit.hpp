#pragma once
/// @file foam_fit.hpp  The computation behind the foam_fit tool (procedural-voronoi-foams.md §4.1):
/// homogenize periodic procedural Voronoi foam samples over a grid of (rho, tau), fit the degree-4
/// polynomial E = P(rho, tau) and the Gibson-Ashby law E/Es = C w^n (§4.3.1), and write the data
/// points (CSV), the generated coefficients header and a plot (plot.hpp). Kept out of main.cpp so
/// the tests can run it end to end (tests/foam/elasticity_fit_run.cpp).
///
/// One sample (rho, tau, seed):
///  - base volume: a cube of side S = elements * h with element (voxel) size h = tau, i.e. half the
///    beam diameter as the paper recommends (§4.1); the paper's >= 60^3 elements is the default;
///  - periodic seeds (seeds.hpp, foam_options::period): period P coarse cells per axis, coarse cell
///    L = S / P with P chosen so that a coarse cell holds about `seeds_per_cell` seeds
///    (t = L^3 rho ~ 4 by default: the un-subdivided regime of Algorithm 3, as a 2-5 mm cell in a
///    typical print has); L >= tau is enforced (the evaluator needs tau <= L);
///  - voxel density = supersampled coverage (s^3 samples) of the voxel by the foam (§4.1: "the
///    volume of structure intersected by the element");
///  - fem::homogenize with Es = 1, nu = 0.3, stiffness linear in the density; floating islands are
///    removed there; fem::fit_isotropic (eq. 1) gives E, nu and the isotropy error (its relative
///    residual ||C^I - C^H||_F / ||C^H||_F). w = mean voxel density (relative volume).
/// Samples are computed one after the other, each with all threads (coverage and FEM loops run
/// through core/parallel.hpp), so the output is byte-identical for any thread count.
///
/// Cache: with config::cache set, finished samples are stored there (rewritten atomically after
/// each sample) and reused by later runs with identical sample parameters, so a long run can be
/// resumed and the outputs regenerated without recomputing.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <fabsynth/core.hpp>
#include <fabsynth/fem/homogenization.hpp>
#include <fabsynth/foam.hpp>
#include <fabsynth/io/detail/atomic_file.hpp>
#include <fabsynth/voxel/grid.hpp>

namespace fabsynth::foam_fit {

/// One grid point of the fit.
struct grid_pair {
    double rho = 0;  ///< seeds/mm^3
    double tau = 0;  ///< mm
};

/// Everything foam_fit needs.
struct config {
    std::vector<grid_pair> pairs;        ///< (rho, tau) grid
    int seeds_per_pair = 3;              ///< realisations per pair (as the paper)
    std::uint64_t first_seed = 1;        ///< global seeds first_seed, first_seed + 1, ...
    int elements = 60;                   ///< hexahedral elements per side (paper: >= 60)
    int supersample = 4;                 ///< s: s^3 coverage samples per element
    double seeds_per_cell = 4.0;         ///< target seeds per coarse cell (sets the period)
    double tolerance = 1e-6;             ///< relative residual of each FEM solve (1e-3 and 1e-6 gave E equal to 5 digits)
    double omega_lo = 0.04, omega_hi = 0.5;  ///< Gibson-Ashby fit range (paper §4.3.1)
    /// Residual the polynomial fit minimises. The paper's is absolute; the default is relative
    /// because the moduli span two decades and the inverse mapping is used with relative targets
    /// (absolute: 45% error at the softest sample, relative: a few %; see data/foam/README.md).
    foam::fit_error fit = foam::fit_error::relative;
    std::string csv, header, plot, cache;    ///< outputs (empty = not written)
};

/// A homogenized sample plus what was done to get it.
struct sample_result {
    foam::elasticity_sample s;
    double removed_fraction = 0;  ///< floating islands removed before the FEM solve
    std::int64_t period = 0;      ///< coarse cells per axis
    int iterations = 0;           ///< CG iterations over the six load cases
    double seconds = 0;           ///< wall time (not written to the CSV: not reproducible)
    bool cached = false;
};

/// Summary of a run.
struct report {
    std::vector<sample_result> samples;
    foam::elasticity_polynomial P;
    double max_deviation = 0;  ///< max_i |P(rho_i, tau_i) - E_i| / E_i
    double max_deviation_other = 0;  ///< the same for a fit with the other objective (for comparison)
    foam::power_law gibson_ashby;
    bool gibson_ashby_ok = false;
    double seconds = 0;
};

/// Full-block density bound 1 / (2 tau)^3 (paper §4.2).
[[nodiscard]] inline double full_block_density(double tau) { return 1.0 / (8.0 * tau * tau * tau); }

/// Throws invalid_input naming the first bad parameter.
inline void validate(const config& c) {
    if (c.pairs.empty()) throw invalid_input("foam_fit: the (rho, tau) grid is empty");
    for (const grid_pair& p : c.pairs) {
        if (!(std::isfinite(p.tau) && p.tau > 0))
            throw invalid_input("foam_fit: beam radius tau = " + std::to_string(p.tau) + " mm must be finite and > 0");
        if (!(std::isfinite(p.rho) && p.rho > 0))
            throw invalid_input("foam_fit: density rho = " + std::to_string(p.rho) + " seeds/mm^3 must be finite and > 0");
        if (p.rho > full_block_density(p.tau))
            throw invalid_input("foam_fit: density rho = " + std::to_string(p.rho) + " exceeds the full-block bound 1/(2 tau)^3 = " +
                                std::to_string(full_block_density(p.tau)) + " for tau = " + std::to_string(p.tau));
    }
    if (c.seeds_per_pair < 1) throw invalid_input("foam_fit: seeds per pair must be >= 1");
    if (c.elements < 8 || c.elements > 256)
        throw invalid_input("foam_fit: elements per side must lie in [8, 256], got " + std::to_string(c.elements));
    if (c.elements % 2 != 0)
        throw invalid_input("foam_fit: elements per side must be even (the periodic multigrid coarsens by 2), got " +
                            std::to_string(c.elements));
    if (c.supersample < 1 || c.supersample > 16) throw invalid_input("foam_fit: supersampling must lie in [1, 16]");
    if (!(std::isfinite(c.seeds_per_cell) && c.seeds_per_cell >= 1 && c.seeds_per_cell <= 8))
        throw invalid_input("foam_fit: seeds per coarse cell must lie in [1, 8]");
    if (!(c.tolerance > 0 && c.tolerance < 1e-2)) throw invalid_input("foam_fit: tolerance must lie in (0, 0.01)");
    if (!(c.omega_lo >= 0 && c.omega_lo < c.omega_hi && c.omega_hi <= 1))
        throw invalid_input("foam_fit: Gibson-Ashby range needs 0 <= lo < hi <= 1");
}

/// "%.17g": doubles that read back bit-exactly.
[[nodiscard]] inline std::string exact(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

/// Coarse cells per axis of a sample's period (see the file comment).
[[nodiscard]] inline std::int64_t sample_period(double rho, double side, double tau, double seeds_per_cell) {
    const double p = std::round(std::cbrt(rho * side * side * side / seeds_per_cell));
    const auto max_p = static_cast<std::int64_t>(std::floor(side / tau + 1e-9));  // L >= tau
    return std::clamp(static_cast<std::int64_t>(p), std::int64_t{1}, std::max<std::int64_t>(1, max_p));
}

/// Voxel densities of one periodic sample: coverage of each of the n^3 elements (side h = tau),
/// equal to voronoi_foam::coverage(centre, h, s) sample for sample. For speed the Voronoi edge
/// pieces are gathered once per block of 4^3 elements (voronoi_foam::edges_in_box on the block
/// grown by tau: every edge point within tau of a sample of the block lies in it), then each
/// element tests its s^3 samples against the pieces whose bounding box comes within tau of it.
[[nodiscard]] inline voxel_grid<double> sample_densities(double rho, double tau, std::uint64_t seed, const config& c,
                                                         std::int64_t* period_out = nullptr) {
    const int n = c.elements, s = c.supersample;
    const double h = tau, side = n * h;
    const std::int64_t P = sample_period(rho, side, tau, c.seeds_per_cell);
    if (period_out) *period_out = P;
    const double L = side / static_cast<double>(P);
    const foam::voronoi_foam foam(foam::constant_field{rho}, foam::constant_field{tau},
                                  {.cell = L, .seed = seed, .period = i64vec3(P)});
    constexpr int B = 4;
    const int nb = (n + B - 1) / B;
    const std::size_t blocks = static_cast<std::size_t>(nb) * nb * nb;
    std::vector<double> cov(static_cast<std::size_t>(n) * n * n);
    const double t2 = tau * tau;
    parallel_for(0, blocks, [&](std::size_t b) {
        const ivec3 lo(static_cast<int>(b % nb) * B, static_cast<int>((b / nb) % nb) * B, static_cast<int>(b / (std::size_t(nb) * nb)) * B);
        const ivec3 hi = glm::min(lo + ivec3(B), ivec3(n));
        std::vector<foam::edge_segment> edges, near;
        foam.edges_in_box(box3(vec3(lo) * h - vec3(tau), vec3(hi) * h + vec3(tau)), edges);
        for (int z = lo.z; z < hi.z; ++z)
            for (int y = lo.y; y < hi.y; ++y)
                for (int x = lo.x; x < hi.x; ++x) {
                    const vec3 vlo = vec3(x, y, z) * h - vec3(tau), vhi = vec3(x + 1, y + 1, z + 1) * h + vec3(tau);
                    near.clear();
                    for (const auto& e : edges)
                        if (glm::all(glm::lessThanEqual(glm::min(e.a, e.b), vhi)) && glm::all(glm::greaterThanEqual(glm::max(e.a, e.b), vlo)))
                            near.push_back(e);
                    // same sample positions and test as voronoi_foam::coverage
                    const vec3 q = (vec3(x, y, z) + 0.5) * h;
                    int count = 0;
                    for (int k = 0; k < s; ++k)
                        for (int j = 0; j < s; ++j)
                            for (int i = 0; i < s; ++i) {
                                const vec3 p = q - vec3(0.5 * h) + h * (vec3(i, j, k) + 0.5) / double(s);
                                for (const auto& e : near)
                                    if (segment_distance2(p, e.a, e.b) <= t2) {
                                        ++count;
                                        break;
                                    }
                            }
                    cov[(static_cast<std::size_t>(z) * n + y) * n + x] = double(count) / double(s * s * s);
                }
    });
    voxel_grid<double> g({n, n, n}, vec3(0.0), h);
    for (std::size_t i = 0; i < cov.size(); ++i)
        g.set(ivec3(static_cast<int>(i % n), static_cast<int>((i / n) % n), static_cast<int>(i / (std::size_t(n) * n))), cov[i]);
    return g;
}

/// Homogenizes one sample (see the file comment).
[[nodiscard]] inline sample_result homogenize_sample(double rho, double tau, std::uint64_t seed, const config& c) {
    const auto t0 = std::chrono::steady_clock::now();
    sample_result r;
    const voxel_grid<double> g = sample_densities(rho, tau, seed, c, &r.period);
    fem::homogenization_options opt;
    opt.solver.tolerance = c.tolerance;
    const fem::homogenization_result h = fem::homogenize(g, {1.0, 0.3}, opt);
    const fem::isotropic_fit fit = fem::fit_isotropic(h.C, 1.0);
    r.s = {.density = rho, .radius = tau, .seed = seed, .E = fit.E, .nu = fit.nu, .anisotropy = fit.relative_residual,
           .volume_fraction = h.volume_fraction};
    r.removed_fraction = h.removed_fraction;
    for (const auto& st : h.stats) r.iterations += st.iterations;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

/// The fit points of the degree-4 polynomial: every homogenized sample (rho, tau) together with
/// its exact scale equivalents (rho (tau / t)^3, t) at each other sampled radius t. Why: the sample
/// of (rho, tau) is the sample of (rho s^3, tau / s) scaled by s — side 60 tau, element size tau,
/// the period in coarse cells (a function of rho tau^3), the coarse cell and every seed position
/// all scale with tau — and C^H does not depend on scale, so E is a function of f = rho (2 tau)^3
/// alone (tests/foam/elasticity_fit_run.cpp checks this by homogenizing a scaled sample). The
/// paper fits P on a uniform (rho, tau) grid of independent samples; here each computed sample
/// covers its whole curve rho tau^3 = const, so a fit on the equivalents is a fit on a full grid
/// (same number of points per radius) at 1/(number of radii) of the cost. Documented deviation.
[[nodiscard]] inline std::vector<foam::elasticity_sample> fit_points(const std::vector<foam::elasticity_sample>& samples) {
    std::vector<double> taus;
    for (const auto& s : samples)
        if (std::find(taus.begin(), taus.end(), s.radius) == taus.end()) taus.push_back(s.radius);
    std::sort(taus.begin(), taus.end());
    std::vector<foam::elasticity_sample> out;
    for (const auto& s : samples)
        for (double t : taus) {
            foam::elasticity_sample e = s;
            if (t != s.radius) {
                const double k = s.radius / t;
                e.density = s.density * k * k * k, e.radius = t;
            }
            out.push_back(e);
        }
    return out;
}

/// The degree-4 fit of §4.1 on fit_points(samples) and its largest relative deviation there.
[[nodiscard]] inline std::pair<foam::elasticity_polynomial, double> fit_elasticity(const std::vector<foam::elasticity_sample>& samples,
                                                                                    foam::fit_error error = foam::fit_error::relative) {
    const std::vector<foam::elasticity_sample> pts = fit_points(samples);
    foam::elasticity_polynomial P = foam::fit_polynomial(pts, 4, error);
    return {P, foam::max_relative_deviation(P, pts)};
}

namespace detail {
[[nodiscard]] inline std::string cache_key(double rho, double tau, std::uint64_t seed, const config& c) {
    return exact(rho) + "," + exact(tau) + "," + std::to_string(seed) + "," + std::to_string(c.elements) + "," +
           std::to_string(c.supersample) + "," + exact(c.seeds_per_cell) + "," + exact(c.tolerance);
}
inline constexpr const char* cache_head = "rho,tau,seed,elements,supersample,seeds_per_cell,tolerance,omega,E,nu,isotropy_error,removed_fraction,period,iterations";

inline std::map<std::string, sample_result> read_cache(const std::string& path) {
    std::map<std::string, sample_result> m;
    std::ifstream in(path);
    if (!in) return m;
    std::string line;
    std::getline(in, line);
    if (line != cache_head) throw io_error("foam_fit: " + path + " is not a foam_fit cache (unexpected header)");
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string t; std::getline(ss, t, ',');) f.push_back(t);
        if (f.size() != 14) throw io_error("foam_fit: malformed cache line in " + path + ": " + line);
        sample_result r;
        try {
            r.s.density = std::stod(f[0]), r.s.radius = std::stod(f[1]), r.s.seed = std::stoull(f[2]);
            r.s.volume_fraction = std::stod(f[7]), r.s.E = std::stod(f[8]), r.s.nu = std::stod(f[9]), r.s.anisotropy = std::stod(f[10]);
            r.removed_fraction = std::stod(f[11]), r.period = std::stoll(f[12]), r.iterations = std::stoi(f[13]);
        } catch (const std::exception&) {
            throw io_error("foam_fit: malformed number in cache " + path + ": " + line);
        }
        r.cached = true;
        m[f[0] + "," + f[1] + "," + f[2] + "," + f[3] + "," + f[4] + "," + f[5] + "," + f[6]] = r;
    }
    return m;
}

inline void write_cache(const std::string& path, const std::map<std::string, sample_result>& m) {
    std::ostringstream o;
    o << cache_head << "\n";
    for (const auto& [k, r] : m)
        o << k << "," << exact(r.s.volume_fraction) << "," << exact(r.s.E) << "," << exact(r.s.nu) << "," << exact(r.s.anisotropy) << ","
          << exact(r.removed_fraction) << "," << r.period << "," << r.iterations << "\n";
    io::detail::atomic_write(path, o.str());
}
}  // namespace detail

/// CSV of the data points (header line, then one line per sample, doubles in "%.17g").
[[nodiscard]] inline std::string format_csv(const std::vector<sample_result>& v) {
    std::ostringstream o;
    o << "rho,tau,seed,omega,E,nu,isotropy_error\n";
    for (const sample_result& r : v)
        o << exact(r.s.density) << "," << exact(r.s.radius) << "," << r.s.seed << "," << exact(r.s.volume_fraction) << ","
          << exact(r.s.E) << "," << exact(r.s.nu) << "," << exact(r.s.anisotropy) << "\n";
    return o.str();
}

/// Reads a CSV written by format_csv. Throws io_error for a missing or malformed file.
[[nodiscard]] inline std::vector<foam::elasticity_sample> read_csv(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw io_error("foam_fit: cannot read " + path.string());
    std::string line;
    if (!std::getline(in, line) || line != "rho,tau,seed,omega,E,nu,isotropy_error")
        throw io_error("foam_fit: " + path.string() + " does not start with the foam_fit CSV header");
    std::vector<foam::elasticity_sample> out;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string t; std::getline(ss, t, ',');) f.push_back(t);
        if (f.size() != 7) throw io_error("foam_fit: malformed line in " + path.string() + ": " + line);
        foam::elasticity_sample s;
        try {
            s.density = std::stod(f[0]), s.radius = std::stod(f[1]), s.seed = std::stoull(f[2]);
            s.volume_fraction = std::stod(f[3]), s.E = std::stod(f[4]), s.nu = std::stod(f[5]), s.anisotropy = std::stod(f[6]);
        } catch (const std::exception&) {
            throw io_error("foam_fit: malformed number in " + path.string() + ": " + line);
        }
        out.push_back(s);
    }
    return out;
}

/// The generated header include/fabsynth/foam/elasticity_fit.hpp (pure data, no includes needed).
[[nodiscard]] inline std::string format_header(const config& c, const report& r) {
    double rmin = 1e300, rmax = 0, tmin = 1e300, tmax = 0, amax = 0, numin = 1, numax = -1, fmin = 1e300, fmax = 0;
    for (const auto& x : r.samples) {
        const double f = x.s.density / full_block_density(x.s.radius);
        fmin = std::min(fmin, f), fmax = std::max(fmax, f);
        rmin = std::min(rmin, x.s.density), rmax = std::max(rmax, x.s.density);
        tmin = std::min(tmin, x.s.radius), tmax = std::max(tmax, x.s.radius);
        amax = std::max(amax, x.s.anisotropy), numin = std::min(numin, x.s.nu), numax = std::max(numax, x.s.nu);
    }
    std::ostringstream o;
    o << "#pragma once\n"
      << "/// @file elasticity_fit.hpp  GENERATED by examples/foam_fit (do not edit by hand; re-run foam_fit,\n"
      << "/// see data/foam/README.md). Degree-" << r.P.degree << " least-squares fit E/Es = P(rho, tau) of\n"
      << "/// procedural-voronoi-foams.md §4.1 to homogenized periodic foam samples (Es = 1, nu_s = 0.3).\n"
      << "///\n"
      << "/// Provenance: " << r.samples.size() << " samples = " << c.pairs.size() << " (rho, tau) pairs x " << c.seeds_per_pair
      << " global seeds (" << c.first_seed << ".." << c.first_seed + static_cast<std::uint64_t>(c.seeds_per_pair) - 1 << ");\n"
      << "/// rho in [" << exact(rmin) << ", " << exact(rmax) << "] seeds/mm^3, tau in [" << exact(tmin) << ", " << exact(tmax)
      << "] mm;\n"
      << "/// base volume " << c.elements << "^3 hexahedral elements of side tau (sample side " << c.elements
      << " tau), coverage supersampled " << c.supersample << "^3 per element,\n"
      << "/// ~" << exact(c.seeds_per_cell) << " seeds per coarse cell, FEM tolerance " << exact(c.tolerance) << ".\n"
      << "/// The fit uses each sample and its exact scale equivalents (rho (tau/t)^3, t) at the other sampled\n"
      << "/// radii t (E depends on rho (2 tau)^3 only; see foam_fit::fit_points).\n"
      << "/// Objective: " << (c.fit == foam::fit_error::relative ? "relative residuals sum ((P - E) / E)^2 (paper: absolute)" : "absolute residuals sum (P - E)^2 (as the paper)") << ".\n"
      << "/// Largest deviation of a fit point from the fit: " << exact(r.max_deviation * 100) << "% of its E (paper: 3.3%;\n"
      << "/// with the " << (c.fit == foam::fit_error::relative ? "absolute" : "relative") << " objective: " << exact(r.max_deviation_other * 100) << "%).\n";
    if (r.gibson_ashby_ok)
        o << "/// Gibson-Ashby fit on " << exact(c.omega_lo) << " < w < " << exact(c.omega_hi) << " (" << r.gibson_ashby.samples_used
          << " samples): C = " << exact(r.gibson_ashby.C) << ", n = " << exact(r.gibson_ashby.n) << " (paper: 0.85, 1.95).\n";
    o << "/// Fitted Poisson's ratio range [" << exact(numin) << ", " << exact(numax) << "]; largest isotropy error " << exact(amax)
      << ".\n"
      << "/// Valid only inside the sampled (rho, tau) region (the polynomial is not monotone far outside it).\n"
      << "#include <cstddef>\n\n"
      << "namespace fabsynth::foam::fitted {\n\n"
      << "/// Coefficients in elasticity_polynomial order: by total degree, then decreasing power of rho.\n"
      << "inline constexpr int degree = " << r.P.degree << ";\n"
      << "inline constexpr double coefficients[] = {\n";
    for (std::size_t i = 0; i < r.P.coeffs.size(); ++i) o << "    " << exact(r.P.coeffs[i]) << (i + 1 < r.P.coeffs.size() ? ",\n" : "\n");
    o << "};\n"
      << "inline constexpr double max_relative_deviation = " << exact(r.max_deviation) << ";\n"
      << "inline constexpr double rho_min = " << exact(rmin) << ", rho_max = " << exact(rmax) << ";  ///< sampled densities, seeds/mm^3\n"
      << "inline constexpr double tau_min = " << exact(tmin) << ", tau_max = " << exact(tmax) << ";  ///< sampled radii, mm\n"
      << "/// Sampled band of f = rho (2 tau)^3 (fraction of the full-block density; E depends on f only).\n"
      << "inline constexpr double fraction_min = " << exact(fmin) << ", fraction_max = " << exact(fmax) << ";\n"
      << "inline constexpr double gibson_ashby_C = " << exact(r.gibson_ashby_ok ? r.gibson_ashby.C : 0.0)
      << ", gibson_ashby_n = " << exact(r.gibson_ashby_ok ? r.gibson_ashby.n : 0.0) << ";\n"
      << "inline constexpr std::size_t samples = " << r.samples.size() << ";\n"
      << "inline constexpr int elements = " << c.elements << ", supersample = " << c.supersample << ", seeds_per_pair = " << c.seeds_per_pair
      << ";\n\n"
      << "}  // namespace fabsynth::foam::fitted\n";
    return o.str();
}

/// Runs the whole computation and writes the outputs named in `c`. `log` receives one line per
/// sample. The plot is written by the caller-supplied `plot` function (may be empty).
inline report run(const config& c, const std::function<void(const std::string&)>& log = {},
                  const std::function<void(const config&, const report&)>& plot = {}) {
    validate(c);
    const auto t0 = std::chrono::steady_clock::now();
    std::map<std::string, sample_result> cache;
    if (!c.cache.empty()) cache = detail::read_cache(c.cache);
    report rep;
    const std::size_t total = c.pairs.size() * static_cast<std::size_t>(c.seeds_per_pair);
    for (const grid_pair& p : c.pairs)
        for (int k = 0; k < c.seeds_per_pair; ++k) {
            const std::uint64_t seed = c.first_seed + static_cast<std::uint64_t>(k);
            const std::string key = detail::cache_key(p.rho, p.tau, seed, c);
            sample_result r;
            if (auto it = cache.find(key); it != cache.end()) r = it->second;
            else {
                r = homogenize_sample(p.rho, p.tau, seed, c);
                if (!c.cache.empty()) {
                    cache[key] = r;
                    detail::write_cache(c.cache, cache);
                }
            }
            rep.samples.push_back(r);
            if (log) {
                char buf[320];
                std::snprintf(buf, sizeof buf,
                              "[%zu/%zu] rho %.4g tau %.4g seed %llu: w %.4f E %.5g nu %.4f iso %.4f islands %.4f period %lld "
                              "iters %d %s %.1f s",
                              rep.samples.size(), total, p.rho, p.tau, static_cast<unsigned long long>(seed), r.s.volume_fraction,
                              r.s.E, r.s.nu, r.s.anisotropy, r.removed_fraction, static_cast<long long>(r.period), r.iterations,
                              r.cached ? "(cached)" : "", r.seconds);
                log(buf);
            }
        }
    std::vector<foam::elasticity_sample> s;
    for (const auto& r : rep.samples) s.push_back(r.s);
    const int ncoef = 15;
    if (static_cast<int>(fit_points(s).size()) >= ncoef) {
        std::tie(rep.P, rep.max_deviation) = fit_elasticity(s, c.fit);
        rep.max_deviation_other =
            fit_elasticity(s, c.fit == foam::fit_error::relative ? foam::fit_error::absolute : foam::fit_error::relative).second;
    } else {
        rep.P.degree = 4;  // too few samples for the degree-4 fit: no polynomial (reported, no header)
    }
    try {
        rep.gibson_ashby = foam::fit_power_law(s, c.omega_lo, c.omega_hi);
        rep.gibson_ashby_ok = true;
    } catch (const no_solution&) {
        rep.gibson_ashby_ok = false;
    }
    if (!c.csv.empty()) io::detail::atomic_write(c.csv, format_csv(rep.samples));
    if (!c.header.empty()) {
        if (rep.P.coeffs.empty())
            throw invalid_input("foam_fit: " + std::to_string(s.size()) + " samples are fewer than the 15 coefficients of the degree-4 "
                                "polynomial; cannot write the coefficients header");
        io::detail::atomic_write(c.header, format_header(c, rep));
    }
    if (!c.plot.empty() && plot) plot(c, rep);
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return rep;
}

}  // namespace fabsynth::foam_fit
