// SPDX-License-Identifier: MIT
#pragma once
/// @file text.hpp  Tokenising text with line numbers, strict number parsing and exact formatting.
///
/// fabsynth parses text formats itself instead of using tinyobjloader & co.: those accept
/// malformed numbers silently ("1.2.3" -> 1.2, "abc" -> 0) and report no line numbers, while every
/// fabsynth reader must reject such input naming the file and line. Numbers are parsed with
/// std::from_chars (locale-independent, exact) and must use the whole token.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

#include "fabsynth/core/error.hpp"

namespace fabsynth::io::detail {

[[nodiscard]] constexpr bool is_blank(char c) noexcept {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}
[[nodiscard]] constexpr bool is_space(char c) noexcept { return is_blank(c) || c == '\n'; }

/// A printable, bounded rendering of a token for error messages.
inline std::string quote(std::string_view t) {
    std::string s = "'";
    for (std::size_t i = 0; i < t.size() && i < 40; ++i) {
        const auto c = static_cast<unsigned char>(t[i]);
        if (c >= 32 && c < 127) s += static_cast<char>(c);
        else s += '?';
    }
    if (t.size() > 40) s += "...";
    return s + "'";
}

/// The whole token as a double, or nullopt if it is not a number in full (an optional leading
/// '+' is allowed). May return inf/nan for "inf"/"nan": callers decide whether that is legal.
inline std::optional<double> to_double(std::string_view t) noexcept {
    if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
    if (t.empty()) return std::nullopt;
    double v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc{} || end != t.data() + t.size()) return std::nullopt;
    return v;
}

/// The whole token as a signed 64-bit integer, or nullopt.
inline std::optional<std::int64_t> to_int(std::string_view t) noexcept {
    if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
    if (t.empty()) return std::nullopt;
    std::int64_t v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc{} || end != t.data() + t.size()) return std::nullopt;
    return v;
}

/// Appends the shortest decimal that reads back as exactly x (std::to_chars round-trip
/// guarantee, at most max_digits10 significant digits). x must be finite.
inline void append_number(std::string& out, double x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, static_cast<std::size_t>(r.ptr - buf));  // (ptr, len): the (first, last) overload trips a GCC 12 -Wrestrict false positive
}
/// Appends the shortest decimal that reads back (as a float) as exactly x. x must be finite.
inline void append_float(std::string& out, float x) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, static_cast<std::size_t>(r.ptr - buf));
}
inline void append_number(std::string& out, std::int64_t x) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, static_cast<std::size_t>(r.ptr - buf));  // (ptr, len): the (first, last) overload trips a GCC 12 -Wrestrict false positive
}

/// Whitespace-separated tokens of an in-memory text with 1-based line numbers.
/// `line()` is the line of the last token returned (or of the current position).
class token_cursor {
public:
    token_cursor(std::string_view data, std::string_view name, std::size_t offset = 0, std::size_t line = 1)
        : data_(data), name_(name), pos_(offset), line_(line), tok_line_(line) {}

    /// Next token anywhere (crossing lines); empty at end of input.
    std::string_view next() {
        while (pos_ < data_.size() && is_space(data_[pos_])) {
            if (data_[pos_] == '\n') ++line_;
            ++pos_;
        }
        return take();
    }
    /// Next token on the current line; empty if the line (or input) ends first.
    std::string_view next_on_line() {
        while (pos_ < data_.size() && is_blank(data_[pos_])) ++pos_;
        if (pos_ >= data_.size() || data_[pos_] == '\n') {
            tok_line_ = line_;
            return {};
        }
        return take();
    }
    /// Skips to just after the next newline (or to the end).
    void skip_line() {
        while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
        if (pos_ < data_.size()) ++pos_, ++line_;
    }
    /// Requires the rest of the current line to be blank and consumes its newline.
    void end_line(std::string_view context) {
        const std::string_view t = next_on_line();
        if (!t.empty()) fail(std::string("unexpected ") + quote(t) + " after " + std::string(context));
        skip_line();
    }
    /// Next token, which must exist; `what` names it in the error.
    std::string_view require(std::string_view what) {
        const std::string_view t = next();
        if (t.empty()) fail(std::string("unexpected end of file, expected ") + std::string(what));
        return t;
    }
    /// Next token on this line, which must exist.
    std::string_view require_on_line(std::string_view what) {
        const std::string_view t = next_on_line();
        if (t.empty()) fail(std::string("line ends early, expected ") + std::string(what));
        return t;
    }
    /// Parses `t` as a finite double or fails naming `what`.
    double finite(std::string_view t, std::string_view what) const {
        const auto v = to_double(t);
        if (!v) fail(std::string("cannot parse ") + std::string(what) + " from " + quote(t));
        if (!std::isfinite(*v)) fail(std::string(what) + " is not finite: " + quote(t));
        return *v;
    }
    /// Parses `t` as an integer in [lo, hi] or fails naming `what`.
    std::int64_t integer(std::string_view t, std::string_view what, std::int64_t lo = std::numeric_limits<std::int64_t>::min(),
                         std::int64_t hi = std::numeric_limits<std::int64_t>::max()) const {
        const auto v = to_int(t);
        if (!v) fail(std::string("cannot parse ") + std::string(what) + " (an integer) from " + quote(t));
        if (*v < lo || *v > hi)
            fail(std::string(what) + " " + std::to_string(*v) + " is out of range [" + std::to_string(lo) + ", " +
                 std::to_string(hi) + "]");
        return *v;
    }

    [[noreturn]] void fail(const std::string& what) const { throw io_error(name_, tok_line_, what); }
    [[noreturn]] void fail_at_byte(std::size_t offset, const std::string& what) const {
        throw io_error::at_byte(name_, offset, what);
    }

    [[nodiscard]] std::size_t line() const noexcept { return tok_line_; }
    [[nodiscard]] std::size_t offset() const noexcept { return pos_; }
    [[nodiscard]] std::size_t remaining() const noexcept { return data_.size() - pos_; }
    [[nodiscard]] std::string_view data() const noexcept { return data_; }
    [[nodiscard]] std::string_view name() const noexcept { return name_; }
    /// Moves forward to `offset` (e.g. past binary data), counting the newlines skipped.
    void advance_to(std::size_t offset) noexcept {
        for (; pos_ < offset && pos_ < data_.size(); ++pos_)
            if (data_[pos_] == '\n') ++line_;
        tok_line_ = line_;
    }

private:
    std::string_view take() {
        tok_line_ = line_;
        const std::size_t start = pos_;
        while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
        return data_.substr(start, pos_ - start);
    }

    std::string_view data_;
    std::string_view name_;
    std::size_t pos_;
    std::size_t line_;
    std::size_t tok_line_;
};

/// ASCII case-insensitive equality.
[[nodiscard]] inline bool iequals(std::string_view a, std::string_view b) noexcept {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        char x = a[i], y = b[i];
        if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
        if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
        if (x != y) return false;
    }
    return true;
}

}  // namespace fabsynth::io::detail
