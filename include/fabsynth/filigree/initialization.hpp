// SPDX-License-Identifier: MIT
#pragma once
/// @file initialization.hpp  Initial element distribution (filigree-synthesis.md §4.1, §7.3): dart
/// throwing around the elements placed so far (sampling/dart_throwing.hpp), keeping a candidate S
/// iff, with areas of covering regions,
///   (1) area(S ∩ union of the others) <= 60% of area(S),
///   (2) area(S ∩ E) <= 30% of area(S) for every other element E,
///   (3) area(S ∩ E) >= 10% of area(S) for at least one E,
/// after S was rotated and scaled by the control field at its reference point.
///
/// Multi-class (§7.3, after Wei 2010): each attempt draws from the class that is most underfilled,
/// (count + 1) / share smallest with share = weight / sum of weights; among equally underfilled
/// classes the smaller element (bounding-box diagonal) goes first, as the paper gives larger
/// elements lower priority. A weight of 0 removes a class (the paper's infinite size factor).
/// Overlaps with an element of the same class count `same_class_penalty` times in (1) and (2), so
/// same-class pile-ups are rejected more often (§7.3). The penalty exists to keep the classes of a
/// mix apart: with a single class of positive weight every overlap is same-class and the penalty
/// would only turn the printed 60/30% rules into 40/20%, so it applies only where the mix has two
/// or more classes (effective_same_class_penalty).
///
/// Domain (§7.2): a candidate's reference point must lie in the domain and the part of S inside the
/// domain not yet covered must be at least `min_new_inside` of area(S); the first element is put at
/// the domain point nearest the centre of its bounding box. Candidates: an element that is not yet
/// exhausted chosen uniformly, a point on its covering boundary (uniform in arc length), then a
/// uniform direction and a distance up to half the new element's size; an element is exhausted
/// after `attempts_per_host` failed candidates around it. Stops when every element is exhausted
/// ("the domain is covered and no element can be added"), at `max_elements`, or after
/// `max_consecutive_rejections` failures in a row. Deterministic: attempt a draws from
/// counter_rng(seed, a), and the loop is sequential.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/filigree/domain.hpp"
#include "fabsynth/filigree/element.hpp"
#include "fabsynth/filigree/field.hpp"
#include "fabsynth/filigree/pattern.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/sampling/dart_throwing.hpp"

namespace fabsynth::filigree {

struct initialization_options {
    double max_union_overlap = 0.60;   ///< rule (1), fraction of area(S)
    double max_single_overlap = 0.30;  ///< rule (2)
    double min_single_overlap = 0.10;  ///< rule (3)
    double same_class_penalty = 1.5;   ///< factor on same-class overlaps in (1) and (2), >= 1
    double min_new_inside = 0.10;      ///< newly covered area inside the domain, fraction of area(S)
    std::size_t attempts_per_host = 60;          ///< failed candidates around one element before it is exhausted
    std::size_t max_consecutive_rejections = 20'000;  ///< safety stop of the loop
    std::size_t max_elements = 5000;
    std::uint64_t seed = 1;
};

/// The smallest covering region (mm^2) among the classes of positive weight, each scaled by
/// `min_scale` (the smallest scale factor of the control field): the element that packs densest.
/// Infinite when every weight is 0. `weights`: one per class.
[[nodiscard]] inline double smallest_covering_area(std::span<const element> classes, std::span<const double> weights, double min_scale = 1.0) {
    if (weights.size() != classes.size()) throw invalid_input("smallest_covering_area: one weight per element class is needed");
    double smallest = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < classes.size(); ++c)
        if (weights[c] > 0) smallest = std::min(smallest, classes[c].covering_area * min_scale * min_scale);
    return smallest;
}

/// An estimate of the most instances initialization places in a domain of `area` mm^2 with
/// elements whose smallest covering region is `smallest_cover` mm^2 (smallest_covering_area): by
/// rule (1) each new instance covers at least (1 - max_union_overlap) of its region anew, so this
/// bounds the count when `area` is the union of the regions (the domain plus what sticks out of
/// it). For refusing oversized work before any is done.
[[nodiscard]] inline double estimated_instances(double area, double smallest_cover, const initialization_options& opt = {}) {
    return area / ((1.0 - opt.max_union_overlap) * smallest_cover);
}

