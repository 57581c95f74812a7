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
///  - detail/canonical_piece.hpp: an edge piece whose distance to a point is computed from its
///    seeds, so the pieces of two different boxes give the same bits;
///  - detail/point_cache.hpp: point queries answered from the binned edge pieces of their coarse
///    cell grown by the maximum radius (a "block"), kept in a per-thread cache;
///  - detail/near_seeds.hpp: contains() away from a held block, decided from the seeds near the
///    point (a certified bound and the few local edges), from per-thread caches of cell seeds;
///  - detail/slicer.hpp: the tiled parallel slicer (a seed cache per slab of slices, edges once
///    per tile column and slab, row intervals per edge and run filling for a constant radius),
///    O(slab) memory.
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
///   f.for_each_slice(heights, {{0, 0}, {50, 50}}, 0.05, [](std::size_t k, fabsynth::image8& img) { ... });
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
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
#include "fabsynth/foam/detail/near_seeds.hpp"
#include "fabsynth/foam/detail/point_cache.hpp"
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
    /// Bytes of Voronoi edge blocks each thread keeps for point queries (contains, distance_to_edges;
    /// detail/point_cache.hpp); a thread holds at most this plus one block. 0 keeps only the block
    /// of the latest query. contains() also keeps, per thread and on top of it, the seeds of the
    /// coarse cells it visited (detail/near_seeds.hpp): extended cells within 1/8 of this and raw
    /// cells within another 1/8 (plus one cell each). Answers do not depend on it.
    std::size_t point_cache_bytes = std::size_t(128) << 20;
};

/// What the calling thread's point-query cache holds (detail/point_cache.hpp): bytes, blocks, and
/// the largest block's bytes (the cache stays within its budget plus one block).
struct point_cache_stats {
    std::size_t bytes = 0, blocks = 0, largest_block_bytes = 0;
};

/// Options of slice().
struct slice_options {
    int supersample = 1;  ///< s: s x s samples per pixel; pixel value = round(255 * covered fraction)
    int tile = 128;       ///< tile side in pixels (work unit of parallel_for); any value gives the same image
    std::size_t slab_bytes = std::size_t(256) << 20;  ///< for_each_slice: images held at once (at least one)
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
    /// r <= max_radius() is answered from q's cached block when there is one; a larger r builds
    /// the edges of the cube q +- r for this call.
    [[nodiscard]] double distance_to_edges(const vec3& q, double r) const {
        if (!(r > 0 && r <= opt_.cell)) throw invalid_input("foam distance_to_edges: r must be in (0, cell]");
        if (r <= opt_.max_radius)
            if (const detail::edge_block* b = block_for(q)) {
                const double d2 = b->nearest2(q, r);
                return std::isinf(d2) ? d2 : std::sqrt(d2);
            }
        return nearest_near(q, r);
    }

    /// F(q): true iff the distance from q to the Voronoi edges is <= tau(q). Repeated calls near
    /// each other reuse the edge pieces of their block (detail/point_cache.hpp), per thread.
    /// A point whose block is not held is first decided from its nearest seeds alone
    /// (detail/near_seeds.hpp: a certified bound on the distance to every edge, and the few edges
    /// of those seeds), from a per-thread cache of coarse-cell seeds; only points within ~1e-9 mm
    /// of a beam surface (and degenerate seed sets) pay the exact query. A block is built for
    /// coherent access only (missed 64 times within a short run of misses): at random, the seeds
    /// answer about as fast as a held block, from ~1/20 of its memory.
    [[nodiscard]] bool contains(const vec3& q) const {
        const double t = radius(q);
        const i64vec3 k = coarse_cell_of(q, opt_.cell);
        detail::edge_block_cache& cache = thread_cache();
        cache.set_budget(opt_.point_cache_bytes);
        if (const detail::edge_block* b = cache.find(id_, k)) return b->any_within(q, t);
        // the seeds answer first, the miss tally after them (its line loads meanwhile): a block
        // built now gives the same bits, one near-seed test wasted per block
        cache.prefetch_tally(id_, k);
        const detail::near_answer near = detail::near_seed_test(q, k, t, gen_, id_, opt_.max_radius, seed_cache_budget(), seed_cache_budget(), near_cache());
        const std::size_t typical = cache.size() ? cache.bytes() / cache.size() : 0;
        if (cache.worth_building(id_, k, opt_.point_cache_bytes, typical, misses_before_build, scattered_misses_before_build)) return build_block(k).any_within(q, t);
        switch (near) {
        case detail::near_answer::solid: return true;
        case detail::near_answer::empty: return false;
        case detail::near_answer::undecided: break;
        }
        return solid_near(q, t);
    }

