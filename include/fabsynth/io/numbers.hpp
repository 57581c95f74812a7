// SPDX-License-Identifier: MIT
#pragma once
/// @file numbers.hpp  Lists of numbers as text: whitespace-separated decimal numbers (blanks,
/// tabs, line breaks), any count per line; a line whose first character is '#' is a comment.
/// Every value must be finite. Used for face id lists and per-vertex scalar files.
///
/// A number is read as std::stod reads it (so "1e3", "0x10" and a leading '+' are accepted); a
/// token that does not start with a number is refused, and characters after a number's end start
/// the next token ("4x" is 4 and then a refused "x"). Errors name the file and the line.
///
/// Usage:
///   std::vector<double> ids = fabsynth::io::read_numbers("region.txt");   // "0 1 2\n# comment\n7\n"
///   std::vector<double> v = fabsynth::io::parse_numbers("1 2.5\n3", "inline");
#include <cctype>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/core/error.hpp"

namespace fabsynth::io {

/// Parses numbers from memory (`name` is used in error messages; see the file comment).
[[nodiscard]] inline std::vector<double> parse_numbers(std::string_view text, const std::string& name) {
    std::vector<double> out;
    std::size_t no = 0, pos = 0;
    while (pos < text.size()) {
        const std::size_t end = std::min(text.find('\n', pos), text.size());
        const std::string line(text.substr(pos, end - pos));
        pos = end + 1;
        ++no;
        if (!line.empty() && line[0] == '#') continue;
        std::size_t at = 0;
        while (at < line.size()) {
            while (at < line.size() && std::isspace(static_cast<unsigned char>(line[at]))) ++at;
            if (at >= line.size()) break;
            std::size_t used = 0;
            double v = 0;
            try {
                v = std::stod(line.substr(at), &used);
            } catch (const std::exception&) {
                throw io_error(name, no, "not a number: '" + line.substr(at, 20) + "'");
            }
            if (!std::isfinite(v)) throw io_error(name, no, "a value is not finite");
            out.push_back(v);
            at += used;
        }
    }
    return out;
}

/// Reads a number file (see the file comment). Throws io_error naming the file (and line).
[[nodiscard]] inline std::vector<double> read_numbers(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw io_error(path.string(), 0, "cannot open");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return parse_numbers(text, path.string());
}

}  // namespace fabsynth::io