/// The same-class factor that applies to a mix: `penalty` when two or more classes have a positive
/// weight, 1 for a single class (see the file comment).
[[nodiscard]] inline double effective_same_class_penalty(std::span<const double> weights, double penalty) {
    std::size_t used = 0;
    for (const double w : weights) used += w > 0;
    return used >= 2 ? penalty : 1.0;
}

/// What initialization produced.
struct initialization_result {
    std::vector<instance> instances;
    std::size_t attempts = 0;
    double covered_fraction = 0.0;  ///< area(domain ∩ union of covering regions) / area(domain)
};

namespace detail::init {

[[nodiscard]] inline std::vector<polygon_with_holes> covering_polys(const placed& p) {
    std::vector<polygon_with_holes> out;
    for (const ring2& r : p.covering) out.push_back({r, {}});
    return out;
}

// The domain point nearest the centre of its bounding box, on a 64 x 64 lattice.
[[nodiscard]] inline vec2 central_point(const planar_domain& d) {
    const vec2 c = 0.5 * (d.bounds.lo + d.bounds.hi);
    if (d.contains(c)) return c;
    vec2 best = c;
    double best_d = std::numeric_limits<double>::infinity();
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            const vec2 p = d.bounds.lo + (d.bounds.hi - d.bounds.lo) * vec2((i + 0.5) / 64, (j + 0.5) / 64);
            if (d.contains(p) && glm::distance(p, c) < best_d) best_d = glm::distance(p, c), best = p;
        }
    return best;
}

// A uniform point (in arc length) on the boundary of p's covering parts.
[[nodiscard]] inline vec2 boundary_point(const placed& p, counter_rng& rng) {
    double total = 0;
    for (const ring2& r : p.covering) total += perimeter(r);
    double t = rng.uniform() * total;
    for (const ring2& r : p.covering)
        for (std::size_t i = 0; i < r.size(); ++i) {
            const vec2 a = r[i], b = r[(i + 1) % r.size()];
            const double l = glm::distance(a, b);
            if (t <= l && l > 0) return a + (b - a) * (t / l);
            t -= l;
        }
    return p.covering.back().back();
}

// Rule checks (1)-(3) and the domain rule for candidate geometry `pc` of class `cls` against the
// accepted instances `geo` (classes `cls_of`) seen in the same frame; `region`: the domain in that
// frame (nullptr: the candidate lies wholly in the domain).
[[nodiscard]] inline bool admissible(const placed& pc, std::uint32_t cls, std::span<const placed> geo, std::span<const std::uint32_t> cls_of,
                                     const std::vector<polygon_with_holes>* region, const initialization_options& opt) {
    const auto S = covering_polys(pc);
    const double aS = area(polygon_union(S, {}));
    if (!(aS > 0)) return false;
    std::vector<polygon_with_holes> others;
    double max_single = 0, union_weighted = 0;
    bool some_contact = geo.empty();
    for (std::size_t j = 0; j < geo.size(); ++j) {
        if (!boxes_meet(pc, geo[j])) continue;
        const auto Ej = covering_polys(geo[j]);
        const double a = area(polygon_intersection(S, Ej));
        if (a <= 0) continue;
        const double pen = cls_of[j] == cls ? opt.same_class_penalty : 1.0;
        max_single = std::max(max_single, pen * a / aS);
        if (a / aS >= opt.min_single_overlap) some_contact = true;
        others.insert(others.end(), Ej.begin(), Ej.end());
        union_weighted = std::max(union_weighted, pen);  // the strongest penalty among the overlapped
    }
    if (!some_contact || max_single > opt.max_single_overlap) return false;
    // The part of S inside the domain that nothing covers yet.
    const auto inside = region ? polygon_intersection(S, *region) : polygon_union(S, {});
    const auto fresh = others.empty() ? inside : polygon_difference(inside, polygon_union(others, {}));
    if (area(fresh) < opt.min_new_inside * aS) return false;
    if (!others.empty()) {
        const double covered = aS - area(polygon_difference(S, polygon_union(others, {})));
        if (std::max(1.0, union_weighted) * covered / aS > opt.max_union_overlap) return false;
    }
    return true;
}

