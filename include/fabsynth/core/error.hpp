// SPDX-License-Identifier: MIT
#pragma once
/// @file error.hpp  The fabsynth exception hierarchy.
///
/// Bad user input throws a subclass of fabsynth::error whose what() starts with "fabsynth: " and
/// names the input and what was wrong. Catch fabsynth::error to handle every library failure.
#include <stdexcept>
#include <string>
#include <string_view>

namespace fabsynth {

/// Base of every exception the library throws.
class error : public std::runtime_error {
public:
    explicit error(const std::string& what) : std::runtime_error(prefixed(what)) {}

private:
    static std::string prefixed(const std::string& what) {
        constexpr std::string_view prefix = "fabsynth: ";
        return what.starts_with(prefix) ? what : std::string(prefix) + what;
    }
};

/// An argument or input value is out of its documented domain (NaN, negative size, empty set...).
class invalid_input : public error {
public:
    using error::error;
};

/// A file could not be opened, read or written, or its content is malformed.
/// The message names the file and, where known, the line or byte offset.
class io_error : public error {
public:
    using error::error;
    /// "fabsynth: FILE:LINE: WHAT" (line 0 = no line number).
    io_error(std::string_view file, std::size_t line, std::string_view what) : error(located(file, line, what)) {}
    /// "fabsynth: FILE: byte OFFSET: WHAT" for binary formats.
    static io_error at_byte(std::string_view file, std::size_t offset, std::string_view what) {
        return io_error(std::string(file) + ": byte " + std::to_string(offset) + ": " + std::string(what));
    }

private:
    static std::string located(std::string_view file, std::size_t line, std::string_view what) {
        std::string s(file);
        if (line) s.append(":").append(std::to_string(line));
        return s.append(": ").append(what);
    }
};

/// The request is well formed but cannot be met (e.g. a topology target no pattern satisfies).
class no_solution : public error {
public:
    using error::error;
};

/// A numerical solve failed: singular or indefinite system, non-convergence.
class solver_error : public error {
public:
    using error::error;
};

/// The caller's progress callback asked to stop.
class cancelled : public error {
public:
    using error::error;
};

}  // namespace fabsynth

/// Internal invariant check (not for user input): active unless NDEBUG.
#ifndef NDEBUG
#define FABSYNTH_ASSERT(cond)                                                                        \
    do {                                                                                             \
        if (!(cond))                                                                                 \
            throw ::fabsynth::error(std::string("internal assertion failed: ") + #cond + " at " +    \
                                    __FILE__ + ":" + std::to_string(__LINE__));                      \
    } while (false)
#else
#define FABSYNTH_ASSERT(cond) ((void)0)
#endif
