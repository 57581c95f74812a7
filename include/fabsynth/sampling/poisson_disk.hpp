// SPDX-License-Identifier: MIT
#pragma once
/// @file poisson_disk.hpp  Poisson-disk down-sampling of a finite point set in 2D or 3D, and the
/// radius search that reaches a target sample count (structurally-sound-patterns.md §5.1, after
/// Bowers, Wang, Wei & Maletz 2010, "Parallel Poisson disk sampling with spectrum analysis on
/// surfaces").
///
/// The result is *defined* without reference to any schedule: candidate i gets the priority
/// hash64(seed, i) (its index in the full point array, so a point keeps its priority in any
/// subset), and the sample set is the sequential greedy "visit candidates by increasing priority
/// (ties by index), accept one iff no accepted point lies at distance < r". Hence every pair of
/// samples is at distance >= r and the set is maximal: every candidate lies within r of a sample
/// (strictly closer than r, or is a sample). The implementation reaches exactly that set for any
/// thread count: candidates are taken in priority order in batches of doubling size; in parallel,
/// each candidate of a batch is tested against the samples of the earlier batches (a rejection
/// there is final, since those samples precede it in the order); the few survivors are then
/// resolved sequentially in priority order among themselves. This plays the role of Bowers et
/// al.'s phase groups (independent work in parallel, dependent work in a fixed order) while giving
/// the sequential greedy bit for bit.
///
/// Usage:
///   std::vector<fabsynth::vec3> pts = ...;                        // e.g. solid voxel centres
///   auto s = fabsynth::sampling::poisson_disk(pts, 2.5, {.seed = 7});       // indices into pts
///   auto c = fabsynth::sampling::poisson_disk_count(pts, 1000, {.seed = 7}); // c.indices, c.radius
///
/// A graph's vertex set is sampled through its vertex positions; restrict the candidates with
/// `subset` (indices) and/or `mask` (one byte per point).
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <ranges>
#include <span>
#include <string>
#include <vector>

#include <nanoflann.hpp>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth::sampling {

/// Trait describing the point types accepted: glm vectors of 2 or 3 float/double components.
template <class P>
struct point_traits {
    static constexpr bool valid = false;
};
template <glm::length_t N, class T, glm::qualifier Q>
    requires((N == 2 || N == 3) && std::floating_point<T>)
struct point_traits<glm::vec<N, T, Q>> {
    static constexpr bool valid = true;
    static constexpr int dim = N;
    using scalar = T;
};

/// A 2D or 3D glm vector of float or double (vec2, vec3, fvec3, glm::vec2...).
template <class P>
concept sample_point = point_traits<P>::valid;

/// A contiguous range of sample points (std::vector<vec3>, std::span<const vec2>, ...).
template <class R>
concept point_range = std::ranges::contiguous_range<const R&> && std::ranges::sized_range<const R&> &&
                      sample_point<std::ranges::range_value_t<R>>;

/// Which points are candidates, and the seed of their priorities.
struct poisson_disk_options {
    std::uint64_t seed = 0;                    ///< priorities are hash64(seed, point index)
    std::span<const std::size_t> subset = {};  ///< candidate indices into the points; empty = all points
    std::span<const std::uint8_t> mask = {};   ///< if not empty: one entry per point, candidate iff != 0
                                               ///< (combined with `subset` by "and")
};

/// Options of the radius search; `sampling` as for poisson_disk().
struct poisson_disk_count_options {
    std::uint64_t seed = 0;
    std::span<const std::size_t> subset = {};
    std::span<const std::uint8_t> mask = {};
    double relative_tolerance = 0.02;  ///< stop when |count - target| <= tolerance * target
    int max_evaluations = 64;          ///< radii tried at most (each one greedy pass)
};

/// Result of poisson_disk_count: the closest count found, and the radius that produced it.
struct poisson_disk_count_result {
    std::vector<std::size_t> indices;  ///< chosen points (indices into the input), in priority order
    double radius = 0.0;               ///< radius (input units) that produced `indices`
    int evaluations = 0;               ///< radii tried
    bool within_tolerance = false;     ///< |indices.size() - target| <= relative_tolerance * target
};

