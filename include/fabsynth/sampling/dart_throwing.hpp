// SPDX-License-Identifier: MIT
#pragma once
/// @file dart_throwing.hpp  Dart throwing with a caller-supplied candidate generator and
/// acceptance predicate (filigree-synthesis.md §4.1: a candidate element is kept iff its overlap
/// ratios with the elements accepted so far meet the paper's conditions; blue-noise dart throwing
/// after Wei 2010).
///
/// Attempt a (a = 0, 1, 2, ...) draws its candidate from counter_rng(seed, a), so the result is a
/// pure function of (seed, generator, predicate): the same on every platform and thread count.
/// The loop is sequential by nature (each decision depends on the samples accepted before it).
///
/// Stopping (whichever comes first, never hangs):
///   - `target` candidates accepted                              -> dart_stop::target_reached
///   - `max_consecutive_rejections` rejections in a row          -> dart_stop::saturated
///   - `max_attempts` attempts in total                          -> dart_stop::max_attempts
/// A generator that fails (returns an empty optional) counts as a rejected attempt.
///
/// Usage:
///   fabsynth::sampling::box_generator<2> gen{{{0, 0}, {10, 10}}};
///   auto r = fabsynth::sampling::dart_throwing(gen,
///       [](const fabsynth::vec2& c, std::span<const fabsynth::vec2> acc) {
///           for (const auto& a : acc) if (glm::distance(a, c) < 1.0) return false;
///           return true; },
///       {.seed = 3, .target = 50});
///   // r.accepted, r.attempts, r.stop
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth::sampling {

namespace detail {
template <class T>
struct optional_value {};
template <class T>
struct optional_value<std::optional<T>> {
    using type = T;
};
}  // namespace detail

/// Callable as g(counter_rng&) -> std::optional<C> (empty = no candidate this attempt). It must
/// draw all its randomness from the rng it is given (that is what makes dart throwing
/// deterministic); expected O(1) draws.
template <class G>
concept candidate_generator = std::invocable<G&, counter_rng&> &&
                              requires { typename detail::optional_value<std::remove_cvref_t<std::invoke_result_t<G&, counter_rng&>>>::type; };

/// The candidate type a generator produces.
template <candidate_generator G>
using candidate_t = typename detail::optional_value<std::remove_cvref_t<std::invoke_result_t<G&, counter_rng&>>>::type;

/// Callable as p(const C& candidate, std::span<const C> accepted_so_far) -> bool (true = accept).
template <class F, class C>
concept acceptance_predicate = std::invocable<F&, const C&, std::span<const C>> &&
                               std::convertible_to<std::invoke_result_t<F&, const C&, std::span<const C>>, bool>;

/// Why dart throwing stopped.
enum class dart_stop {
    target_reached,  ///< `target` candidates accepted
    saturated,       ///< `max_consecutive_rejections` rejections in a row
    max_attempts     ///< `max_attempts` attempts made
};

struct dart_options {
    std::uint64_t seed = 0;
    std::size_t target = std::numeric_limits<std::size_t>::max();  ///< stop after this many acceptances
    std::size_t max_consecutive_rejections = 1000;                 ///< >= 1
    std::size_t max_attempts = 1'000'000;                          ///< >= 1
};

template <class C>
struct dart_result {
    std::vector<C> accepted;    ///< in acceptance order
    std::size_t attempts = 0;   ///< candidates drawn (including failed generations)
    dart_stop stop = dart_stop::max_attempts;
};

/// Dart throwing: for a = 0, 1, ...: c = generate(counter_rng(seed, a)); keep c iff
/// accept(c, accepted so far). Stops as documented in the file comment. Throws invalid_input if
/// max_consecutive_rejections or max_attempts is 0; exceptions of the callables propagate.
/// Cost: max_attempts calls of each callable at most.
template <candidate_generator G, acceptance_predicate<candidate_t<G>> F>
[[nodiscard]] dart_result<candidate_t<G>> dart_throwing(G&& generate, F&& accept, const dart_options& opt = {}) {
    if (opt.max_consecutive_rejections == 0)
        throw invalid_input("dart_throwing: max_consecutive_rejections must be >= 1");
    if (opt.max_attempts == 0) throw invalid_input("dart_throwing: max_attempts must be >= 1");
    dart_result<candidate_t<G>> result;
    if (opt.target == 0) {
        result.stop = dart_stop::target_reached;
        return result;
    }
    std::size_t rejections = 0;
    while (result.attempts < opt.max_attempts) {
        counter_rng rng(opt.seed, static_cast<std::uint64_t>(result.attempts));
        ++result.attempts;
        auto c = std::invoke(generate, rng);
        if (c && static_cast<bool>(std::invoke(accept, std::as_const(*c),
                                               std::span<const candidate_t<G>>(result.accepted)))) {
            result.accepted.push_back(std::move(*c));
            rejections = 0;
            if (result.accepted.size() >= opt.target) {
                result.stop = dart_stop::target_reached;
                return result;
            }
        } else if (++rejections >= opt.max_consecutive_rejections) {
            result.stop = dart_stop::saturated;
            return result;
        }
    }
    result.stop = dart_stop::max_attempts;
    return result;
}

/// Uniform points in an axis-aligned box (N = 2 or 3): one draw per coordinate, never fails.
template <glm::length_t N>
    requires(N == 2 || N == 3)
struct box_generator {
    box<N, double> domain;  ///< non-empty, finite
    explicit box_generator(const box<N, double>& b) : domain(b) {
        if (b.empty() || !all_finite(b.lo) || !all_finite(b.hi))
            throw invalid_input("box_generator: the box must be non-empty and finite");
    }
    std::optional<glm::vec<N, double>> operator()(counter_rng& rng) const {
        glm::vec<N, double> p;
        for (glm::length_t i = 0; i < N; ++i) p[i] = rng.uniform(domain.lo[i], domain.hi[i]);
        return p;
    }
};

/// Uniform points in the part of a box where inside(p) holds, by rejection: at most `max_tries`
/// points of the box are drawn per attempt, then the attempt fails (empty optional).
template <glm::length_t N, class Inside>
    requires((N == 2 || N == 3) && std::predicate<const Inside&, const glm::vec<N, double>&>)
struct region_generator {
    box_generator<N> bounds;
    Inside inside;
    int max_tries = 64;
    region_generator(const box<N, double>& b, Inside in, int tries = 64) : bounds(b), inside(std::move(in)), max_tries(tries) {
        if (tries < 1) throw invalid_input("region_generator: max_tries must be >= 1");
    }
    std::optional<glm::vec<N, double>> operator()(counter_rng& rng) const {
        for (int t = 0; t < max_tries; ++t) {
            const auto p = *bounds(rng);
            if (inside(p)) return p;
        }
        return std::nullopt;
    }
};

/// Point-in-polygon test of geometry/polygon.hpp (holes excluded, boundary included) as a region.
struct polygon_region {
    polygon_with_holes polygon;
    bool operator()(const vec2& p) const { return point_in_polygon(polygon, p); }
};

/// Uniform points in a 2D polygon with holes, by rejection in its bounding box (max_tries draws per
/// attempt). Throws invalid_input for an outer ring with fewer than 3 points, non-finite
/// coordinates or zero area. Each try costs O(#polygon vertices).
[[nodiscard]] inline region_generator<2, polygon_region> polygon_generator(polygon_with_holes polygon, int max_tries = 64) {
    if (polygon.outer.size() < 3) throw invalid_input("polygon_generator: the outer ring has fewer than 3 points");
    for (const vec2& p : polygon.outer)
        if (!all_finite(p)) throw invalid_input("polygon_generator: the outer ring has a non-finite point");
    for (const ring2& h : polygon.holes)
        for (const vec2& p : h)
            if (!all_finite(p)) throw invalid_input("polygon_generator: a hole has a non-finite point");
    if (!(area(polygon) > 0.0)) throw invalid_input("polygon_generator: the polygon has no area");
    const box2 b = bounding_box(polygon.outer);
    return region_generator<2, polygon_region>(b, polygon_region{std::move(polygon)}, max_tries);
}

}  // namespace fabsynth::sampling
