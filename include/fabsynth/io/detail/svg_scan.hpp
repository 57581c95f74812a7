// SPDX-License-Identifier: MIT
#pragma once
/// @file svg_scan.hpp  Internal: SVG number grammar, transform lists and 2D affine maps.
/// Not part of the public API.
///
/// Numbers follow the SVG 1.1 grammar (sign? (digits? '.' digits | digits '.'?) exponent?): so
/// "1.5.5" is 1.5 then .5, "-.5" and "1e-3" are numbers, "1e" is 1 followed by a bad 'e'.
/// "NaN", "inf" and hexadecimal are not numbers. Values beyond the double range are errors;
/// values below it become 0.
#include <charconv>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>
#include <string_view>
#include <system_error>

#include "fabsynth/core/types.hpp"
#include "fabsynth/io/detail/svg_xml.hpp"

namespace fabsynth::io::detail::svg {

/// Cursor over an attribute value located at byte `base` of the source (for error positions).
struct scanner {
    const source* src;
    std::string_view s;
    std::size_t base = 0;
    std::size_t pos = 0;
    std::string_view what;  ///< attribute name, for messages

    [[noreturn]] void fail(std::string_view msg) const {
        src->fail(base + pos, std::string(what) + ": " + std::string(msg));
    }
    [[nodiscard]] bool at_end() const noexcept { return pos >= s.size(); }
    [[nodiscard]] char peek() const noexcept { return pos < s.size() ? s[pos] : '\0'; }
    void skip_wsp() noexcept {
        while (pos < s.size() && (is_xml_space(s[pos]) || s[pos] == '\f')) ++pos;
    }
    /// Skips wsp* ','? wsp*; returns true if a comma was skipped.
    bool skip_comma_wsp() noexcept {
        skip_wsp();
        if (peek() != ',') return false;
        ++pos;
        skip_wsp();
        return true;
    }
    [[nodiscard]] bool at_number() const noexcept {
        const char c = peek();
        return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+';
    }

    /// Parses one number at the cursor (no leading whitespace skipped).
    double number() {
        const std::size_t start = pos;
        std::size_t p = pos;
        const auto digit = [&](std::size_t i) { return i < s.size() && s[i] >= '0' && s[i] <= '9'; };
        if (p < s.size() && (s[p] == '+' || s[p] == '-')) ++p;
        const std::size_t mant = p;
        std::size_t ndig = 0;
        while (digit(p)) ++p, ++ndig;
        if (p < s.size() && s[p] == '.' && (ndig > 0 || digit(p + 1))) {
            ++p;
            while (digit(p)) ++p, ++ndig;
        }
        if (ndig == 0) fail("expected a number");
        const std::size_t mant_end = p;
        long exp10 = 0;
        if (p < s.size() && (s[p] == 'e' || s[p] == 'E')) {
            std::size_t q = p + 1;
            bool neg = false;
            if (q < s.size() && (s[q] == '+' || s[q] == '-')) neg = s[q] == '-', ++q;
            if (digit(q)) {
                while (digit(q)) {
                    if (exp10 < 100000) exp10 = exp10 * 10 + (s[q] - '0');
                    ++q;
                }
                if (neg) exp10 = -exp10;
                p = q;
            }
        }
        const std::size_t from = s[start] == '+' ? start + 1 : start;  // from_chars rejects '+'
        double v = 0.0;
        const auto [end, ec] = std::from_chars(s.data() + from, s.data() + p, v, std::chars_format::general);
        if (ec == std::errc::result_out_of_range) {
            // Decimal magnitude: exponent plus the position of the first non-zero digit.
            long mag = exp10;
            std::size_t int_digits = 0, lead_zero_frac = 0;
            bool seen_point = false, seen_nonzero = false;
            for (std::size_t i = mant; i < mant_end; ++i) {
                const char c = s[i];
                if (c == '.') { seen_point = true; continue; }
                if (c != '0') seen_nonzero = true;
                if (!seen_point && seen_nonzero) ++int_digits;
                if (seen_point && !seen_nonzero) ++lead_zero_frac;
            }
            mag += int_digits > 0 ? static_cast<long>(int_digits) : -static_cast<long>(lead_zero_frac);
            pos = start;
            if (mag > 0) fail("number " + std::string(s.substr(start, p - start)) + " is out of the double range");
            v = s[start] == '-' ? -0.0 : 0.0;  // underflow: rounds to zero
        } else if (ec != std::errc() || end != s.data() + p) {
            pos = start;
            fail("unparsable number");
        }
        pos = p;
        return v;
    }

    /// Skips comma-wsp, then parses a number; fails with `msg` if none follows.
    double next_number(std::string_view msg) {
        skip_comma_wsp();
        if (!at_number()) fail(msg);
        return number();
    }

    /// Arc flag: a single '0' or '1' (may be followed directly by the next number).
    bool flag() {
        skip_comma_wsp();
        const char c = peek();
        if (c != '0' && c != '1') fail("arc flag must be 0 or 1");
        ++pos;
        return c == '1';
    }
};

/// 2D affine map p -> (a x + c y + e, b x + d y + f), the SVG matrix(a b c d e f).
struct affine2 {
    double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;

