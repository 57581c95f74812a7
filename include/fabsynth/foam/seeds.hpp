// SPDX-License-Identifier: MIT
#pragma once
/// @file seeds.hpp  Graded jittered-grid Voronoi seeds: Algorithm 3 (SUBDIVIDECELL) of
/// Martinez, Dumas & Lefebvre, "Procedural Voronoi Foams for Additive Manufacturing", SIGGRAPH 2016.
///
/// Space is cut into coarse cubic cells of side L (`seed_options::cell`, 2-5 mm in the paper). A
/// cell of side l centred at c must hold t = l^3 rho(c) seeds. If t > 8 it is split into its 8
/// children (recursively); otherwise n = floor(t) distinct children, picked by a random
/// permutation, receive one uniform seed each, and one more child receives a seed with
/// probability t - n. Every random number comes from fabsynth::counter_rng keyed by
/// (global seed, cell coordinates at that level, level), so the seeds of a cell never depend on
/// the order of queries or on the thread count.
///
/// Density handling (documented clamps and errors):
///  - rho(c) NaN, infinite or negative: throws invalid_input naming the point;
///  - rho(c) < 1/L^3 is raised to 1/L^3 (the paper's minimum: every coarse cell gets >= 1 seed);
///  - rho(c) > max_density is lowered to max_density; max_density is itself capped at
///    `max_seeds_per_cell / L^3` so a coarse cell never holds more than 32768 seeds (bounded memory).
///  - if the subdivision of a coarse cell (t > 8 at its centre but small rho at every child centre)
///    drew no seed at all, one fallback seed is drawn uniformly in the coarse cell, keyed by level -1.
///    So EVERY coarse cell holds at least one seed; the evaluator relies on it only to bound its search.
///
/// Periodic foams (for homogenization, paper §4.1 "a periodic version of the structure in a base
/// volume"): with a period P = (Px, Py, Pz) coarse cells, the seeds of coarse cell c are those of the
/// wrapped cell w = c mod P (hash keys AND density lookups use w and positions inside w's cell)
/// shifted by (c - w) L. The seed set is then invariant under translations by Pa L along each axis
/// a, so its Voronoi diagram, and the foam evaluated on it, tile space exactly with the box
/// [0, P L) as one period; the evaluator needs no change because it only asks for cell_seeds(c).
/// The period is seed_options::period (voronoi_foam forwards foam_options::period).
///
/// Usage:
///   fabsynth::foam::seed_generator gen(fabsynth::foam::constant_field{0.5}, {.cell = 2.0, .seed = 7});
///   std::vector<fabsynth::vec3> s = gen.seeds_in_box({{0,0,0},{10,10,10}});
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/fields.hpp"

namespace fabsynth::foam {

/// Most seeds one coarse cell may hold (bounds memory and time per query).
inline constexpr double max_seeds_per_cell = 32768.0;
/// Largest |coordinate| / cell accepted (coarse indices and their level-5 refinements fit in int64).
inline constexpr double max_cell_index = 1e12;

/// Parameters of the seed process.
struct seed_options {
    double cell = 2.0;               ///< coarse cell side L, mm (> 0)
    std::uint64_t seed = 0;          ///< global random seed
    double max_density = 1e300;      ///< seeds/mm^3; clamped to max_seeds_per_cell / L^3
    i64vec3 period{0};               ///< coarse cells per period on each axis; (0,0,0) = aperiodic, else all >= 1
};

/// Largest period accepted (coarse cells per axis).
inline constexpr std::int64_t max_period_cells = 1 << 20;

namespace detail {
/// Floor division of a by b > 0.
[[nodiscard]] constexpr std::int64_t floor_div(std::int64_t a, std::int64_t b) noexcept {
    const std::int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}
}  // namespace detail

/// Coarse cell index holding point p (floor(p / L)); throws invalid_input for non-finite or huge p.
[[nodiscard]] inline i64vec3 coarse_cell_of(const vec3& p, double cell) {
    i64vec3 c;
    for (int a = 0; a < 3; ++a) {
        const double v = p[a] / cell;
        if (!(std::abs(v) <= max_cell_index))
            throw invalid_input("foam query point coordinate " + std::to_string(p[a]) +
                                " is not finite or too far from the origin (|x| / cell must be <= 1e12)");
        // floor(v) without the library call (std::floor is one on baseline x86-64); |v| <= 1e12
        // truncates exactly
        const auto i = static_cast<std::int64_t>(v);
        c[a] = i - (v < static_cast<double>(i));
    }
    return c;
}

/// Seeds of Algorithm 3 for a density field (any scalar_field, seeds/mm^3).
template <scalar_field Density>
class seed_generator {
public:
    seed_generator(Density rho, seed_options opt) : rho_(std::move(rho)), opt_(opt) {
        require_positive(opt_.cell, "foam seed_options.cell (coarse cell size, mm)");
        if (!(opt_.max_density > 0) || std::isnan(opt_.max_density))
            throw invalid_input("foam seed_options.max_density must be > 0");
        const double l3 = opt_.cell * opt_.cell * opt_.cell;
        min_density_ = 1.0 / l3;
        max_density_ = std::max(min_density_, std::min(opt_.max_density, max_seeds_per_cell / l3));
        if (opt_.period != i64vec3(0))
            for (int a = 0; a < 3; ++a)
                if (opt_.period[a] < 1 || opt_.period[a] > max_period_cells)
                    throw invalid_input("foam seed period must be (0,0,0) (aperiodic) or >= 1 and <= " +
                                        std::to_string(max_period_cells) + " coarse cells on every axis, got " +
                                        std::to_string(opt_.period[a]) + " on axis " + std::to_string(a));
    }