// Multi-class draw of §7.3 (see the file comment): the most underfilled class, smaller first on ties.
struct class_picker {
    std::span<const element> classes;
    std::span<const double> weights;
    double wsum = 0;
    std::vector<std::size_t> count;

    class_picker(std::span<const element> c, std::span<const double> w) : classes(c), weights(w), count(c.size(), 0) {
        if (classes.empty()) throw invalid_input("initialization: no element classes");
        if (weights.size() != classes.size()) throw invalid_input("initialization: one weight per element class is needed");
        for (double x : weights) {
            if (!(std::isfinite(x) && x >= 0)) throw invalid_input("initialization: class weights must be finite and >= 0");
            wsum += x;
        }
        if (!(wsum > 0)) throw invalid_input("initialization: at least one class weight must be > 0");
    }
    // The most underfilled class among those `allowed` accepts (UINT32_MAX when none does).
    template <class Allowed>
    [[nodiscard]] std::uint32_t pick(Allowed&& allowed) const {
        std::uint32_t best = UINT32_MAX;
        double best_key = std::numeric_limits<double>::infinity();
        for (std::uint32_t c = 0; c < classes.size(); ++c) {
            if (weights[c] <= 0 || !allowed(c)) continue;
            const double key = (static_cast<double>(count[c]) + 1.0) / (weights[c] / wsum);
            if (key < best_key * (1 - 1e-12) ||
                (std::abs(key - best_key) <= 1e-12 * best_key && best != UINT32_MAX && classes[c].size < classes[best].size))
                best_key = key, best = c;
        }
        return best;
    }
    [[nodiscard]] std::uint32_t pick() const {
        return pick([](std::uint32_t) { return true; });
    }
};

// Hosts: elements around which candidates are still thrown. One that has produced
// attempts_per_host failures in total is exhausted, so the loop keeps exploring the open fronts
// (a narrow domain has only a few) and ends when every element is exhausted.
struct host_pool {
    std::size_t attempts_per_host;
    std::vector<std::size_t> alive, failures;
    std::size_t host = SIZE_MAX, first_failures = 0;  // host of the current candidate (SIZE_MAX: the first element)

    explicit host_pool(std::size_t per_host) : attempts_per_host(per_host) {}

    void failed() {
        if (host == SIZE_MAX) {
            ++first_failures;
            return;
        }
        if (++failures[host] < attempts_per_host) return;
        alive.erase(std::find(alive.begin(), alive.end(), host));
    }
    void added() { alive.push_back(failures.size()), failures.push_back(0); }
    // Draws the host of the next candidate; false when every element is exhausted.
    [[nodiscard]] bool draw(counter_rng& rng) {
        if (alive.empty()) return false;
        host = alive[static_cast<std::size_t>(rng.uniform_int(alive.size()))];
        return true;
    }
};

// A candidate position around host covering `host_geo`: a point of its covering boundary, then a
// uniform direction and a distance up to half the new element's size (at the field's scale there).
[[nodiscard]] inline vec2 position_near(const placed& host_geo, double class_size, const std::function<double(vec2)>& scale_at, counter_rng& rng) {
    const vec2 b = boundary_point(host_geo, rng);
    const double reach = 0.5 * class_size * scale_at(b) * rng.uniform();
    const double angle = 2 * std::numbers::pi * rng.uniform();
    return b + reach * vec2(std::cos(angle), std::sin(angle));
}

// Dart-throwing options of an initialization.
[[nodiscard]] inline sampling::dart_options dart_options_of(const initialization_options& opt) {
    sampling::dart_options dopt;
    dopt.seed = opt.seed;
    dopt.target = opt.max_elements;
    dopt.max_consecutive_rejections = opt.max_consecutive_rejections;
    // Every failure exhausts a host a little: at most attempts_per_host per element, plus the
    // attempts after the last host is exhausted.
    dopt.max_attempts = opt.max_elements * (opt.attempts_per_host + 1) + opt.max_consecutive_rejections;
    return dopt;
}

}  // namespace detail::init

