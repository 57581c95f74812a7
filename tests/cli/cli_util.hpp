// Running the tools as child processes from a Catch2 test (stdout and stderr to files, stdin
// closed), shared by tests/cli/*.cpp.
#pragma once
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

const fs::path bin_dir = FABSYNTH_TOOLS_DIR;
const fs::path data_dir = FABSYNTH_DATA_DIR;
const fs::path work_dir = FABSYNTH_TEST_TMP;

struct result {
    int code = -1;
    std::string out, err;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// Runs TOOL ARGS... with stdin from /dev/null and FABSYNTH_NUM_THREADS=threads; `wrapper` (e.g.
// coreutils' "timeout -s KILL 1") is put before the tool.
result run(const std::string& tool, const std::vector<std::string>& args, int threads = 1, const std::string& wrapper = "") {
    fs::create_directories(work_dir);
    const fs::path out = work_dir / (tool + ".out"), err = work_dir / (tool + ".err");
    std::string cmd = "FABSYNTH_NUM_THREADS=";  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on literal + string&&
    cmd += std::to_string(threads);
    cmd += ' ';
    cmd += wrapper;
    cmd += ' ';
    cmd += quote((bin_dir / tool / tool).string());
    for (const auto& a : args) {
        cmd += ' ';
        cmd += quote(a);
    }
    cmd += " </dev/null >";
    cmd += quote(out.string());
    cmd += " 2>";
    cmd += quote(err.string());
    const int status = std::system(cmd.c_str());
    result r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

std::string write_file(const std::string& name, const std::string& text) {
    fs::create_directories(work_dir);
    const fs::path p = work_dir / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
}

// A row of the table: a command line and what the convention promises for it.
struct cli_case {
    std::string what;
    std::vector<std::string> args;
    int code;
    std::string message;  // substring of stderr (empty: only the "fabsynth:" prefix is checked)
};

void check_case(const std::string& tool, const cli_case& c) {
    INFO(tool << ": " << c.what);
    const result r = run(tool, c.args);
    INFO("stderr: " << r.err);
    CHECK(r.code == c.code);
    if (c.code != 0) {
        CHECK(r.err.find("fabsynth:") != std::string::npos);
        if (!c.message.empty()) CHECK(r.err.find(c.message) != std::string::npos);
    }
    CHECK(r.err.find('\r') == std::string::npos);  // stderr is a file here: plain lines only
}

}  // namespace