    /// True when the seeds repeat with period options().period coarse cells.
    [[nodiscard]] bool periodic() const noexcept { return opt_.period != i64vec3(0); }
    /// Side of one period in mm per axis (period * cell); zero when aperiodic.
    [[nodiscard]] vec3 period_length() const noexcept { return vec3(opt_.period) * opt_.cell; }

    [[nodiscard]] const seed_options& options() const noexcept { return opt_; }
    [[nodiscard]] const Density& density() const noexcept { return rho_; }
    [[nodiscard]] double min_density() const noexcept { return min_density_; }
    [[nodiscard]] double max_density() const noexcept { return max_density_; }

    /// rho(x) after the documented clamps (seeds/mm^3); throws invalid_input on NaN/inf/negative.
    [[nodiscard]] double effective_density(const vec3& x) const {
        const double r = static_cast<double>(rho_(x));
        if (!std::isfinite(r) || r < 0)
            throw invalid_input("foam density field returned " + std::to_string(r) + " at (" + std::to_string(x.x) +
                                ", " + std::to_string(x.y) + ", " + std::to_string(x.z) +
                                "); it must be finite and >= 0 seeds/mm^3");
        return std::clamp(r, min_density_, max_density_);
    }

    /// Appends the seeds of coarse cell `c` (cell [c L, (c+1) L]^3) to `out`.
    /// Periodic: the seeds of the wrapped cell c mod period, shifted by whole periods.
    void cell_seeds(const i64vec3& c, std::vector<vec3>& out) const {
        const std::size_t before = out.size();
        i64vec3 w = c;
        vec3 shift(0.0);
        if (periodic())
            for (int a = 0; a < 3; ++a) {
                const std::int64_t k = detail::floor_div(c[a], opt_.period[a]);
                w[a] = c[a] - k * opt_.period[a];
                shift[a] = static_cast<double>(k * opt_.period[a]) * opt_.cell;
            }
        subdivide(w, 0, opt_.cell, out);
        if (out.size() == before) {  // see file comment: guarantee >= 1 seed per coarse cell
            counter_rng r(opt_.seed, w.x, w.y, w.z, std::int64_t{-1});
            const vec3 lo = vec3(w) * opt_.cell;
            out.push_back(lo + opt_.cell * vec3(r.uniform(), r.uniform(), r.uniform()));
        }
        if (periodic())
            for (std::size_t i = before; i < out.size(); ++i) out[i] += shift;
    }

    /// Every seed inside the closed box b. Throws invalid_input when b spans more than 1e7 coarse
    /// cells (a region too large to hold in memory) or is not finite.
    [[nodiscard]] std::vector<vec3> seeds_in_box(const box3& b) const {
        std::vector<vec3> out, tmp;
        if (b.empty()) return out;
        if (!all_finite(b.lo) || !all_finite(b.hi)) throw invalid_input("foam seeds_in_box: box is not finite");
        const i64vec3 lo = coarse_cell_of(b.lo, opt_.cell), hi = coarse_cell_of(b.hi, opt_.cell);
        const double cells = double(hi.x - lo.x + 1) * double(hi.y - lo.y + 1) * double(hi.z - lo.z + 1);
        if (cells > 1e7)
            throw invalid_input("foam seeds_in_box: box spans " + std::to_string(cells) +
                                " coarse cells (limit 1e7); use a smaller box or a larger cell");
        for (std::int64_t z = lo.z; z <= hi.z; ++z)
            for (std::int64_t y = lo.y; y <= hi.y; ++y)
                for (std::int64_t x = lo.x; x <= hi.x; ++x) {
                    tmp.clear();
                    cell_seeds({x, y, z}, tmp);
                    for (const vec3& s : tmp)
                        if (b.contains(s)) out.push_back(s);
                }
        return out;
    }

private:
    // Algorithm 3, with the cell given by integer coordinates at `level` (side l = L / 2^level).
    void subdivide(const i64vec3& c, int level, double l, std::vector<vec3>& out) const {
        const vec3 lo = vec3(c) * l;
        const double t = l * l * l * effective_density(lo + vec3(0.5 * l));
        // level < 8 is implied by the clamp (t <= 32768 / 8^level); kept as a hard stop.
        if (t > 8.0 && level < 8) {
            for (int k = 0; k < 8; ++k)
                subdivide(i64vec3(2 * c.x + (k & 1), 2 * c.y + ((k >> 1) & 1), 2 * c.z + ((k >> 2) & 1)), level + 1,
                          0.5 * l, out);
            return;
        }
        counter_rng r(opt_.seed, c.x, c.y, c.z, std::int64_t{level});
        std::array<int, 8> perm{0, 1, 2, 3, 4, 5, 6, 7};
        for (int i = 7; i > 0; --i)  // Fisher-Yates
            std::swap(perm[static_cast<std::size_t>(i)], perm[r.uniform_int(static_cast<std::uint64_t>(i) + 1)]);
        const int n = std::min(8, static_cast<int>(std::floor(t)));
        const double frac = t - n;
        const double h = 0.5 * l;
        auto draw = [&](int child) {
            const vec3 o = lo + h * vec3(child & 1, (child >> 1) & 1, (child >> 2) & 1);
            out.push_back(o + h * vec3(r.uniform(), r.uniform(), r.uniform()));
        };
        for (int i = 0; i < n; ++i) draw(perm[static_cast<std::size_t>(i)]);
        const double p = r.uniform();
        if (n < 8 && p < frac) draw(perm[static_cast<std::size_t>(n)]);
    }

    Density rho_;
    seed_options opt_;
    double min_density_ = 0, max_density_ = 0;
};

}  // namespace fabsynth::foam
