// foam_fit: elasticity control of procedural Voronoi foams (procedural-voronoi-foams.md §4.1).
//
//   foam_fit [--tau T1,T2,...] [--fraction 0.002 0.2 --rho-count 4 | --pairs RHO:TAU,...]
//            [--seeds 3] [--first-seed 1] [--elements 60] [--supersample 4] [--seeds-per-cell 4]
//            [--tol 1e-6] [--threads 0] [--csv data/foam/elasticity_samples.csv]
//            [--header include/fabsynth/foam/elasticity_fit.hpp] [--plot data/foam/elasticity_fit.png]
//            [--cache FILE]
//
// Grid: M = (number of taus) x --rho-count fractions f_i uniformly spaced in [LO, HI]; fraction f_i
// goes to tau number (i mod number of taus) as rho = f_i / (2 tau)^3 (f = 1 is the full-block bound
// of paper §4.2). So each tau gets --rho-count uniformly spaced densities and the f values of the
// different taus interleave. Why interleave: a sample (rho, tau) is an exact scaled copy of the
// sample (rho s^3, tau / s) (the sample side, element size, coarse cell and seeds all scale with
// tau), so E depends on f = rho (2 tau)^3 only; equal f at two taus would repeat a computation.
// Or an explicit --pairs list.
// Each (rho, tau) is realised with --seeds global seeds as a periodic foam of --elements^3
// hexahedral elements of side tau, homogenized (Es = 1, nu = 0.3) and fitted with an isotropic
// tensor; then E = P(rho, tau) (degree 4) and E/Es = C w^n on 0.04 < w < 0.5 are fitted.
// Writes the CSV of data points, the coefficients header and the PNG plot (only those asked for);
// prints one line per sample (stderr, not with --quiet) and a summary (stdout; --json: JSON).
// Outputs are written only at the end, after every check passed (the cache after each sample).
// Conventions (exit codes, --quiet, --json, --version): docs/tools.md.

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/foam/elasticity_study.hpp>
#include <fabsynth/foam/elasticity_text.hpp>
#include <fabsynth/foam/fit_plot.hpp>
#include <fabsynth/io/atomic_file.hpp>
#include <fabsynth/io/image.hpp>

#include "output_set.hpp"
#include "tool.hpp"

namespace {
// Wall seconds of one sample on the reference machine (2 threads, benchmarks/README.md "Tool
// limits"): E^3 (fem + coverage s^3), fitted to 60^3 s = 4 (15.1 s) and 32^3 s = 8 (3.1 s); and
// the peak bytes per element of its multigrid solve.
constexpr double fem_seconds_per_element = 6.6e-5, coverage_seconds_per_sample = 5.7e-8, bytes_per_element = 1000;

// The sample cache file, if it exists (an absent cache is an empty one).
fabsynth::foam::sample_cache read_cache(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    std::stringstream ss;
    ss << in.rdbuf();
    return fabsynth::foam::parse_sample_cache(ss.str(), path);
}

std::vector<double> parse_list(const std::string& s, const char* what) {
    std::vector<double> v;
    std::stringstream ss(s);
    for (std::string t; std::getline(ss, t, ',');) {
        try {
            std::size_t used = 0;
            v.push_back(std::stod(t, &used));
            if (used != t.size()) throw std::invalid_argument(t);
        } catch (const std::exception&) {
            throw fabsynth::invalid_input(std::string("foam_fit: ") + what + ": '" + t + "' is not a number");
        }
    }
    return v;
}
}  // namespace

