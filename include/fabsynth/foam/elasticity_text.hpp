// SPDX-License-Identifier: MIT
#pragma once
/// @file elasticity_text.hpp  Text forms of an elasticity fit (elasticity_study.hpp), built and
/// parsed in memory; the caller reads and writes the files (examples/foam_fit):
///  - the data-points CSV: header "rho,tau,seed,omega,E,nu,isotropy_error", one line per sample,
///    doubles in "%.17g" so they read back bit-exactly (data/foam/elasticity_samples.csv);
///  - the sample cache: the cache key fields, then omega, E, nu, isotropy error, removed island
///    fraction, period and CG iterations per line;
///  - the generated coefficients header include/fabsynth/foam/elasticity_fit.hpp.
///
/// Usage:
///   std::string csv = fabsynth::foam::format_samples_csv(report.samples);
///   std::vector<fabsynth::foam::elasticity_sample> s = fabsynth::foam::parse_samples_csv(csv, "samples.csv");
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/foam/elasticity_study.hpp"
#include "fabsynth/foam/fit.hpp"

namespace fabsynth::foam {

namespace detail {
inline constexpr const char* samples_csv_head = "rho,tau,seed,omega,E,nu,isotropy_error";
inline constexpr const char* sample_cache_head =
    "rho,tau,seed,elements,supersample,seeds_per_cell,tolerance,omega,E,nu,isotropy_error,removed_fraction,period,iterations";
[[nodiscard]] inline std::vector<std::string> split_commas(const std::string& line) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string t; std::getline(ss, t, ',');) f.push_back(t);
    return f;
}
}  // namespace detail

/// CSV of the data points (see the file comment).
[[nodiscard]] inline std::string format_samples_csv(const std::vector<homogenized_sample>& v) {
    using detail::exact_double;
    std::ostringstream o;
    o << detail::samples_csv_head << "\n";
    for (const homogenized_sample& r : v)
        o << exact_double(r.s.density) << "," << exact_double(r.s.radius) << "," << r.s.seed << ","
          << exact_double(r.s.volume_fraction) << "," << exact_double(r.s.E) << "," << exact_double(r.s.nu) << ","
          << exact_double(r.s.anisotropy) << "\n";
    return o.str();
}

/// Parses a CSV written by format_samples_csv (empty lines skipped). `source` names the text in
/// errors. Throws io_error (source:line) for a wrong header, a wrong field count or a bad number.
[[nodiscard]] inline std::vector<elasticity_sample> parse_samples_csv(std::string_view text, std::string_view source) {
    std::istringstream in{std::string(text)};
    std::string line;
    if (!std::getline(in, line) || line != detail::samples_csv_head)
        throw io_error(source, 1, std::string("does not start with the elasticity samples CSV header ") + detail::samples_csv_head);
    std::vector<elasticity_sample> out;
    for (std::size_t ln = 2; std::getline(in, line); ++ln) {
        if (line.empty()) continue;
        const std::vector<std::string> f = detail::split_commas(line);
        if (f.size() != 7) throw io_error(source, ln, "expected 7 comma-separated fields: " + line);
        elasticity_sample s;
        try {
            s.density = std::stod(f[0]), s.radius = std::stod(f[1]), s.seed = std::stoull(f[2]);
            s.volume_fraction = std::stod(f[3]), s.E = std::stod(f[4]), s.nu = std::stod(f[5]), s.anisotropy = std::stod(f[6]);
        } catch (const std::exception&) {
            throw io_error(source, ln, "malformed number: " + line);
        }
        out.push_back(s);
    }
    return out;
}

/// Text of a sample cache (see the file comment), entries in key order.
[[nodiscard]] inline std::string format_sample_cache(const sample_cache& m) {
    using detail::exact_double;
    std::ostringstream o;
    o << detail::sample_cache_head << "\n";
    for (const auto& [k, r] : m)
        o << k << "," << exact_double(r.s.volume_fraction) << "," << exact_double(r.s.E) << "," << exact_double(r.s.nu) << ","
          << exact_double(r.s.anisotropy) << "," << exact_double(r.removed_fraction) << "," << r.period << "," << r.iterations
          << "\n";
    return o.str();
}

/// Parses a sample cache written by format_sample_cache; its entries are marked `cached`.
/// Throws io_error (source:line) for a wrong header, a wrong field count or a bad number.
[[nodiscard]] inline sample_cache parse_sample_cache(std::string_view text, std::string_view source) {
    sample_cache m;
    std::istringstream in{std::string(text)};
    std::string line;
    std::getline(in, line);
    if (line != detail::sample_cache_head) throw io_error(source, 1, "not an elasticity sample cache (unexpected header)");
    for (std::size_t ln = 2; std::getline(in, line); ++ln) {
        const std::vector<std::string> f = detail::split_commas(line);
        if (f.size() != 14) throw io_error(source, ln, "malformed cache line: " + line);
        homogenized_sample r;
        try {
            r.s.density = std::stod(f[0]), r.s.radius = std::stod(f[1]), r.s.seed = std::stoull(f[2]);
            r.s.volume_fraction = std::stod(f[7]), r.s.E = std::stod(f[8]), r.s.nu = std::stod(f[9]),
            r.s.anisotropy = std::stod(f[10]);
            r.removed_fraction = std::stod(f[11]), r.period = std::stoll(f[12]), r.iterations = std::stoi(f[13]);
        } catch (const std::exception&) {
            throw io_error(source, ln, "malformed number in cache line: " + line);
        }
        for (double v : {r.s.density, r.s.radius, r.s.volume_fraction, r.s.E, r.s.nu, r.s.anisotropy, r.removed_fraction})
            if (!std::isfinite(v)) throw io_error(source, ln, "non-finite value in cache line (a cache holds measured samples only): " + line);
        r.cached = true;
        m[f[0] + "," + f[1] + "," + f[2] + "," + f[3] + "," + f[4] + "," + f[5] + "," + f[6]] = r;
    }
    return m;
}

/// The text of the generated header include/fabsynth/foam/elasticity_fit.hpp (pure data, no
/// includes needed) for a finished run. Throws invalid_input when the run has no polynomial.
[[nodiscard]] inline std::string format_elasticity_fit_header(const elasticity_fit_config& c, const elasticity_fit_report& r) {
    if (r.P.coeffs.empty())
        throw invalid_input("elasticity fit: " + std::to_string(r.samples.size()) + " samples are fewer than the 15 coefficients "
                            "of the degree-4 polynomial; cannot write the coefficients header");
    constexpr auto exact = &detail::exact_double;
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
      << "/// radii t (E depends on rho (2 tau)^3 only; see foam/fit.hpp fit_points).\n"
      << "/// Objective: " << (c.fit == fit_error::relative ? "relative residuals sum ((P - E) / E)^2 (paper: absolute)" : "absolute residuals sum (P - E)^2 (as the paper)") << ".\n"
      << "/// Largest deviation of a fit point from the fit: " << exact(r.max_deviation * 100) << "% of its E (paper: 3.3%;\n"
      << "/// with the " << (c.fit == fit_error::relative ? "absolute" : "relative") << " objective: " << exact(r.max_deviation_other * 100) << "%).\n";
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

}  // namespace fabsynth::foam
