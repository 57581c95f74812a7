// SPDX-License-Identifier: MIT
#pragma once
/// @file evaluator.hpp  Exact procedural Voronoi foam F(q): solid iff the distance from q to the
/// EDGES of the 3D Voronoi diagram of the seeds (seeds.hpp) is <= tau(q).
///
/// The class below is the public face; its parts live behind it, one job per header:
///  - detail/certificate.hpp: which seeds the edges inside a box depend on (the proof that replaces
///    the paper's disputed 2-ring rule of Fig. 4, a certificate computed per query), and the
///    gather that applies it per sub-box;
///  - detail/voronoi_edges.hpp: the exact Voronoi edge pieces inside a box (cells of the gathered
///    seeds clipped by bisectors, detail/polytope.hpp; each edge emitted once);
///  - detail/slicer.hpp: the tiled parallel slicer (a seed cache per slice, edges once per tile,
///    row intervals per edge and run filling for a constant radius), O(slice) memory.
/// Every answer is exact (floating-point rounding of ~1e-13 mm aside), so point queries, coverage
/// and slices agree, and slices are bit-identical for any thread count and tile size.
///
/// Bad input (documented): tau(q) NaN/inf/<= 0 throws invalid_input; tau(q) > max radius is
/// clamped to it; the max radius must be finite, > 0 and <= the coarse cell size; the density is
/// clamped to the full-block bound 1/(2 tau(x))^3 (paper §4.2) and as in seeds.hpp; regions over
/// 1e9 pixels, or pixel sizes <= 0, throw invalid_input.
///
/// Usage:
///   using namespace fabsynth::foam;
///   voronoi_foam f(linear_field{0, 0.01, 0.5, 0, 50}, constant_field{0.25}, {.cell = 5, .seed = 1});
///   bool solid = f.contains({1, 2, 3});
///   fabsynth::image8 img = f.slice(10.0, {{0, 0}, {50, 50}}, 0.05);   // 1000 x 1000, 255 = solid
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/detail/certificate.hpp"
#include "fabsynth/foam/detail/slicer.hpp"
#include "fabsynth/foam/detail/voronoi_edges.hpp"
#include "fabsynth/foam/detail/workspace.hpp"
#include "fabsynth/foam/fields.hpp"
#include "fabsynth/foam/seeds.hpp"
#include "fabsynth/geometry/segment.hpp"

namespace fabsynth::foam {

/// Parameters of a foam (besides its two fields).
struct foam_options {
    double cell = 2.0;           ///< coarse cell side L, mm
    std::uint64_t seed = 0;      ///< global random seed
    double max_density = 1e300;  ///< extra density cap, seeds/mm^3 (the full-block bound always applies)
    double max_radius = 0;       ///< bound on tau(x), mm; 0 = Radius::max_value() (required otherwise)
    i64vec3 period{0};           ///< periodic foam: coarse cells per period per axis (seeds.hpp); 0 = aperiodic
};

/// Options of slice().
struct slice_options {
    int supersample = 1;  ///< s: s x s samples per pixel; pixel value = round(255 * covered fraction)
    int tile = 128;       ///< tile side in pixels (work unit of parallel_for); any value gives the same image
};

namespace detail {
/// Density as seen by the seed process: rho(x) capped by the full-block bound 1/(2 tau(x))^3.
template <scalar_field Density, scalar_field Radius>
struct capped_density {
    Density rho;
    Radius tau;
    double operator()(const vec3& x) const {
        const double r = static_cast<double>(rho(x));
        const double t = static_cast<double>(tau(x));
        if (!(std::isfinite(r) && r >= 0) || !(std::isfinite(t) && t > 0)) return r;  // validated elsewhere
        return std::min(r, 1.0 / (8.0 * t * t * t));
    }
};
}  // namespace detail

/// Procedural Voronoi foam over a density field (seeds/mm^3) and a radius field (mm).
template <scalar_field Density, scalar_field Radius>
class voronoi_foam {
public:
    using seeds_type = seed_generator<detail::capped_density<Density, Radius>>;