    [[nodiscard]] bool is_identity() const noexcept { return a == 1 && b == 0 && c == 0 && d == 1 && e == 0 && f == 0; }
    [[nodiscard]] vec2 apply(vec2 p) const noexcept {
        if (is_identity()) return p;  // keeps coordinates bit-exact (e.g. -0 stays -0)
        return {a * p.x + c * p.y + e, b * p.x + d * p.y + f};
    }
    /// Linear part only (for directions).
    [[nodiscard]] vec2 apply_linear(vec2 v) const noexcept { return {a * v.x + c * v.y, b * v.x + d * v.y}; }
    /// Composition: (*this * o)(p) = this(o(p)).
    [[nodiscard]] affine2 operator*(const affine2& o) const noexcept {
        return {a * o.a + c * o.b, b * o.a + d * o.b, a * o.c + c * o.d, b * o.c + d * o.d, a * o.e + c * o.f + e,
                b * o.e + d * o.f + f};
    }
    [[nodiscard]] double det() const noexcept { return a * d - b * c; }
    [[nodiscard]] bool finite() const noexcept {
        return std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && std::isfinite(d) && std::isfinite(e) &&
               std::isfinite(f);
    }
    friend bool operator==(const affine2&, const affine2&) = default;
};

/// Largest singular value of the 2x2 matrix [[m00 m01] [m10 m11]].
[[nodiscard]] inline double max_singular_value(double m00, double m01, double m10, double m11) noexcept {
    const double fro2 = m00 * m00 + m01 * m01 + m10 * m10 + m11 * m11;
    const double det = m00 * m11 - m01 * m10;
    const double disc = std::sqrt(std::max(0.0, fro2 * fro2 - 4.0 * det * det));
    return std::sqrt(0.5 * (fro2 + disc));
}

/// Parses an SVG transform list ("translate(10) rotate(30 5 5), scale(2)") into one matrix
/// (the leftmost transform is applied last, as in SVG).
[[nodiscard]] inline affine2 parse_transform(scanner& sc) {
    affine2 m;
    constexpr double deg = std::numbers::pi / 180.0;
    sc.skip_wsp();
    while (!sc.at_end()) {
        const std::size_t name_begin = sc.pos;
        while (!sc.at_end() && ((sc.peek() >= 'a' && sc.peek() <= 'z') || (sc.peek() >= 'A' && sc.peek() <= 'Z'))) ++sc.pos;
        const std::string_view name = sc.s.substr(name_begin, sc.pos - name_begin);
        if (name.empty()) sc.fail("expected a transform name");
        sc.skip_wsp();
        if (sc.peek() != '(') sc.fail("expected '(' after " + std::string(name));
        ++sc.pos;
        double v[6];
        int count = 0;
        sc.skip_wsp();
        while (sc.peek() != ')') {
            if (count == 6) sc.fail("too many arguments to " + std::string(name));
            if (count > 0) sc.skip_comma_wsp();
            if (!sc.at_number()) sc.fail(sc.at_end() ? "unterminated " + std::string(name) + "(" : "expected a number");
            v[count++] = sc.number();
            sc.skip_wsp();
        }
        const std::size_t close = sc.pos;
        ++sc.pos;
        affine2 t;
        auto bad_count = [&](const char* expected) {
            sc.pos = close;
            sc.fail(std::string(name) + " takes " + expected + " arguments, got " + std::to_string(count));
        };
        if (name == "matrix") {
            if (count != 6) bad_count("6");
            t = {v[0], v[1], v[2], v[3], v[4], v[5]};
        } else if (name == "translate") {
            if (count != 1 && count != 2) bad_count("1 or 2");
            t.e = v[0];
            t.f = count == 2 ? v[1] : 0.0;
        } else if (name == "scale") {
            if (count != 1 && count != 2) bad_count("1 or 2");
            t.a = v[0];
            t.d = count == 2 ? v[1] : v[0];
        } else if (name == "rotate") {
            if (count != 1 && count != 3) bad_count("1 or 3");
            const double cs = std::cos(v[0] * deg), sn = std::sin(v[0] * deg);
            t = {cs, sn, -sn, cs, 0, 0};
            if (count == 3) t = affine2{1, 0, 0, 1, v[1], v[2]} * t * affine2{1, 0, 0, 1, -v[1], -v[2]};
        } else if (name == "skewX") {
            if (count != 1) bad_count("1");
            t.c = std::tan(v[0] * deg);
        } else if (name == "skewY") {
            if (count != 1) bad_count("1");
            t.b = std::tan(v[0] * deg);
        } else {
            sc.pos = name_begin;
            sc.fail("unknown transform '" + std::string(name) + "'");
        }
        m = m * t;
        if (!m.finite()) {
            sc.pos = name_begin;
            sc.fail("transform overflows the double range");
        }
        sc.skip_comma_wsp();
    }
    return m;
}

}  // namespace fabsynth::io::detail::svg