namespace detail {

/// nanoflann dataset over a list of indices into the point array; coordinates read as double.
template <class P>
struct indexed_points {
    std::span<const P> points;
    const std::vector<std::size_t>* ids;
    [[nodiscard]] std::size_t kdtree_get_point_count() const { return ids->size(); }
    [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t d) const {
        return static_cast<double>(points[(*ids)[i]][static_cast<glm::length_t>(d)]);
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
        return false;
    }
};

template <class P>
[[nodiscard]] inline double distance_sq(const P& a, const P& b) noexcept {
    double s = 0.0;
    for (glm::length_t d = 0; d < point_traits<P>::dim; ++d) {
        const double t = static_cast<double>(a[d]) - static_cast<double>(b[d]);
        s += t * t;
    }
    return s;
}

/// nanoflann result set: "is some point strictly closer than r?" (stops at the first one).
/// The tree only prunes (with a slightly enlarged bound, so rounding in its box distances never
/// drops a point); the decision uses distance_sq, the same formula everywhere.
template <class P>
struct any_within {
    std::span<const P> points;
    const std::vector<std::size_t>* ids;
    P query;
    double r2;
    double prune2;
    bool found = false;
    std::size_t hit = 0;
    [[nodiscard]] double worstDist() const { return prune2; }
    [[nodiscard]] bool full() const { return true; }
    bool addPoint(double, std::size_t i) {
        if (distance_sq(points[(*ids)[i]], query) < r2) {
            found = true;
            hit = i;
            return false;  // stop the search
        }
        return true;
    }
};

/// nanoflann result set collecting every point strictly closer than r.
template <class P>
struct all_within {
    std::span<const P> points;
    const std::vector<std::size_t>* ids;
    P query;
    double r2;
    double prune2;
    std::vector<std::size_t>* out;
    [[nodiscard]] double worstDist() const { return prune2; }
    [[nodiscard]] bool full() const { return true; }
    bool addPoint(double, std::size_t i) {
        if (distance_sq(points[(*ids)[i]], query) < r2) out->push_back(i);
        return true;
    }
};

template <class P>
using kd_tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, indexed_points<P>, double>,
                                                    indexed_points<P>, point_traits<P>::dim, std::size_t>;

/// The candidates in priority order, validated once; evaluate(r) runs the greedy for radius r.
/// A k-d tree (nanoflann) over the samples of earlier batches answers "any sample within r?";
/// it is rebuilt once per batch (batches double, so O(log n) rebuilds of at most #samples points).
/// nanoflann rather than a uniform grid of cell r/sqrt(d): no cell-count blow-up for tiny radii
/// during the count search, nor for flat or clustered point sets.
template <class P>
class greedy_sampler {
public:
    greedy_sampler(std::span<const P> points, std::uint64_t seed, std::span<const std::size_t> subset,
                   std::span<const std::uint8_t> mask, const char* who) {
        const std::string name(who);
        if (points.empty()) throw invalid_input(name + ": the point set is empty");
        if (!mask.empty() && mask.size() != points.size())
            throw invalid_input(name + ": mask has " + std::to_string(mask.size()) + " entries for " +
                                std::to_string(points.size()) + " points");
        if (subset.empty()) {
            order_.resize(points.size());
            std::iota(order_.begin(), order_.end(), std::size_t{0});
        } else {
            order_.assign(subset.begin(), subset.end());
            for (std::size_t i : order_)
                if (i >= points.size())
                    throw invalid_input(name + ": subset index " + std::to_string(i) + " is out of range (" +
                                        std::to_string(points.size()) + " points)");
            std::sort(order_.begin(), order_.end());
            order_.erase(std::unique(order_.begin(), order_.end()), order_.end());
        }
        if (!mask.empty()) std::erase_if(order_, [&](std::size_t i) { return mask[i] == 0; });
        if (order_.empty()) throw invalid_input(name + ": no candidate point (subset and mask select none)");
        for (std::size_t i : order_)
            if (!all_finite(points[i]))
                throw invalid_input(name + ": point " + std::to_string(i) + " has a non-finite coordinate");
        std::vector<std::uint64_t> key(points.size());
        for (std::size_t i : order_) key[i] = hash64(seed, i);
        std::sort(order_.begin(), order_.end(),
                  [&](std::size_t a, std::size_t b) { return key[a] < key[b] || (key[a] == key[b] && a < b); });
        // A copy in priority order: the batches then read memory sequentially.
        ranked_.resize(order_.size());
        for (std::size_t k = 0; k < order_.size(); ++k) ranked_[k] = points[order_[k]];
    }

    [[nodiscard]] std::size_t candidates() const noexcept { return order_.size(); }
    [[nodiscard]] const std::vector<std::size_t>& order() const noexcept { return order_; }

