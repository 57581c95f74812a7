// SPDX-License-Identifier: MIT
#pragma once
// The convention every fabsynth tool follows (docs/tools.md): exit codes, the catch-all that ends
// every failure in a `fabsynth:` message, --version, --quiet, --json, defaults in --help, and
// progress that is a live percentage on a terminal and plain lines in a log.
//
//   int main(int argc, char** argv) {
//       CLI::App app{"..."};
//       fabsynth::tool::common c(app);                 // --version, --quiet, --json, defaults shown
//       app.add_option("--size", size, "...");
//       return fabsynth::tool::run(app, c, argc, argv, [&] {
//           auto progress = c.progress();                // a fabsynth::progress_callback
//           ...
//           c.summary({{"slices", n}});                   // printed on stdout with --json
//       });
//   }
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <new>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <fabsynth/core/error.hpp>
#include <fabsynth/version.hpp>

namespace fabsynth::tool {

/// Exit codes of every tool.
enum exit_code : int {
    exit_ok = 0,
    exit_internal = 1,      ///< an unexpected internal error (a bug; the message says what)
    exit_bad_input = 2,     ///< bad arguments or a bad input file
    exit_no_solution = 3,   ///< a valid request that cannot be met (fabsynth::no_solution)
    exit_solver = 4,        ///< solver or numerical failure, out of memory, cancelled
    exit_io = 5,            ///< reading or writing a file failed
};

/// What a failed run reports: its exit code and its `fabsynth:` message.
struct failure {
    int code;
    std::string message;
};

/// Classifies the exception in flight (call inside a catch block).
inline failure current_failure(std::string_view tool) {
    const std::string prefix = "fabsynth: " + std::string(tool) + ": ";
    try {
        throw;
    } catch (const invalid_input& e) {
        return {exit_bad_input, e.what()};
    } catch (const no_solution& e) {
        return {exit_no_solution, e.what()};
    } catch (const io_error& e) {
        return {exit_io, e.what()};
    } catch (const error& e) {  // solver_error, cancelled
        return {exit_solver, e.what()};
    } catch (const std::filesystem::filesystem_error& e) {
        return {exit_io, prefix + e.what()};
    } catch (const std::bad_alloc&) {
        return {exit_solver, prefix + "out of memory"};
    } catch (const std::exception& e) {
        return {exit_internal, prefix + "internal error: " + e.what()};
    } catch (...) {
        return {exit_internal, prefix + "internal error: unknown exception"};
    }
}

/// Refuses, before any work, an output path that is one of the input files (the same file by
/// std::filesystem::equivalent, so links and other spellings count) or that two outputs share:
/// invalid_input (exit 2) naming both. Empty paths are ignored. Outputs that do not exist yet
/// cannot be an existing input; two of them are compared by their normalised absolute paths.
inline void check_outputs(const std::vector<std::filesystem::path>& inputs, const std::vector<std::filesystem::path>& outputs) {
    namespace fs = std::filesystem;
    std::error_code ec;
    std::vector<fs::path> existing_inputs;
    for (const fs::path& in : inputs)
        if (!in.empty() && fs::exists(in, ec)) existing_inputs.push_back(in);
    std::map<fs::path, std::size_t> seen;  // normalised output -> its index (a slice stack has thousands)
    for (std::size_t k = 0; k < outputs.size(); ++k) {
        const fs::path& out = outputs[k];
        if (out.empty()) continue;
        if (fs::exists(out, ec))
            for (const fs::path& in : existing_inputs)
                if (fs::equivalent(out, in, ec))
                    throw invalid_input("output '" + out.string() + "' is the input '" + in.string() + "': refusing to overwrite an input");
        const auto [at, fresh] = seen.emplace(fs::weakly_canonical(fs::absolute(out), ec), k);
        if (!fresh) throw invalid_input("outputs '" + outputs[at->second].string() + "' and '" + out.string() + "' are the same file");
    }
}

/// `v` with a few significant digits ("1e+308", "0.25"), for messages.
inline std::string short_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

/// Returns v if it is finite and within [lo, hi], else invalid_input naming the option, e.g.
/// require_range(height, 1e-3, 1e5, "--height", "mm"): values that would overflow or vanish in a
/// computation are refused where they enter.
inline double require_range(double v, double lo, double hi, const std::string& option, const char* unit) {
    if (!(std::isfinite(v) && v >= lo && v <= hi)) {
        char msg[160];
        std::snprintf(msg, sizeof msg, " = %g must be a finite value in [%g, %g] %s", v, lo, hi, unit);
        throw invalid_input(option + msg);
    }
    return v;
}

/// Refuses, before the work starts, a run whose estimated peak memory exceeds the --max-memory
/// limit (GiB): invalid_input (exit 2) with the estimate, naming what needs it and the option that
/// raises the limit.
inline void require_memory(double bytes, double max_gib, const std::string& what) {
    const double gib = bytes / double(1ull << 30);
    if (!(gib <= max_gib)) {
        char msg[128];
        std::snprintf(msg, sizeof msg, " needs about %.3g GiB of memory, above --max-memory %.3g GiB (raise it if the machine has more)", gib,
                      max_gib);
        throw invalid_input(what + msg);
    }
}

/// Refuses a run whose estimated work `units` exceeds `limit` (the value of `option`): the message
/// gives the estimate, its duration at `rate_per_second` units/s on one core of the reference
/// machine (docs/tools.md), the option that raises the limit, and `hint` (another way) if given.
inline void require_work(double units, double limit, double rate_per_second, const char* unit, const char* option, const std::string& what,
                         const std::string& hint = "") {
    if (!(units <= limit)) {
        const double hours = units / rate_per_second / 3600.0;
        char msg[256];
        std::snprintf(msg, sizeof msg, " needs about %.3g %s (%.3g h of one core), above %s %.3g (raise it to run anyway", units, unit, hours, option,
                      limit);
        throw invalid_input(what + msg + (hint.empty() ? "" : "; " + hint) + ")");
    }
}

/// The --max-memory option every tool with large work has (GiB, default 16).
inline CLI::Option* add_memory_limit(CLI::App& app, double& max_gib) {
    return app.add_option("--max-memory", max_gib, "refuse runs estimated to need more memory than this (GiB)")->check(CLI::PositiveNumber);
}

/// Progress on stderr: a live percentage when stderr is a terminal, otherwise one plain line per
/// stage and per 10%; nothing with --quiet. Satisfies fabsynth::progress_callback.
class progress_printer {
public:
    explicit progress_printer(bool quiet) : quiet_(quiet), live_(!quiet && ::isatty(STDERR_FILENO) == 1) {}
    progress_printer(const progress_printer&) = delete;
    progress_printer& operator=(const progress_printer&) = delete;
    ~progress_printer() {
        if (live_ && shown_) std::fputs("\n", stderr);
    }

