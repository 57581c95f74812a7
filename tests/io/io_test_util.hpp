#pragma once
// Shared helpers for the io tests.
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/mesh.hpp"

namespace io_test {

inline std::filesystem::path tmp_dir() {
    const std::filesystem::path d = std::filesystem::path(FABSYNTH_TEST_TMP) / "io";
    std::filesystem::create_directories(d);
    return d;
}

inline std::filesystem::path data(const char* rel) { return std::filesystem::path(FABSYNTH_DATA_DIR) / rel; }

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void spit(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary);
    out << bytes;
}

/// A random mesh with awkward doubles (many significant digits, tiny and huge magnitudes,
/// negative zero) whose vertices are all referenced in order of first appearance and distinct,
/// so formats that weld or drop unreferenced vertices still read it back unchanged.
inline fabsynth::triangle_mesh awkward_mesh(std::uint64_t seed, std::size_t nv = 60) {
    fabsynth::counter_rng r(seed);
    fabsynth::triangle_mesh m;
    const double scales[] = {1.0, 1e-7, 1e6, 0.1, 3.0};
    for (std::size_t i = 0; i < nv; ++i) {
        const double s = scales[i % 5];
        m.vertices.emplace_back(r.uniform(-1, 1) * s, r.uniform(-1, 1) * s, r.uniform(-1, 1) * s);
    }
    m.vertices[1].y = -0.0;
    m.vertices[2] = {1.0 / 3.0, 2.0 / 3.0, 0.1};  // classic non-representable decimals
    for (std::size_t i = 0; i + 2 < nv; i += 3) m.faces.push_back({std::uint32_t(i), std::uint32_t(i + 1), std::uint32_t(i + 2)});
    for (std::size_t k = 0; k < nv; ++k)
        m.faces.push_back({std::uint32_t(r.uniform_int(nv)), std::uint32_t(r.uniform_int(nv)), std::uint32_t(r.uniform_int(nv))});
    return m;
}

/// Coordinates rounded to float, as binary STL/PLY store them.
/// (Not written as `v[a] = double(float(v[a]))` in a loop: GCC 12.2 at -O2 miscompiles that
/// pattern through glm's switch-based operator[] and rounds only z.)
inline double to_float(double x) {
    volatile float f = static_cast<float>(x);
    return static_cast<double>(f);
}
inline fabsynth::triangle_mesh float_rounded(fabsynth::triangle_mesh m) {
    for (auto& v : m.vertices) v = fabsynth::vec3(to_float(v.x), to_float(v.y), to_float(v.z));
    return m;
}

/// Independent oracle for STL reading: weld corners with a std::map keyed on (x,y,z) values,
/// numbering vertices in order of first appearance along the faces.
inline fabsynth::triangle_mesh welded_by_map(const fabsynth::triangle_mesh& m) {
    fabsynth::triangle_mesh out;
    std::map<std::array<double, 3>, std::uint32_t> index;
    for (const auto& f : m.faces) {
        std::array<std::uint32_t, 3> t{};
        for (int k = 0; k < 3; ++k) {
            const auto& p = m.vertices[f[k]];
            const std::array<double, 3> key{p.x + 0.0, p.y + 0.0, p.z + 0.0};
            auto it = index.find(key);
            if (it == index.end()) {
                it = index.emplace(key, std::uint32_t(out.vertices.size())).first;
                out.vertices.push_back(p);
            }
            t[k] = it->second;
        }
        out.faces.push_back(t);
    }
    return out;
}

/// Bitwise equality of the vertices (distinguishes -0 from +0 and catches any rounding).
inline bool bit_equal(const fabsynth::triangle_mesh& a, const fabsynth::triangle_mesh& b) {
    if (a.faces != b.faces || a.vertices.size() != b.vertices.size()) return false;
    for (std::size_t i = 0; i < a.vertices.size(); ++i)
        for (int k = 0; k < 3; ++k)
            if (std::signbit(a.vertices[i][k]) != std::signbit(b.vertices[i][k]) || a.vertices[i][k] != b.vertices[i][k])
                return false;
    return true;
}

}  // namespace io_test
