// SPDX-License-Identifier: MIT
#pragma once
// Running CalculiX (Debian calculix-ccx), the independent FEM oracle, and reading its results.
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace fabsynth::test {

inline bool have_ccx() { return std::system("command -v ccx > /dev/null 2>&1") == 0; }

/// Displacements of CalculiX's .dat file (*NODE PRINT, U): node label -> (ux, uy, uz).
inline std::map<long, std::array<double, 3>> read_ccx_displacements(const std::filesystem::path& dat) {
    std::ifstream in(dat);
    std::map<long, std::array<double, 3>> u;
    std::string line;
    bool in_block = false;
    while (std::getline(in, line)) {
        if (line.find("displacements") != std::string::npos) { in_block = true; continue; }
        if (line.find_first_of("abcdefghijklmnopqrstuvwxyz") != std::string::npos) {  // numbers are 1.234E-04
            in_block = false;  // the next block's header (stresses, ...)
            continue;
        }
        if (!in_block) continue;
        std::istringstream s(line);
        long node;
        std::array<double, 3> v;
        if (s >> node >> v[0] >> v[1] >> v[2]) u[node] = v;
    }
    return u;
}

/// Writes `text` to DIR/STEM.inp and runs `ccx -i STEM` there; true when ccx exits 0 and wrote
/// STEM.dat. Its log goes to DIR/STEM.log.
inline bool run_ccx(const std::filesystem::path& dir, const std::string& stem, const std::string& text) {
    std::filesystem::create_directories(dir);
    std::filesystem::remove(dir / (stem + ".dat"));
    std::ofstream(dir / (stem + ".inp"), std::ios::binary) << text;
    const std::string cmd = "cd '" + dir.string() + "' && ccx -i " + stem + " > " + stem + ".log 2>&1";
    return std::system(cmd.c_str()) == 0 && std::filesystem::exists(dir / (stem + ".dat"));
}

}  // namespace fabsynth::test