int main(int argc, char** argv) {
    using namespace fabsynth;
    CLI::App app{"Homogenize periodic procedural Voronoi foams over a (rho, tau) grid and fit E = P(rho, tau)", "foam_fit"};
    tool::common common(app);
    foam::elasticity_fit_config c;
    std::string csv_path, header_path, plot_path, cache_path;
    std::string taus = "0.2,0.225,0.25,0.275,0.3", pairs;
    std::vector<double> fraction{0.002, 0.2};
    int rho_count = 4;
    unsigned threads = 0;
    app.add_option("--tau", taus, "beam radii tau (mm), comma separated")->capture_default_str();
    app.add_option("--fraction", fraction, "density range as fractions LO HI of the full-block bound 1/(2 tau)^3")
        ->expected(2)->capture_default_str();
    app.add_option("--rho-count", rho_count, "densities per tau, uniformly spaced")->capture_default_str();
    app.add_option("--pairs", pairs, "explicit grid RHO:TAU,RHO:TAU,... (replaces --tau/--fraction)");
    app.add_option("--seeds", c.seeds_per_pair, "global random seeds per (rho, tau)")->capture_default_str();
    app.add_option("--first-seed", c.first_seed, "first global seed")->capture_default_str();
    app.add_option("--elements", c.elements, "hexahedral elements per side of the periodic sample")->capture_default_str();
    app.add_option("--supersample", c.supersample, "s: s^3 coverage samples per element")->capture_default_str();
    app.add_option("--seeds-per-cell", c.seeds_per_cell, "target seeds per coarse cell (sets the seed period)")->capture_default_str();
    app.add_option("--tol", c.tolerance, "relative residual of each FEM solve")->capture_default_str();
    std::string objective = "relative";
    app.add_option("--objective", objective, "polynomial fit residual: relative (default) or absolute (the paper's)")
        ->check(CLI::IsMember({"relative", "absolute"}))
        ->capture_default_str();
    app.add_option("--threads", threads, "worker threads (0 = all cores); results do not depend on it")->capture_default_str();
    app.add_option("--csv", csv_path, "data points CSV to write");
    app.add_option("--header", header_path, "generated coefficients header to write");
    app.add_option("--plot", plot_path, "PNG plot to write");
    app.add_option("--cache", cache_path, "sample cache (reused and extended; lets a run resume)");
    double max_memory_gib = 16, max_hours = 24;
    tool::add_memory_limit(app, max_memory_gib);
    app.add_option("--max-hours", max_hours, "refuse runs estimated to take longer than this (hours on 2 cores; cached samples count as free)")
        ->check(CLI::PositiveNumber);
    return tool::run(app, common, argc, argv, [&] {
        tool::check_outputs({cache_path}, {csv_path, header_path, plot_path});
        foam::sample_cache cache;
        if (!cache_path.empty()) cache = read_cache(cache_path);
        // Hours on 2 cores for `pairs` density/radius pairs, the cached samples free: checked before
        // the grid of pairs is built, so a huge --rho-count is refused at once.
        const auto require_hours = [&](double pairs) {
            const double per_element = static_cast<double>(c.elements) * c.elements * c.elements;
            const double s3 = static_cast<double>(c.supersample) * c.supersample * c.supersample;
            const double samples = pairs * c.seeds_per_pair - static_cast<double>(cache.size());
            const double hours = std::max(0.0, samples) * per_element * (fem_seconds_per_element + coverage_seconds_per_sample * s3) / 3600.0;
            char what[160];
            std::snprintf(what, sizeof what, "%.4g samples of %d^3 elements, supersample %d", pairs * c.seeds_per_pair, c.elements, c.supersample);
            tool::require_work(hours, max_hours, 1.0 / 3600.0, "hours on 2 cores", "--max-hours", what);
        };
        c.fit = objective == "absolute" ? foam::fit_error::absolute : foam::fit_error::relative;
        set_num_threads(threads);
        if (!pairs.empty()) {
            std::stringstream ss(pairs);
            for (std::string t; std::getline(ss, t, ',');) {
                const auto colon = t.find(':');
                if (colon == std::string::npos) throw invalid_input("foam_fit: --pairs entry '" + t + "' is not RHO:TAU");
                const auto r = parse_list(t.substr(0, colon), "--pairs"), u = parse_list(t.substr(colon + 1), "--pairs");
                if (r.size() != 1 || u.size() != 1) throw invalid_input("foam_fit: --pairs entry '" + t + "' is not RHO:TAU");
                c.pairs.push_back({r[0], u[0]});
            }
        } else {
            if (rho_count < 1) throw invalid_input("foam_fit: --rho-count must be >= 1");
            if (!(fraction[0] > 0 && fraction[0] <= fraction[1] && fraction[1] <= 1))
                throw invalid_input("foam_fit: --fraction needs 0 < LO <= HI <= 1");
            const std::vector<double> tau = parse_list(taus, "--tau");
            if (tau.empty()) throw invalid_input("foam_fit: --tau is empty");
            const std::size_t m = tau.size(), total = m * static_cast<std::size_t>(rho_count);
            require_hours(static_cast<double>(total));
            for (std::size_t i = 0; i < total; ++i) {  // in increasing f, so a cut-short run still spans every tau
                const double f = total == 1 ? fraction[0] : fraction[0] + (fraction[1] - fraction[0]) * double(i) / double(total - 1);
                c.pairs.push_back({f * foam::full_block_density(tau[i % m]), tau[i % m]});
            }
        }
        c.validate();
        // The header needs the degree-4 polynomial: refuse before any work if it cannot be fitted.
        constexpr std::size_t polynomial_terms = 15;
        if (!header_path.empty() && c.pairs.size() * static_cast<std::size_t>(c.seeds_per_pair) < polynomial_terms)
            throw invalid_input("foam_fit: --header needs at least " + std::to_string(polynomial_terms) + " samples for the degree-4 fit, the grid has " +
                                std::to_string(c.pairs.size() * static_cast<std::size_t>(c.seeds_per_pair)));
        const double per_element = static_cast<double>(c.elements) * c.elements * c.elements;
        tool::require_memory(per_element * bytes_per_element, max_memory_gib, "a sample of --elements " + std::to_string(c.elements));
        require_hours(static_cast<double>(c.pairs.size()));
        tool::output_set outputs;  // the three outputs appear together at the end
        const std::filesystem::path csv_file = csv_path.empty() ? std::filesystem::path() : outputs.add(csv_path),
                                    header_file = header_path.empty() ? std::filesystem::path() : outputs.add(header_path),
                                    plot_file = plot_path.empty() ? std::filesystem::path() : outputs.add(plot_path);
        auto progress = [&](const foam::homogenized_sample& r, std::size_t index, std::size_t total, bool computed) {
            if (computed && !cache_path.empty()) io::atomic_write(cache_path, foam::format_sample_cache(cache));
            char buf[320];
            std::snprintf(buf, sizeof buf,
                          "[%zu/%zu] rho %.4g tau %.4g seed %llu: w %.4f E %.5g nu %.4f iso %.4f islands %.4f period %lld "
                          "iters %d %s %.1f s",
                          index, total, r.s.density, r.s.radius, static_cast<unsigned long long>(r.s.seed), r.s.volume_fraction,
                          r.s.E, r.s.nu, r.s.anisotropy, r.removed_fraction, static_cast<long long>(r.period), r.iterations,
                          r.cached ? "(cached)" : "", r.seconds);
            if (!common.quiet()) std::cerr << buf << std::endl;
        };
        const foam::elasticity_fit_report r = foam::run_elasticity_fit(c, &cache, progress);
        if (!csv_path.empty()) io::atomic_write(csv_file, foam::format_samples_csv(r.samples));
        if (!header_path.empty()) io::atomic_write(header_file, foam::format_elasticity_fit_header(c, r));
        if (!plot_path.empty()) io::write_png(plot_file, foam::draw_elasticity_fit(c, r));
        outputs.commit();
        std::ostringstream out;
        char buf[512];
        std::snprintf(buf, sizeof buf, "samples %zu (%zu pairs x %d seeds), %d^3 elements, supersample %d\n", r.samples.size(), c.pairs.size(),
                      c.seeds_per_pair, c.elements, c.supersample);
        out << buf;
        if (!r.P.coeffs.empty()) {
            std::snprintf(buf, sizeof buf,
                          "degree-4 polynomial E = P(rho, tau), %s residuals: max deviation %.3f%% of E (paper: 3.3%%; the other "
                          "objective: %.3f%%)\ncoefficients:",
                          objective.c_str(), 100 * r.max_deviation, 100 * r.max_deviation_other);
            out << buf;
            for (double x : r.P.coeffs) std::snprintf(buf, sizeof buf, " %.9g", x), out << buf;
            out << "\n";
        } else {
            out << "too few samples for the degree-4 polynomial (need 15)\n";
        }
        if (r.gibson_ashby_ok)
            std::snprintf(buf, sizeof buf, "Gibson-Ashby E/Es = C w^n on %.3g < w < %.3g (%zu samples): C = %.4f, n = %.4f (paper: 0.85, 1.95)\n",
                          c.omega_lo, c.omega_hi, r.gibson_ashby.samples_used, r.gibson_ashby.C, r.gibson_ashby.n);
        else
            std::snprintf(buf, sizeof buf, "Gibson-Ashby: fewer than two samples with %.3g < w < %.3g\n", c.omega_lo, c.omega_hi);
        out << buf;
        std::snprintf(buf, sizeof buf, "time %.1f s", r.seconds);
        out << buf;
        common.say(out.str());
        common.summary({{"samples", r.samples.size()},
                        {"pairs", c.pairs.size()},
                        {"polynomial", r.P.coeffs},
                        {"max_deviation", r.P.coeffs.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.max_deviation)},
                        {"gibson_ashby",
                         r.gibson_ashby_ok ? nlohmann::ordered_json{{"C", r.gibson_ashby.C}, {"n", r.gibson_ashby.n}} : nlohmann::ordered_json(nullptr)},
                        {"seconds", r.seconds}});
    });
}