    /// Diagonal of the candidates' bounding box.
    [[nodiscard]] double diameter() const {
        P lo = ranked_[0], hi = lo;
        for (const P& p : ranked_) lo = glm::min(lo, p), hi = glm::max(hi, p);
        return std::sqrt(distance_sq(lo, hi));
    }

    /// The greedy sample set for radius r (> 0), in priority order (indices into the input).
    [[nodiscard]] std::vector<std::size_t> evaluate(double r) const {
        // All indices below are ranks (positions in the priority order, i.e. into ranked_).
        const std::span<const P> pts(ranked_);
        const double r2 = r * r, prune2 = r2 * (1.0 + 1e-9) + std::numeric_limits<double>::min();
        std::vector<std::size_t> accepted;
        indexed_points<P> accepted_data{pts, &accepted};
        std::vector<std::uint8_t> survives;
        std::vector<std::size_t> survivors, near;
        indexed_points<P> survivor_data{pts, &survivors};
        std::vector<std::uint8_t> killed;
        std::size_t batch = 256;
        for (std::size_t begin = 0; begin < pts.size(); begin += batch, batch *= 2) {
            const std::size_t end = std::min(pts.size(), begin + batch);
            // 1. In parallel: a candidate near a sample of an earlier batch is rejected for good.
            survives.assign(end - begin, 1);
            if (!accepted.empty()) {
                kd_tree<P> tree(point_traits<P>::dim, accepted_data, nanoflann::KDTreeSingleIndexAdaptorParams(16));
                parallel_for(
                    begin, end,
                    [&](std::size_t k) {
                        any_within<P> rs{pts, &accepted, pts[k], r2, prune2};
                        double qd[3] = {0.0, 0.0, 0.0};
                        for (glm::length_t d = 0; d < point_traits<P>::dim; ++d) qd[d] = static_cast<double>(pts[k][d]);
                        tree.findNeighbors(rs, qd, {});
                        survives[k - begin] = rs.found ? 0 : 1;
                    },
                    {.grain = 1024});
            }
            survivors.clear();
            for (std::size_t k = begin; k < end; ++k)
                if (survives[k - begin]) survivors.push_back(k);
            if (survivors.empty()) continue;
            // 2. Sequentially, in priority order: greedy among the survivors (a k-d tree over them
            //    finds the survivors an accepted one rejects).
            killed.assign(survivors.size(), 0);
            kd_tree<P> tree(point_traits<P>::dim, survivor_data, nanoflann::KDTreeSingleIndexAdaptorParams(16));
            for (std::size_t s = 0; s < survivors.size(); ++s) {
                if (killed[s]) continue;
                accepted.push_back(survivors[s]);
                const P& q = pts[survivors[s]];
                near.clear();
                all_within<P> rs{pts, &survivors, q, r2, prune2, &near};
                double qd[3] = {0.0, 0.0, 0.0};
                for (glm::length_t d = 0; d < point_traits<P>::dim; ++d) qd[d] = static_cast<double>(q[d]);
                tree.findNeighbors(rs, qd, {});
                for (std::size_t t : near) killed[t] = 1;
            }
        }
        for (std::size_t& a : accepted) a = order_[a];
        return accepted;
    }

private:
    std::vector<std::size_t> order_;  // candidates by increasing priority
    std::vector<P> ranked_;           // the points in that order: ranked_[k] = points[order_[k]]
};

template <class R>
[[nodiscard]] auto as_span(const R& points) {
    using P = std::ranges::range_value_t<R>;
    return std::span<const P>(std::ranges::data(points), std::ranges::size(points));
}

}  // namespace detail

/// Poisson-disk sample of the candidate points for radius r: indices into `points` (in priority
/// order) such that every pair is at distance >= r and every candidate is within r of a sample;
/// equal to the sequential greedy in priority order (see the file comment), for any thread count.
/// @param points  #points 2D or 3D positions (any units; r in the same units)
/// @param radius  minimum distance between samples, finite and > 0
/// Throws invalid_input for an empty point or candidate set, non-finite candidate coordinates, a bad
/// radius, a subset index out of range or a mask of the wrong size.
/// Cost: O(n log n) for the priority order plus O(n log s) for n candidates and s samples.
template <point_range R>
[[nodiscard]] std::vector<std::size_t> poisson_disk(const R& points, double radius, const poisson_disk_options& opt = {}) {
    using P = std::ranges::range_value_t<R>;
    if (!(std::isfinite(radius) && radius > 0.0))
        throw invalid_input("poisson_disk: radius must be finite and > 0, got " + std::to_string(radius));
    const detail::greedy_sampler<P> sampler(detail::as_span(points), opt.seed, opt.subset, opt.mask, "poisson_disk");
    return sampler.evaluate(radius);
}

