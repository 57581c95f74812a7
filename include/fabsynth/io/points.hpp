// SPDX-License-Identifier: MIT
#pragma once
/// @file points.hpp  Point lists as text: one point per line, coordinates separated by commas
/// and/or blanks ("x,y,z" or "x y z", mm); blank lines and lines starting with '#' are skipped.
///
/// Every coordinate must be a complete decimal number ("1.2.3" and "4x" are refused, not read as
/// 1.2 or 4) and finite; a line must hold exactly three of them. Errors name the file and line.
///
/// Usage:
///   std::vector<fabsynth::vec3> pts = fabsynth::io::read_points_csv("in.csv");
///   fabsynth::io::write_points_csv("out.csv", pts);            // shortest round-trip decimals, atomic
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/io/atomic_file.hpp"
#include "fabsynth/io/detail/number_lines.hpp"
#include "fabsynth/io/detail/read_file.hpp"

namespace fabsynth::io {

/// Parses points from memory (`name` is used in error messages).
[[nodiscard]] inline std::vector<vec3> parse_points_csv(std::string_view text, const std::string& name) {
    std::vector<vec3> pts;
    detail::for_each_number_line(text, name, [&](std::size_t line_no, const std::vector<double>& c) {
        if (c.size() != 3) throw io_error(name, line_no, "expected three coordinates x,y,z, found " + std::to_string(c.size()));
        pts.emplace_back(c[0], c[1], c[2]);
    });
    return pts;
}

/// Reads a point file (see the file comment). Throws io_error naming the file (and line).
[[nodiscard]] inline std::vector<vec3> read_points_csv(const std::filesystem::path& path) {
    return parse_points_csv(detail::read_file(path), path.string());
}

/// "x,y,z" lines with the shortest decimals that read back to the same doubles.
[[nodiscard]] inline std::string format_points_csv(const std::vector<vec3>& pts) {
    std::string s;
    s.reserve(pts.size() * 40);
    char buf[32];
    for (const vec3& p : pts)
        for (int a = 0; a < 3; ++a) {
            const auto r = std::to_chars(buf, buf + sizeof buf, p[a]);
            s.append(buf, r.ptr);
            s += a < 2 ? ',' : '\n';
        }
    return s;
}

/// Writes format_points_csv(pts) atomically (temporary file + rename).
inline void write_points_csv(const std::filesystem::path& path, const std::vector<vec3>& pts) {
    atomic_write(path, format_points_csv(pts));
}

}  // namespace fabsynth::io
