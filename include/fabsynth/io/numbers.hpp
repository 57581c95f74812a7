// SPDX-License-Identifier: MIT
#pragma once
/// @file numbers.hpp  Lists of numbers as text: decimal numbers separated by blanks, tabs, commas
/// and line breaks, any count per line; blank lines and lines starting with '#' are skipped. Every
/// token must be a complete finite decimal number ("4x", "1.2.3" and "0x10" are refused, a
/// leading '+' is accepted). Errors name the file and the line. Used for face id lists and
/// per-vertex scalar files. The scanner is io/points.hpp's (detail/number_lines.hpp).
///
/// Usage:
///   std::vector<double> ids = fabsynth::io::read_numbers("region.txt");   // "0 1 2\n# comment\n7\n"
///   std::vector<double> v = fabsynth::io::parse_numbers("1 2.5\n3", "inline");
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/io/detail/number_lines.hpp"
#include "fabsynth/io/detail/read_file.hpp"

namespace fabsynth::io {

/// Parses numbers from memory (`name` is used in error messages; see the file comment).
[[nodiscard]] inline std::vector<double> parse_numbers(std::string_view text, const std::string& name) {
    std::vector<double> out;
    detail::for_each_number_line(text, name, [&](std::size_t, const std::vector<double>& v) { out.insert(out.end(), v.begin(), v.end()); });
    return out;
}

/// Reads a number file (see the file comment). Throws io_error naming the file (and line).
[[nodiscard]] inline std::vector<double> read_numbers(const std::filesystem::path& path) {
    return parse_numbers(detail::read_file(path), path.string());
}

}  // namespace fabsynth::io