/// Distributes instances of `classes` over `domain` (see the file comment). weights: one per class,
/// finite and >= 0, not all 0. Throws invalid_input for bad weights or
/// options; no_solution for an element whose covering region (scaled by the field at the domain's
/// centre) is larger than the domain, or when no element can be placed at all.
template <control_field F>
[[nodiscard]] initialization_result initialize(std::span<const element> classes, std::span<const double> weights, const planar_domain& domain,
                                               const F& field, const initialization_options& opt = {}) {
    namespace di = detail::init;
    di::class_picker picker(classes, weights);
    if (!(opt.same_class_penalty >= 1)) throw invalid_input("initialization: same_class_penalty must be >= 1");
    initialization_options rules = opt;
    rules.same_class_penalty = effective_same_class_penalty(weights, opt.same_class_penalty);

    {  // an element whose covering region exceeds the domain cannot be distributed over it
        const double s0 = field(di::central_point(domain)).scale;
        for (std::size_t c = 0; c < classes.size(); ++c)
            if (weights[c] > 0 && classes[c].covering_area * s0 * s0 > domain.area)
                throw no_solution("initialization: element " + classes[c].name + " (covering " + std::to_string(classes[c].covering_area * s0 * s0) +
                                  " mm^2) is larger than the domain (" + std::to_string(domain.area) + " mm^2)");
    }
    std::vector<placed> geo;
    std::vector<std::uint32_t> geo_cls;
    di::host_pool hosts(opt.attempts_per_host);
    const std::function<double(vec2)> scale_at = [&](vec2 p) { return field(p).scale; };

    // The class drawn for a candidate at p: the most underfilled one, or with element sets per
    // region the most underfilled of those allowed at p (UINT32_MAX: none is).
    auto class_at = [&](std::uint32_t current, vec2 p) {
        if (!domain.class_allowed || domain.class_allowed(current, p)) return current;
        return picker.pick([&](std::uint32_t c) { return domain.class_allowed(c, p); });
    };
    auto generate = [&](counter_rng& rng) -> std::optional<instance> {
        const std::uint32_t current = picker.pick();
        hosts.host = SIZE_MAX;
        if (geo.empty()) {  // the first element: the centre, then uniform points of the domain
            if (hosts.first_failures >= opt.attempts_per_host) return std::nullopt;
            const vec2 p = hosts.first_failures == 0 ? di::central_point(domain)
                                                     : domain.bounds.lo + (domain.bounds.hi - domain.bounds.lo) * vec2(rng.uniform(), rng.uniform());
            const std::uint32_t cls = hosts.first_failures == 0 || domain.contains(p) ? class_at(current, p) : UINT32_MAX;
            if (cls == UINT32_MAX) return ++hosts.first_failures, std::nullopt;
            return make_instance(classes, cls, p, field);
        }
        if (!hosts.draw(rng)) return std::nullopt;
        const vec2 p = di::position_near(geo[hosts.host], classes[current].size, scale_at, rng);
        const std::uint32_t cls = domain.contains(p) ? class_at(current, p) : UINT32_MAX;
        if (cls == UINT32_MAX) {
            hosts.failed();
            return std::nullopt;
        }
        return make_instance(classes, cls, p, field);
    };

    auto accept = [&](const instance& cand, std::span<const instance>) {
        placed pc = place(classes[cand.cls], cand);
        if (!di::admissible(pc, cand.cls, geo, geo_cls, &domain.region, rules)) {
            hosts.failed();
            return false;
        }
        geo.push_back(std::move(pc)), geo_cls.push_back(cand.cls);
        ++picker.count[cand.cls];
        hosts.added();
        return true;
    };

    const sampling::dart_options dopt = di::dart_options_of(opt);
    auto r = sampling::dart_throwing(generate, accept, dopt);
    if (r.accepted.empty()) throw no_solution("initialization: no element fits in the domain (is an element larger than the domain?)");

    initialization_result out;
    out.attempts = r.attempts;
    out.instances = std::move(r.accepted);
    std::vector<polygon_with_holes> all;
    for (const placed& p : geo) {
        const auto c = di::covering_polys(p);
        all.insert(all.end(), c.begin(), c.end());
    }
    out.covered_fraction = area(polygon_intersection(polygon_union(all, {}), domain.region)) / domain.area;
    return out;
}

}  // namespace fabsynth::filigree
