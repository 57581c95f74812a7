// SPDX-License-Identifier: MIT
#pragma once
/// @file elasticity_study.hpp  The whole elasticity fit of procedural-voronoi-foams.md §4.1 over a
/// (rho, tau) grid: homogenize every (pair, seed) sample (elasticity_samples.hpp), fit the degree-4
/// polynomial E = P(rho, tau) on the samples and their scale equivalents (fit.hpp: fit_elasticity)
/// and the Gibson-Ashby law E/Es = C w^n (§4.3.1). Text outputs (CSV, sample cache, the generated
/// coefficients header) are in elasticity_text.hpp; files are the caller's (examples/foam_fit).
///
/// Samples are computed one after the other, each with all threads, so the report is bit-identical
/// for any thread count (timings aside).
///
/// Sample cache: a map from sample_cache_key(rho, tau, seed, config) to finished samples. Samples
/// found there are reused (marked `cached`), computed ones are added, so a long run can be resumed
/// and its outputs regenerated without recomputing; on_sample lets the caller persist the cache
/// after each computed sample.
///
/// Usage:
///   fabsynth::foam::elasticity_fit_config c{.pairs = {{0.15, 0.25}, {0.3, 0.25}}, .seeds_per_pair = 1};
///   fabsynth::foam::elasticity_fit_report r = fabsynth::foam::run_elasticity_fit(c);
///   double dev = r.max_deviation;   // of the polynomial r.P (empty below 15 fit points)
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/foam/elasticity.hpp"
#include "fabsynth/foam/elasticity_samples.hpp"
#include "fabsynth/foam/fit.hpp"

namespace fabsynth::foam {

/// Summary of a run.
struct elasticity_fit_report {
    std::vector<homogenized_sample> samples;  ///< in grid order, seeds innermost
    elasticity_polynomial P;          ///< degree 4; no coefficients when there are fewer than 15 fit points
    double max_deviation = 0;         ///< max_i |P(rho_i, tau_i) - E_i| / E_i over the fit points
    double max_deviation_other = 0;   ///< the same for a fit with the other objective (for comparison)
    power_law gibson_ashby;
    bool gibson_ashby_ok = false;     ///< false when fewer than two distinct w fall in the fit range
    double seconds = 0;               ///< wall time of run_elasticity_fit

    /// The homogenized samples without the bookkeeping.
    [[nodiscard]] std::vector<elasticity_sample> plain_samples() const {
        std::vector<elasticity_sample> s;
        s.reserve(samples.size());
        for (const auto& r : samples) s.push_back(r.s);
        return s;
    }
};

/// Finished samples by sample_cache_key.
using sample_cache = std::map<std::string, homogenized_sample>;

namespace detail {
/// "%.17g": doubles that read back bit-exactly.
[[nodiscard]] inline std::string exact_double(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}
}  // namespace detail

/// Key of one sample in a sample_cache: every parameter the sample depends on, doubles exact.
[[nodiscard]] inline std::string sample_cache_key(double rho, double tau, std::uint64_t seed, const elasticity_fit_config& c) {
    using detail::exact_double;
    return exact_double(rho) + "," + exact_double(tau) + "," + std::to_string(seed) + "," + std::to_string(c.elements) +
           "," + std::to_string(c.supersample) + "," + exact_double(c.seeds_per_cell) + "," + exact_double(c.tolerance);
}

/// Called after each sample with the sample, its 1-based index, the total and whether it was
/// computed (false: taken from the cache).
using sample_callback = std::function<void(const homogenized_sample&, std::size_t index, std::size_t total, bool computed)>;

/// Runs the grid (see the file comment). `cache` may be null. Throws invalid_input for a bad config.
inline elasticity_fit_report run_elasticity_fit(const elasticity_fit_config& c, sample_cache* cache = nullptr,
                                                const sample_callback& on_sample = {}) {
    c.validate();
    const auto t0 = std::chrono::steady_clock::now();
    elasticity_fit_report rep;
    const std::size_t total = c.pairs.size() * static_cast<std::size_t>(c.seeds_per_pair);
    for (const foam_parameters& p : c.pairs)
        for (int k = 0; k < c.seeds_per_pair; ++k) {
            const std::uint64_t seed = c.first_seed + static_cast<std::uint64_t>(k);
            const std::string key = cache ? sample_cache_key(p.density, p.radius, seed, c) : std::string();
            const homogenized_sample* hit = nullptr;
            if (cache)
                if (auto it = cache->find(key); it != cache->end()) hit = &it->second;
            const bool computed = hit == nullptr;
            const homogenized_sample r = computed ? homogenize_sample(p.density, p.radius, seed, c) : *hit;
            if (computed && cache) (*cache)[key] = r;
            rep.samples.push_back(r);
            if (on_sample) on_sample(r, rep.samples.size(), total, computed);
        }
    const std::vector<elasticity_sample> s = rep.plain_samples();
    constexpr int ncoef = 15;  // of the degree-4 polynomial
    if (static_cast<int>(fit_points(s).size()) >= ncoef) {
        std::tie(rep.P, rep.max_deviation) = fit_elasticity(s, c.fit);
        rep.max_deviation_other =
            fit_elasticity(s, c.fit == fit_error::relative ? fit_error::absolute : fit_error::relative).second;
    } else {
        rep.P.degree = 4;  // too few samples for the degree-4 fit: no polynomial (reported, no header)
    }
    try {
        rep.gibson_ashby = fit_power_law(s, c.omega_lo, c.omega_hi);
        rep.gibson_ashby_ok = true;
    } catch (const no_solution&) {
        rep.gibson_ashby_ok = false;
    }
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return rep;
}

}  // namespace fabsynth::foam