    void operator()(double fraction, std::string_view stage) {
        if (quiet_ || !std::isfinite(fraction)) return;
        const int percent = static_cast<int>(std::floor(std::clamp(fraction, 0.0, 1.0) * 100.0));
        const bool new_stage = stage != stage_;
        if (live_) {
            if (!new_stage && percent == percent_) return;
            std::fprintf(stderr, "\r%s%.*s %3d%%", new_stage && shown_ ? "\n" : "", static_cast<int>(stage.size()), stage.data(), percent);
            std::fflush(stderr);
        } else {
            if (!new_stage && percent / 10 == percent_ / 10) return;
            std::fprintf(stderr, "%.*s %d%%\n", static_cast<int>(stage.size()), stage.data(), percent);
        }
        shown_ = true;
        stage_ = stage;
        percent_ = percent;
    }

private:
    bool quiet_, live_;
    bool shown_ = false;
    std::string stage_;
    int percent_ = -1;
};

/// The options every tool has, and its machine-readable summary.
class common {
public:
    explicit common(CLI::App& app) : app_(app) {
        app.set_version_flag("--version", std::string("fabsynth ") + FABSYNTH_VERSION_STRING);
        app.option_defaults()->always_capture_default();
        app.fallthrough();  // inherited by subcommands: `tool sub ... --json` reaches these options
        app.add_flag("--quiet,-q", quiet_, "no progress on stderr");
        app.add_flag("--json", json_, "print a JSON summary of the run on stdout (human-readable lines go to stderr)");
    }
    [[nodiscard]] bool quiet() const noexcept { return quiet_; }
    [[nodiscard]] bool json() const noexcept { return json_; }

