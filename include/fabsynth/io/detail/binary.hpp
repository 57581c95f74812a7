// SPDX-License-Identifier: MIT
#pragma once
/// @file binary.hpp  Endian-explicit reading and writing of fixed-size numbers.
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>

namespace fabsynth::io::detail {

enum class byte_order { little, big };

/// Reads a T stored in `order` at p (no bounds check: callers check sizes first).
template <class T>
[[nodiscard]] T load(const char* p, byte_order order) noexcept {
    static_assert(std::is_trivially_copyable_v<T>);
    unsigned char b[sizeof(T)];
    std::memcpy(b, p, sizeof(T));
    const bool native_little = std::endian::native == std::endian::little;
    if ((order == byte_order::little) != native_little)
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
}

/// Appends x to out in `order`.
template <class T>
void store(std::string& out, T x, byte_order order) {
    static_assert(std::is_trivially_copyable_v<T>);
    unsigned char b[sizeof(T)];
    std::memcpy(b, &x, sizeof(T));
    const bool native_little = std::endian::native == std::endian::little;
    if ((order == byte_order::little) != native_little)
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

}  // namespace fabsynth::io::detail