    /// contains() without the cache: the edge pieces of the cube q +- tau(q) alone, built for this
    /// call (the same bits, detail/canonical_piece.hpp; for tests, and for callers that must not
    /// keep memory between calls).
    [[nodiscard]] bool contains_uncached(const vec3& q) const {
        const double t = radius(q);
        return solid_near(q, t);
    }

    /// distance_to_edges() without the cache (the same bits).
    [[nodiscard]] double distance_to_edges_uncached(const vec3& q, double r) const {
        if (!(r > 0 && r <= opt_.cell)) throw invalid_input("foam distance_to_edges_uncached: r must be in (0, cell]");
        return nearest_near(q, r);
    }

    /// The calling thread's point-query cache (shared by the foams of this type).
    [[nodiscard]] static point_cache_stats point_cache() {
        const detail::edge_block_cache& c = thread_cache();
        return {c.bytes(), c.size(), c.largest_block_bytes()};
    }

    /// contains() for many points: out[i] = contains(points[i]) (1 or 0). The points are visited
    /// block by block (sorted by coarse cell), the blocks spread over the threads, so scattered
    /// points recover the cache's coherence; results do not depend on the thread count. Throws
    /// invalid_input for spans of different sizes, and as contains().
    void contains(std::span<const vec3> points, std::span<std::uint8_t> out) const {
        if (points.size() != out.size())
            throw invalid_input("foam contains: " + std::to_string(points.size()) + " points but " + std::to_string(out.size()) + " results");
        std::vector<std::pair<i64vec3, std::uint32_t>> order(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) order[i] = {coarse_cell_of(points[i], opt_.cell), static_cast<std::uint32_t>(i)};
        std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
            if (a.first.z != b.first.z) return a.first.z < b.first.z;
            if (a.first.y != b.first.y) return a.first.y < b.first.y;
            if (a.first.x != b.first.x) return a.first.x < b.first.x;
            return a.second < b.second;
        });
        std::vector<std::size_t> runs;  // starts of equal-cell runs, and the end
        for (std::size_t i = 0; i < order.size(); ++i)
            if (i == 0 || order[i].first != order[i - 1].first) runs.push_back(i);
        runs.push_back(order.size());
        parallel_for(0, runs.size() - 1, [&](std::size_t r) {
            for (std::size_t i = runs[r]; i < runs[r + 1]; ++i) {
                const std::uint32_t p = order[i].second;
                out[p] = contains(points[p]) ? 1 : 0;
            }
        });
    }

    /// Supersampled coverage in [0,1] (grayscale exposure, paper §3.2): the fraction of the s^3
    /// cell-centred samples of the cube of side `voxel` (mm) centred at q that are solid
    /// (each sample decided as contains() decides it).
    [[nodiscard]] double coverage(const vec3& q, double voxel, int s) const {
        require_positive(voxel, "foam coverage voxel size");
        if (s < 1 || s > 64) throw invalid_input("foam coverage: supersampling must be in [1, 64]");
        const double half = 0.5 * voxel;
        // one gather for all samples: the pieces of the voxel grown by the maximum radius hold the
        // ball of every sample's radius, so each sample gets contains()'s bits (canonical_piece.hpp)
        thread_local detail::foam_workspace ws;
        thread_local std::vector<detail::canonical_piece> near;
        near.clear();
        detail::for_each_voronoi_piece(box3(q - vec3(half + opt_.max_radius), q + vec3(half + opt_.max_radius)), gen_, opt_.max_radius, id_, ws,
                                       [&](const detail::canonical_piece& p, const vec3&, const vec3&) {
                                           near.push_back(p);
                                           return true;
                                       });
        int count = 0;
        for (int k = 0; k < s; ++k)
            for (int j = 0; j < s; ++j)
                for (int i = 0; i < s; ++i) {
                    const vec3 p = q - vec3(half) + voxel * (vec3(i, j, k) + 0.5) / double(s);
                    const double t = radius(p), t2 = t * t;
                    count += std::any_of(near.begin(), near.end(), [&](const detail::canonical_piece& e) { return detail::distance2(e, p) <= t2; });
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
        render_slab(std::span<const double>(&z, 1), origin, pixel, so, std::span<image8>(&img, 1));
    }

    /// A stack of slices at the increasing heights zs (mm), each the image slice(zs[k], region,
    /// pixel, so) would give, handed to emit(k, img) in order of k (img may be moved from).
    /// The stack is rendered a slab at a time: the slices within one coarse cell's height, at most
    /// so.slab_bytes of images; each tile builds the Voronoi edges of its column through the slab
    /// once and renders all the slab's slices from them. Memory: the slab's images and seeds.
    /// Throws invalid_input for no heights, heights not finite or not increasing, and as slice().
    template <class Emit>
    void for_each_slice(std::span<const double> zs, const box2& region, double pixel, Emit&& emit, slice_options so = {}) const {
        const auto [w, h] = slice_size(region, pixel);
        if (zs.empty()) throw invalid_input("foam slices: no heights given");
        for (std::size_t k = 0; k < zs.size(); ++k) {
            require_finite(zs[k], "foam slice z");
            if (k > 0 && !(zs[k] > zs[k - 1])) throw invalid_input("foam slices: heights must increase (z[" + std::to_string(k) + "] = " + std::to_string(zs[k]) + ")");
        }
        const std::size_t per_image = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
        const std::size_t most = std::max<std::size_t>(1, so.slab_bytes / per_image);
        std::vector<image8> slab;
        for (std::size_t s = 0; s < zs.size();) {
            std::size_t e = s + 1;
            while (e < zs.size() && e - s < most && zs[e] - zs[s] <= opt_.cell) ++e;
            slab.resize(e - s);  // the images are kept from slab to slab unless emit moved them away
            for (image8& img : slab)
                if (img.width != w || img.height != h || img.channels != 1 || img.data.size() != per_image) img = image8(w, h, 1, 0);
            render_slab(zs.subspan(s, e - s), region.lo, pixel, so, slab);
            for (std::size_t k = s; k < e; ++k) emit(k, slab[k - s]);
            s = e;
        }
    }

    /// count slices at z0, z0 + dz, ... (dz > 0, count in [1, 1e6]) over region, as for_each_slice.
    [[nodiscard]] std::vector<image8> slices(double z0, double dz, int count, const box2& region, double pixel, slice_options so = {}) const {
        require_finite(z0, "foam slices z0");
        require_positive(dz, "foam slices dz");
        if (count < 1 || count > 1000000) throw invalid_input("foam slices: count must be in [1, 1e6], got " + std::to_string(count));
        std::vector<double> zs(static_cast<std::size_t>(count));
        for (int k = 0; k < count; ++k) zs[static_cast<std::size_t>(k)] = z0 + k * dz;
        std::vector<image8> out(zs.size());
        for_each_slice(zs, region, pixel, [&](std::size_t k, image8& img) { out[k] = std::move(img); }, so);
        return out;
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
    // Renders the slices at heights zs (increasing, within a few cells) into imgs (sized alike):
    // per tile, the edges of its column through zs once, then every slice from them.
    void render_slab(std::span<const double> zs, const vec2& origin, double pixel, const slice_options& so, std::span<image8> imgs) const {
        require_positive(pixel, "foam slice pixel size");
        if (!all_finite(origin)) throw invalid_input("foam slice: region corner is not finite");
        if (so.supersample < 1 || so.supersample > 16) throw invalid_input("foam slice: supersample must be in [1, 16]");
        if (so.tile < 8 || so.tile > 1024) throw invalid_input("foam slice: tile must be in [8, 1024]");
        const image8& first = imgs.front();
        for (const image8& img : imgs)
            if (img.channels != 1 || img.width != first.width || img.height != first.height)
                throw invalid_input("foam slice: images must have one channel and one size");
        const int T = so.tile;
        const int tx = (first.width + T - 1) / T, ty = (first.height + T - 1) / T;
        detail::seed_cache cache;
        detail::fill_seed_cache(cache, gen_, opt_.max_radius, zs.front(), zs.back(), origin, first.width, first.height, pixel, T);
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
            const int tw = std::min(T, first.width - i0), th = std::min(T, first.height - j0);
            detail::gather_tile_edges(*this, zs.front(), zs.back(), origin, pixel, i0, j0, tw, th, ws);
            for (std::size_t k = 0; k < zs.size(); ++k)
                detail::render_tile<constant_tau>(*this, imgs[k], zs[k], origin, pixel, i0, j0, tw, th, so.supersample, ws);
        });
    }

    // The block that answers queries at q of radius <= max radius: held, or built when worth it
    // (detail/point_cache.hpp), else null.
    [[nodiscard]] const detail::edge_block* block_for(const vec3& q) const {
        const i64vec3 k = coarse_cell_of(q, opt_.cell);
        detail::edge_block_cache& cache = thread_cache();
        cache.set_budget(opt_.point_cache_bytes);
        if (const detail::edge_block* b = cache.find(id_, k)) return b;
        const std::size_t typical = cache.size() ? cache.bytes() / cache.size() : 0;
        if (!cache.worth_building(id_, k, opt_.point_cache_bytes, typical, misses_before_build, misses_before_build)) return nullptr;
        return &build_block(k);
    }
    // Block k, built now when it is not held.
    const detail::edge_block& build_block(const i64vec3& k) const {
        thread_local detail::foam_workspace ws;
        return thread_cache().get(id_, k, opt_.point_cache_bytes, [&](detail::edge_block& blk) {
            detail::build_edge_block(blk, id_, k, opt_.cell, opt_.max_radius, ws, [&](const box3& bx, detail::foam_workspace& w, auto&& f) {
                detail::for_each_voronoi_piece(bx, gen_, opt_.max_radius, id_, w, f);
            });
        });
    }
    // Some piece of the cube q +- t lies within t of q (stops at the first).
    [[nodiscard]] bool solid_near(const vec3& q, double t) const {
        thread_local detail::foam_workspace ws;
        const double t2 = t * t;
        bool solid = false;
        detail::for_each_voronoi_piece(box3(q - vec3(t), q + vec3(t)), gen_, opt_.max_radius, id_, ws,
                                       [&](const detail::canonical_piece& p, const vec3&, const vec3&) { return !(solid = detail::distance2(p, q) <= t2); });
        return solid;
    }
    // The distance from q to the nearest piece of the cube q +- r if it is <= r, else +infinity.
    [[nodiscard]] double nearest_near(const vec3& q, double r) const {
        thread_local detail::foam_workspace ws;
        double best = r * r;
        bool found = false;
        detail::for_each_voronoi_piece(box3(q - vec3(r), q + vec3(r)), gen_, opt_.max_radius, id_, ws,
                                       [&](const detail::canonical_piece& p, const vec3&, const vec3&) {
                                           const double d2 = detail::distance2(p, q);
                                           if (d2 <= best) best = d2, found = true;
                                           return true;
                                       });
        return found ? std::sqrt(best) : std::numeric_limits<double>::infinity();
    }
    // A block costs about 200 of its misses to build (each answered from its own small cube);
    // building after 64 keeps a coherent scan cheap and bounds the waste of scattered points.
    static constexpr int misses_before_build = 64;
    // contains() answers a scattered miss from its nearest seeds (~0.5 us, detail/near_seeds.hpp),
    // about as fast as a held block at random (the block's memory is ~20x the seeds'), so a block
    // is built for runs of misses only (this count is never reached within the run window).
    static constexpr int scattered_misses_before_build = std::numeric_limits<int>::max();
    static detail::edge_block_cache& thread_cache() {
        thread_local detail::edge_block_cache cache;
        return cache;
    }
    // The thread's seeds for contains() (detail/near_seeds.hpp): extended cells within 1/8 of the
    // point-cache budget, raw cells within another 1/8 (an extended-cell build reads 64 raw cells,
    // and a thrashing extended-cell cache answers from raw cells: with a seed working set twice the
    // cache, raw cells within 1/32 or 1/16 thrashed as well; benchmarks/README.md).
    static detail::near_seeds& near_cache() {
        thread_local detail::near_seeds cache;
        return cache;
    }
    [[nodiscard]] std::size_t seed_cache_budget() const noexcept { return opt_.point_cache_bytes / 8; }

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
