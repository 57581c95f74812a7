// SPDX-License-Identifier: MIT
#pragma once
/// @file number_lines.hpp  The one scanner of the text formats made of numbers (io/numbers.hpp's
/// lists, io/points.hpp's point files): lines split at '\n' (a trailing '\r' dropped), lines blank
/// or starting with '#' (after blanks) skipped, tokens separated by blanks, tabs and commas, every
/// token a complete finite decimal number read by std::from_chars (a leading '+' allowed; "4x",
/// "1.2.3" and "0x10" refused). Errors name the file and the line.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"

namespace fabsynth::io::detail {

/// Calls on_line(line number (1-based), the line's numbers) for every line holding a number.
/// `name` names the input in errors (io_error).
template <class OnLine>
void for_each_number_line(std::string_view text, const std::string& name, OnLine&& on_line) {
    std::vector<double> values;
    std::size_t line_no = 0, pos = 0;
    const auto separator = [](char c) { return c == ' ' || c == '\t' || c == ','; };
    while (pos < text.size()) {
        const std::size_t end = std::min(text.find('\n', pos), text.size());
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        const std::size_t first = line.find_first_not_of(" \t");
        if (first == std::string_view::npos || line[first] == '#') continue;
        values.clear();
        for (std::size_t i = first; i < line.size();) {
            while (i < line.size() && separator(line[i])) ++i;
            if (i == line.size()) break;
            std::size_t j = i;
            while (j < line.size() && !separator(line[j])) ++j;
            const std::string_view tok = line.substr(i, j - i);
            double v = 0;
            const char* b = tok.data() + (tok.front() == '+' ? 1 : 0);
            const auto [ptr, ec] = std::from_chars(b, tok.data() + tok.size(), v);
            if (ec != std::errc() || ptr != tok.data() + tok.size()) throw io_error(name, line_no, "'" + std::string(tok) + "' is not a number");
            if (!std::isfinite(v)) throw io_error(name, line_no, "'" + std::string(tok) + "' is not finite");
            values.push_back(v);
            i = j;
        }
        if (!values.empty()) on_line(line_no, std::as_const(values));
    }
}

}  // namespace fabsynth::io::detail