    /// A fresh progress printer honouring --quiet.
    [[nodiscard]] progress_printer progress() const { return progress_printer(quiet_); }

    /// Human-readable line: stdout normally, stderr with --json (stdout then holds JSON only).
    void say(const std::string& line) const { (json_ ? std::cerr : std::cout) << line << "\n"; }
    /// A warning on stderr ("fabsynth: warning: ..."), also with --quiet: the result is written but
    /// falls short of what was asked.
    void warn(const std::string& what) const { std::cerr << "fabsynth: warning: " << what << "\n"; }

    /// Adds fields to the JSON summary (printed by run() after success, with "tool" and "version").
    void summary(const nlohmann::ordered_json& fields) { summary_.update(fields); }

    /// Called by run(): with --json, prints the summary (or the failure) on stdout.
    void finish(const failure* f = nullptr) const {
        if (!json_) return;
        nlohmann::ordered_json out = {{"tool", app_.get_name()}, {"version", FABSYNTH_VERSION_STRING}};
        if (f) {
            out["status"] = "error";
            out["exit_code"] = f->code;
            out["message"] = f->message;
        } else {
            out["status"] = "ok";
            out.update(summary_);
        }
        std::cout << out.dump(2) << "\n";  // non-finite numbers print as null, so the output stays JSON
    }

private:
    CLI::App& app_;
    bool quiet_ = false, json_ = false;
    nlohmann::ordered_json summary_ = nlohmann::ordered_json::object();
};

/// glibc serves every allocation above its mmap threshold (at most 32 MiB) with a fresh mapping
/// and unmaps it on free, so each large temporary (a sparse matrix, a slice buffer) is page-faulted
/// in again (benchmarks/README.md, FEM at scale). A tool is one short process: it keeps freed
/// memory for reuse instead.
inline void keep_freed_memory() {
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, 1 << 30);
    mallopt(M_TRIM_THRESHOLD, -1);
#endif
}

/// The first option of `app` (or of a subcommand it parsed) given an empty value, such as
/// `--out-dir ""`; empty when there is none. No option of the tools takes an empty string.
inline std::string option_given_empty(const CLI::App& app) {
    for (const CLI::Option* opt : app.get_options())
        for (const std::string& r : opt->get_type_size_max() == 0 ? std::vector<std::string>{} : opt->results())  // flags take no value
            if (r.empty()) return opt->get_name();
    for (const CLI::App* sub : app.get_subcommands())
        if (std::string name = option_given_empty(*sub); !name.empty()) return name;
    return "";
}

/// Parses the arguments and runs body(): every failure ends in a `fabsynth:` message on stderr and
/// the exit code of the convention; --help and --version exit 0.
template <class Body>
int run(CLI::App& app, common& c, int argc, char** argv, Body&& body) {
    keep_freed_memory();
    if (app.get_name().empty() && argc > 0) app.name(std::filesystem::path(argv[0]).filename().string());
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "fabsynth: " << app.get_name() << ": " << e.what() << " (see --help)\n";
        return exit_bad_input;
    }
    if (const std::string empty = option_given_empty(app); !empty.empty()) {
        std::cerr << "fabsynth: " << app.get_name() << ": " << empty << " is given an empty value (see --help)\n";
        return exit_bad_input;
    }
    try {
        body();
        c.finish();
        return exit_ok;
    } catch (...) {
        const failure f = current_failure(app.get_name());
        std::cerr << f.message << "\n";
        c.finish(&f);
        return f.code;
    }
}

}  // namespace fabsynth::tool