/// Poisson-disk sample with about `target` points: a search on the radius (bisection in log r,
/// with log-log interpolation where it stays well inside the bracket). The count is not monotone
/// in r in general (a larger disc can block a point that would have blocked two), so the search
/// keeps a bracket [lo, hi] with count(lo) >= target > count(hi), stops when a count is within
/// `relative_tolerance * target` of the target, when the bracket collapses (relative width 1e-12)
/// or after `max_evaluations` radii, and returns the closest count found (ties: the first found)
/// with its radius. Throws invalid_input as poisson_disk() does, and for target 0 or target larger
/// than the number of candidates, a negative/non-finite tolerance or max_evaluations < 1.
template <point_range R>
[[nodiscard]] poisson_disk_count_result poisson_disk_count(const R& points, std::size_t target,
                                                           const poisson_disk_count_options& opt = {}) {
    using P = std::ranges::range_value_t<R>;
    const detail::greedy_sampler<P> sampler(detail::as_span(points), opt.seed, opt.subset, opt.mask, "poisson_disk_count");
    if (target == 0 || target > sampler.candidates())
        throw invalid_input("poisson_disk_count: target " + std::to_string(target) + " must be in [1, " +
                            std::to_string(sampler.candidates()) + "] (the number of candidates)");
    if (!(std::isfinite(opt.relative_tolerance) && opt.relative_tolerance >= 0.0))
        throw invalid_input("poisson_disk_count: relative_tolerance must be finite and >= 0");
    if (opt.max_evaluations < 1) throw invalid_input("poisson_disk_count: max_evaluations must be >= 1");

    const double t = static_cast<double>(target);
    const double slack = opt.relative_tolerance * t;
    poisson_disk_count_result best;
    double best_error = std::numeric_limits<double>::infinity();
    auto try_radius = [&](double r) {
        std::vector<std::size_t> s = sampler.evaluate(r);
        ++best.evaluations;
        const double c = static_cast<double>(s.size());
        if (std::abs(c - t) < best_error) {
            best_error = std::abs(c - t);
            best.indices = std::move(s);
            best.radius = r;
            best.within_tolerance = best_error <= slack;
        }
        return c;
    };
    const double diameter = sampler.diameter();
    // Above the diameter every candidate is within r of the first: count 1, known without a pass.
    double hi = diameter > 0.0 ? diameter * (1.0 + 1e-9) : 1.0, c_hi = 1.0;
    if (target == 1 || diameter == 0.0) {
        try_radius(hi);
        return best;
    }
    // Shrink from the diameter until the count reaches the target (each halving multiplies the
    // count by about 2^dim); stop at a floor where no further candidate can be separated.
    double lo = hi, c_lo = c_hi;
    const double floor_radius = diameter * 1e-12;
    while (best.evaluations < opt.max_evaluations) {
        hi = lo, c_hi = c_lo;
        lo = hi / 4.0;
        c_lo = try_radius(lo);
        if (best.within_tolerance || c_lo >= t || lo < floor_radius) break;
    }
    if (best.within_tolerance || c_lo < t) return best;  // done, or the target is unreachable
    // Invariant: c_lo >= target > c_hi.
    while (best.evaluations < opt.max_evaluations && !best.within_tolerance && hi / lo - 1.0 > 1e-12) {
        const double llo = std::log(lo), lhi = std::log(hi);
        double lm = 0.5 * (llo + lhi);
        if (c_lo > c_hi && c_hi > 0.0) {  // count ~ r^-dim: interpolate log count linearly in log r
            const double f = (std::log(c_lo) - std::log(t)) / (std::log(c_lo) - std::log(c_hi));
            if (f > 0.1 && f < 0.9) lm = llo + f * (lhi - llo);
        }
        const double mid = std::exp(lm);
        if (!(mid > lo && mid < hi)) break;
        const double c = try_radius(mid);
        if (c >= t)
            lo = mid, c_lo = c;
        else
            hi = mid, c_hi = c;
    }
    return best;
}

}  // namespace fabsynth::sampling