    voronoi_foam(Density rho, Radius tau, foam_options opt = {})
        : tau_(tau), opt_(opt),
          gen_(detail::capped_density<Density, Radius>{std::move(rho), tau},
               seed_options{.cell = opt.cell, .seed = opt.seed, .max_density = opt.max_density, .period = opt.period}) {
        if constexpr (bounded_field<Radius>) {
            if (opt_.max_radius == 0) opt_.max_radius = static_cast<double>(tau_.max_value());
        }
        if (!(std::isfinite(opt_.max_radius) && opt_.max_radius > 0))
            throw invalid_input("foam radius: the maximum beam radius (foam_options.max_radius or the radius "
                                "field's max_value()) must be finite and > 0 mm, got " +
                                std::to_string(opt_.max_radius));
        if (opt_.max_radius > opt_.cell)
            throw invalid_input("foam radius: maximum beam radius " + std::to_string(opt_.max_radius) +
                                " mm exceeds the coarse cell size " + std::to_string(opt_.cell) +
                                " mm (such beams fill the block; use a larger cell)");
    }

    [[nodiscard]] const seeds_type& seeds() const noexcept { return gen_; }
    [[nodiscard]] const foam_options& options() const noexcept { return opt_; }
    [[nodiscard]] double max_radius() const noexcept { return opt_.max_radius; }

    /// tau(q) after validation and the documented clamp, mm.
    [[nodiscard]] double radius(const vec3& q) const {
        const double t = static_cast<double>(tau_(q));
        if (!(std::isfinite(t) && t > 0))
            throw invalid_input("foam radius field returned " + std::to_string(t) + " at (" + std::to_string(q.x) +
                                ", " + std::to_string(q.y) + ", " + std::to_string(q.z) +
                                "); it must be finite and > 0 mm");
        return std::min(t, opt_.max_radius);
    }

    /// Distance from q to the Voronoi edges if it is <= r (0 < r <= cell), else +infinity.
    [[nodiscard]] double distance_to_edges(const vec3& q, double r) const {
        if (!(r > 0 && r <= opt_.cell)) throw invalid_input("foam distance_to_edges: r must be in (0, cell]");
        thread_local detail::foam_workspace ws;
        double best = r * r;
        bool found = false;
        for_each_edge(box3(q - vec3(r), q + vec3(r)), ws, [&](const vec3& a, const vec3& b) {
            const double d2 = segment_distance2(q, a, b);
            if (d2 <= best) best = d2, found = true;
            return true;
        });
        return found ? std::sqrt(best) : std::numeric_limits<double>::infinity();
    }

    /// F(q): true iff the distance from q to the Voronoi edges is <= tau(q).
    [[nodiscard]] bool contains(const vec3& q) const {
        const double t = radius(q);
        thread_local detail::foam_workspace ws;
        bool solid = false;
        const double t2 = t * t;
        for_each_edge(box3(q - vec3(t), q + vec3(t)), ws, [&](const vec3& a, const vec3& b) {
            if (segment_distance2(q, a, b) <= t2) solid = true;
            return !solid;
        });
        return solid;
    }

    /// Supersampled coverage in [0,1] (grayscale exposure, paper §3.2): the fraction of the s^3
    /// cell-centred samples of the cube of side `voxel` (mm) centred at q that are solid.
    [[nodiscard]] double coverage(const vec3& q, double voxel, int s) const {
        require_positive(voxel, "foam coverage voxel size");
        if (s < 1 || s > 64) throw invalid_input("foam coverage: supersampling must be in [1, 64]");
        thread_local detail::foam_workspace ws;
        const double half = 0.5 * voxel;
        ws.edges.clear();
        for_each_edge(box3(q - vec3(half + opt_.max_radius), q + vec3(half + opt_.max_radius)), ws,
                      [&](const vec3& a, const vec3& b) {
                          ws.edges.push_back({a, b});
                          return true;
                      });
        int count = 0;
        for (int k = 0; k < s; ++k)
            for (int j = 0; j < s; ++j)
                for (int i = 0; i < s; ++i) {
                    const vec3 p = q - vec3(half) + voxel * (vec3(i, j, k) + 0.5) / double(s);
                    const double t = radius(p), t2 = t * t;
                    for (const edge_segment& e : ws.edges)
                        if (segment_distance2(p, e.a, e.b) <= t2) {
                            ++count;
                            break;
                        }
                }
        return double(count) / double(s * s * s);
    }

    /// Every Voronoi edge piece inside box b (clipped to b), appended to out. The box must be
    /// finite with extent <= 64 coarse cells.
    void edges_in_box(const box3& b, std::vector<edge_segment>& out) const {
        detail::foam_workspace ws;
        for_each_edge(b, ws, [&](const vec3& a, const vec3& c) {
            out.push_back({a, c});
            return true;
        });
    }

