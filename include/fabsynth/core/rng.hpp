// SPDX-License-Identifier: MIT
#pragma once
/// @file rng.hpp  Counter-based hash random numbers.
///
/// Every random number is a pure function of (user seed, integer keys, counter), so results are the
/// same on every platform, for every thread count and every evaluation order. The mixing function
/// is the SplitMix64 finaliser (Steele, Lea & Flood, "Fast splittable pseudorandom number
/// generators", OOPSLA 2014), which passes BigCrush when fed a Weyl sequence.
///
/// Usage:
///   fabsynth::counter_rng r(seed, cell.x, cell.y, cell.z, level);
///   double u = r.uniform();          // [0,1), 53 random bits
///   double h = fabsynth::hash_uniform(seed, i, j);   // one-shot
#include <cmath>
#include <concepts>
#include <cstdint>
#include <numbers>

namespace fabsynth {

inline constexpr std::uint64_t golden_gamma = 0x9e3779b97f4a7c15ULL;

/// SplitMix64 finaliser: a bijection of 64-bit words with full avalanche.
[[nodiscard]] constexpr std::uint64_t mix64(std::uint64_t z) noexcept {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

namespace detail {
template <std::integral K>
constexpr std::uint64_t as_u64(K k) noexcept {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(k));  // sign-extends, two's complement
}
}  // namespace detail

/// Hash of a seed and any number of integer keys; order of keys matters.
template <std::integral... K>
[[nodiscard]] constexpr std::uint64_t hash64(std::uint64_t seed, K... keys) noexcept {
    std::uint64_t h = mix64(seed + golden_gamma);
    std::uint64_t i = 1;
    ((h = mix64(h ^ mix64(detail::as_u64(keys) + golden_gamma * ++i))), ...);
    return h;
}

/// High 64 bits of the 128-bit product a*b (portable; no __int128).
[[nodiscard]] constexpr std::uint64_t mulhi64(std::uint64_t a, std::uint64_t b) noexcept {
    const std::uint64_t a_lo = a & 0xffffffffULL, a_hi = a >> 32, b_lo = b & 0xffffffffULL, b_hi = b >> 32;
    const std::uint64_t lo_lo = a_lo * b_lo, hi_lo = a_hi * b_lo, lo_hi = a_lo * b_hi, hi_hi = a_hi * b_hi;
    const std::uint64_t cross = (lo_lo >> 32) + (hi_lo & 0xffffffffULL) + lo_hi;
    return hi_hi + (hi_lo >> 32) + (cross >> 32);
}

/// Top 53 bits of a word as a double in [0, 1).
[[nodiscard]] constexpr double to_unit(std::uint64_t bits) noexcept {
    return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

/// One-shot uniform in [0,1) for (seed, keys...).
template <std::integral... K>
[[nodiscard]] constexpr double hash_uniform(std::uint64_t seed, K... keys) noexcept {
    return to_unit(hash64(seed, keys...));
}

/// A stream of random numbers attached to (seed, keys...): the n-th draw is hash(base, n).
class counter_rng {
public:
    template <std::integral... K>
    constexpr explicit counter_rng(std::uint64_t seed, K... keys) noexcept : base_(hash64(seed, keys...)) {}

    /// Next 64 random bits.
    constexpr std::uint64_t next_u64() noexcept { return mix64(base_ + golden_gamma * ++counter_); }
    /// Uniform double in [0, 1).
    constexpr double uniform() noexcept { return to_unit(next_u64()); }
    /// Uniform double in [a, b).
    constexpr double uniform(double a, double b) noexcept { return a + (b - a) * uniform(); }
    /// Uniform integer in [0, n), n > 0 (multiply-shift; bias below 2^-32 for n < 2^32).
    constexpr std::uint64_t uniform_int(std::uint64_t n) noexcept {
        return mulhi64(next_u64(), n);
    }
    /// Standard normal deviate (Box-Muller, one value per call; uses two draws).
    double normal() noexcept {
        const double u1 = 1.0 - uniform();  // (0, 1]
        const double u2 = uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
    }
    /// Number of draws made so far.
    [[nodiscard]] constexpr std::uint64_t draws() const noexcept { return counter_; }

private:
    std::uint64_t base_;
    std::uint64_t counter_ = 0;
};

}  // namespace fabsynth