    /// Slice at height z over region [lo, hi] (mm) with square pixels of side `pixel` (mm).
    /// The image is ceil((hi - lo) / pixel) pixels; pixel (i, j) is centred at
    /// (lo.x + (i + 1/2) pixel, lo.y + (j + 1/2) pixel, z); row j = 0 is at lo.y.
    /// Value 255 = solid, 0 = empty (or 255 * coverage with supersampling).
    [[nodiscard]] image8 slice(double z, const box2& region, double pixel, slice_options so = {}) const {
        const auto [w, h] = slice_size(region, pixel);
        image8 img(w, h, 1, 0);
        slice_into(img, z, region.lo, pixel, so);
        return img;
    }

    /// Fills img (already sized) with the slice whose pixel (0,0) has its low corner at `origin`.
    void slice_into(image8& img, double z, const vec2& origin, double pixel, slice_options so = {}) const {
        require_finite(z, "foam slice z");
        require_positive(pixel, "foam slice pixel size");
        if (!all_finite(origin)) throw invalid_input("foam slice: region corner is not finite");
        if (so.supersample < 1 || so.supersample > 16) throw invalid_input("foam slice: supersample must be in [1, 16]");
        if (so.tile < 8 || so.tile > 1024) throw invalid_input("foam slice: tile must be in [8, 1024]");
        if (img.channels != 1) throw invalid_input("foam slice: image must have one channel");
        const int T = so.tile;
        const int tx = (img.width + T - 1) / T, ty = (img.height + T - 1) / T;
        detail::seed_cache cache;
        detail::fill_seed_cache(cache, gen_, opt_.max_radius, z, origin, img.width, img.height, pixel, T);
        constexpr bool constant_tau = std::is_same_v<Radius, constant_field>;
        parallel_for(0, static_cast<std::size_t>(tx) * static_cast<std::size_t>(ty), [&](std::size_t t) {
            thread_local detail::foam_workspace ws;
            ws.cache = cache.start.empty() ? nullptr : &cache;
            struct reset {
                detail::foam_workspace& w;
                ~reset() { w.cache = nullptr; }
            } guard{ws};
            const int i0 = static_cast<int>(t % static_cast<std::size_t>(tx)) * T;
            const int j0 = static_cast<int>(t / static_cast<std::size_t>(tx)) * T;
            detail::render_tile<constant_tau>(*this, img, z, origin, pixel, i0, j0, std::min(T, img.width - i0),
                                              std::min(T, img.height - j0), so.supersample, ws);
        });
    }

    /// Image size of slice(region, pixel); throws invalid_input for bad or over-large (> 1e9 px) regions.
    [[nodiscard]] static std::pair<int, int> slice_size(const box2& region, double pixel) {
        require_positive(pixel, "foam slice pixel size");
        if (!all_finite(region.lo) || !all_finite(region.hi) || region.empty())
            throw invalid_input("foam slice: region must be a finite, non-empty rectangle");
        const double w = std::ceil((region.hi.x - region.lo.x) / pixel - 1e-9);
        const double h = std::ceil((region.hi.y - region.lo.y) / pixel - 1e-9);
        if (!(w * h <= 1e9) || w > 1e6 || h > 1e6)
            throw invalid_input("foam slice: region of " + std::to_string(w) + " x " + std::to_string(h) +
                                " pixels is too large (limit 1e9 pixels, 1e6 per side)");
        return {std::max(1, static_cast<int>(w)), std::max(1, static_cast<int>(h))};
    }

    /// Calls f(a, b) for every Voronoi edge piece inside box b (clipped to b) until f returns false.
    /// The box must be finite with circumradius <= 64 coarse cells. ws: per-thread scratch space.
    template <class F>
    void for_each_edge(const box3& b, detail::foam_workspace& ws, F&& f) const {
        detail::for_each_voronoi_edge(b, gen_, opt_.max_radius, id_, ws, std::forward<F>(f));
    }

private:
    static std::uint64_t next_id() {
        static std::atomic<std::uint64_t> counter{0};
        return ++counter;
    }

    Radius tau_;
    foam_options opt_;
    seeds_type gen_;
    std::uint64_t id_ = next_id();  // identifies this foam's seeds in per-thread caches (copies share it)
};

}  // namespace fabsynth::foam
