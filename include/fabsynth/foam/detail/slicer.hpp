// SPDX-License-Identifier: MIT
#pragma once
/// @file slicer.hpp  (internal, behind evaluator.hpp) The tiled slicer of voronoi_foam::slice.
///
/// The seeds of every coarse cell a tile can need are generated once per slice, in parallel
/// (fill_seed_cache); the slice is cut into tiles processed with parallel_for (bit-identical for
/// any thread count and tile size, since every pixel is decided exactly). Each tile builds its
/// edge pieces once (the Voronoi edges near a tile are the same for all its pixels) and, per edge
/// and pixel row, computes the row interval the edge's tube (capsule) can cover, padded by 1e-7 mm.
/// With a constant radius (compile-time: Radius = constant_field) the tube is convex, so its solid
/// pixels on a row are one run: the run's ends are found by the exact point-segment test, scanning
/// inwards from the padded interval, and the pixels between are filled. A filled pixel lies
/// between two pixels within tau of the segment, hence (the distance to a segment is convex along
/// a line) within tau itself, up to the rounding of the test (~1e-13 mm): the image equals the
/// per-pixel exact test outside that band. A varying radius tests every pixel of the interval.
/// A stack of slices is rendered a slab at a time (voronoi_foam::for_each_slice): each tile builds
/// the edges of its column through the slab once and renders every slice of the slab from them;
/// every pixel is decided exactly whatever box the edges came from (up to the ~1e-13 mm rounding
/// of the test, as for any tile size), so the images equal single slices. Memory is O(the slab's images + the seeds of the slab grown by
/// ~2 (sqrt(3) L + 2 tau)).
/// Tile size and compiler-flag measurements: benchmarks/README.md (foam).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/detail/workspace.hpp"
#include "fabsynth/foam/seeds.hpp"

namespace fabsynth::foam::detail {

/// Generates, in parallel, the seeds of every coarse cell a tile column of the slices at heights
/// z_lo..z_hi can gather: those within R of the slab (origin, width x height pixels, z_lo..z_hi),
/// where R bounds the margin of gather_certified_seeds for a tile column's box (tile +- max
/// radius): usually m <= 2 h + max(1.5 rho^(-1/3), sqrt(3) L) <= 2 h + sqrt(3) L (rho >= 1/L^3;
/// h = sub-box circumradius). Cells outside the cache still work (slower). Leaves the cache empty
/// when it would span more than 4e6 coarse cells.
template <class Seeds>
void fill_seed_cache(seed_cache& cache, const Seeds& gen, double max_radius, double z_lo, double z_hi, const vec2& origin, int width,
                     int height, double pixel, int tile) {
    const double cell = gen.options().cell;
    const double tmax = max_radius;
    const double step_xy = std::max(2 * tmax, (tile * pixel + 2 * tmax) / 16);
    const double step_z = std::max(2 * tmax, (z_hi - z_lo + 2 * tmax) / 16);
    const double hs_max = 0.5 * std::sqrt(2 * step_xy * step_xy + step_z * step_z);
    const double R = tmax + 2 * hs_max + std::sqrt(3.0) * cell + 1e-6 * (1 + cell);
    const double cells = (width * pixel + 2 * R) * (height * pixel + 2 * R) * (z_hi - z_lo + 2 * R) / (cell * cell * cell);
    if (!(cells < 4e6)) return;
    cache.lo = coarse_cell_of(vec3(origin, z_lo) - vec3(R), cell);
    cache.dims = coarse_cell_of(vec3(origin + vec2(width, height) * pixel, z_hi) + vec3(R), cell) - cache.lo + i64vec3(1);
    const std::size_t n = static_cast<std::size_t>(cache.dims.x * cache.dims.y * cache.dims.z);
    std::vector<std::vector<vec3>> per(n);
    parallel_for(0, n, [&](std::size_t i) {
        const std::int64_t ii = static_cast<std::int64_t>(i);
        const i64vec3 k = cache.lo + i64vec3(ii % cache.dims.x, (ii / cache.dims.x) % cache.dims.y,
                                             ii / (cache.dims.x * cache.dims.y));
        gen.cell_seeds(k, per[i]);
    }, {.grain = 16});
    cache.start.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) cache.start[i + 1] = cache.start[i] + static_cast<std::uint32_t>(per[i].size());
    cache.seeds.reserve(cache.start[n]);
    for (auto& v : per) cache.seeds.insert(cache.seeds.end(), v.begin(), v.end());
}

/// Sample raster of one tile: W x H samples (pixels x supersampling) of pitch sp, sample (0, 0)
/// centred at (x0, y0, z).
struct tile_raster {
    int i0, j0, tw, th, ss;  ///< tile origin and size in pixels, supersampling
    int W, H;                ///< samples per row and column
    double sp, x0, y0, z;    ///< sample pitch and first sample centre, mm
    double tmax;             ///< max radius, mm
    [[nodiscard]] std::size_t index(int x, int y) const noexcept {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x);
    }
};

[[nodiscard]] inline tile_raster make_tile_raster(const vec2& origin, double pixel, double z, int i0, int j0, int tw,
                                                  int th, int ss, double tmax) {
    tile_raster r{i0, j0, tw, th, ss, tw * ss, th * ss, pixel / ss, 0, 0, z, tmax};
    r.x0 = origin.x + i0 * pixel + 0.5 * r.sp, r.y0 = origin.y + j0 * pixel + 0.5 * r.sp;
    return r;
}

/// Samples an edge's tube can touch: rows ya..yb, columns xa..xb (empty if xa > xb or ya > yb).
struct sample_rect {
    int xa, xb, ya, yb;
    [[nodiscard]] bool empty() const noexcept { return xa > xb || ya > yb; }
};

/// The bounding rectangle of the footprint of the part of edge e within tmax of the plane; empty
/// when no part is.
[[nodiscard]] inline sample_rect edge_footprint(const edge_segment& e, const tile_raster& r) {
    const double z = r.z, tmax = r.tmax;
    double t0 = 0, t1 = 1;
    const double dz = e.b.z - e.a.z;
    if (dz != 0) {
        double ta = (z - tmax - e.a.z) / dz, tb = (z + tmax - e.a.z) / dz;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta), t1 = std::min(t1, tb);
        if (t0 > t1) return {0, -1, 0, -1};
    } else if (std::abs(e.a.z - z) > tmax) {
        return {0, -1, 0, -1};
    }
    const vec3 p0 = e.a + t0 * (e.b - e.a), p1 = e.a + t1 * (e.b - e.a);
    return {std::max(0, static_cast<int>(std::floor((std::min(p0.x, p1.x) - tmax - r.x0) / r.sp))),
            std::min(r.W - 1, static_cast<int>(std::ceil((std::max(p0.x, p1.x) + tmax - r.x0) / r.sp))),
            std::max(0, static_cast<int>(std::floor((std::min(p0.y, p1.y) - tmax - r.y0) / r.sp))),
            std::min(r.H - 1, static_cast<int>(std::ceil((std::max(p0.y, p1.y) + tmax - r.y0) / r.sp)))};
}

/// One edge as a tube for the row scans: the segment a + t ab, its unit direction u, and the
/// quantities of the row-interval quadratic.
struct edge_tube {
    vec3 a, ab, u, eperp;
    double inv_len2;  ///< 1 / |ab|^2 (0 for a point)
    double len;       ///< |ab|
    double az;        ///< z - a.z
    double tlim;      ///< radius bounding the tube, mm
    double A;         ///< |eperp|^2, eperp = x-axis minus its component along u
};

[[nodiscard]] inline edge_tube make_edge_tube(const edge_segment& e, double z, double tlim) {
    edge_tube t;
    t.a = e.a;
    t.ab = e.b - e.a;
    const double l2 = glm::dot(t.ab, t.ab);
    t.inv_len2 = l2 > 0 ? 1.0 / l2 : 0.0;
    t.az = z - e.a.z;
    t.len = std::sqrt(l2);
    t.u = t.len > 0 ? t.ab / t.len : vec3(0);
    t.tlim = tlim;
    t.eperp = vec3(1, 0, 0) - t.u.x * t.u;
    t.A = glm::dot(t.eperp, t.eperp);
    return t;
}

/// The columns [xlo, xhi] of sample row y (at offset ay = y - a.y) that the tube can cover: the
/// row line meets the capsule in an interval inside {infinite cylinder} and {slab -tlim <= (p -
/// a).u <= |ab| + tlim}; both are solved for x, padded by 1e-7 mm against rounding, and clamped
/// to the footprint. False when the row misses the tube.
[[nodiscard]] inline bool row_interval(const edge_tube& t, double ay, const sample_rect& fp, const tile_raster& r, int& xlo,
                                       int& xhi) {
    xlo = fp.xa, xhi = fp.xb;
    if (!(t.len > 0)) return true;
    const vec3 w0(0, ay, t.az);
    const double wu = glm::dot(w0, t.u);
    const vec3 w0p = w0 - wu * t.u;
    const double B = glm::dot(w0p, t.eperp), C = glm::dot(w0p, w0p) - t.tlim * t.tlim;
    double lo = -1e300, hi = 1e300;
    if (t.A > 1e-12) {
        const double disc = B * B - t.A * C;
        if (disc < 0) return false;
        const double sq = std::sqrt(disc);
        lo = (-B - sq) / t.A, hi = (-B + sq) / t.A;
    } else if (C > 1e-9) {
        return false;
    }
    if (std::abs(t.u.x) > 1e-12) {
        double s0 = (-t.tlim - wu) / t.u.x, s1 = (t.len + t.tlim - wu) / t.u.x;
        if (s0 > s1) std::swap(s0, s1);
        lo = std::max(lo, s0), hi = std::min(hi, s1);
    }
    lo += t.a.x - 1e-7, hi += t.a.x + 1e-7;
    if (!(lo <= hi)) return false;
    // clamp to the tile before converting to int (avoids out-of-range casts)
    lo = std::max(lo, r.x0 - r.sp), hi = std::min(hi, r.x0 + (r.W + 1) * r.sp);
    if (lo > hi) return false;
    xlo = std::max(fp.xa, static_cast<int>(std::floor((lo - r.x0) / r.sp)));
    xhi = std::min(fp.xb, static_cast<int>(std::ceil((hi - r.x0) / r.sp)));
    return true;
}

/// Squared distance from sample (x, row at offset ay) to the tube's segment: the exact test.
[[nodiscard]] inline double sample_distance2(const edge_tube& t, const tile_raster& r, int x, double ay) {
    const double ax = r.x0 + x * r.sp - t.a.x;
    const double s = std::clamp((ax * t.ab.x + ay * t.ab.y + t.az * t.ab.z) * t.inv_len2, 0.0, 1.0);
    const double dx = ax - s * t.ab.x, dy = ay - s * t.ab.y, dz = t.az - s * t.ab.z;
    return dx * dx + dy * dy + dz * dz;
}

/// Constant radius: marks the run of solid samples of the row in [xlo, xhi]. The tube is convex,
/// so along a row its solid samples form one run: find the first and last solid samples by the
/// exact test and fill between them. A sample between two solid ones is within tau (+ the ~1e-13
/// mm rounding of the test) of the edge by convexity of the distance, so the result equals the
/// per-sample test outside that rounding band (which the tests exclude at 1e-9 mm).
inline void fill_row_run(const edge_tube& t, const tile_raster& r, double ay, int xlo, int xhi, double tau2,
                         std::uint8_t* row) {
    int first = xlo;
    while (first <= xhi && !(sample_distance2(t, r, first, ay) <= tau2)) ++first;
    if (first > xhi) return;
    int last = xhi;
    while (last > first && !(sample_distance2(t, r, last, ay) <= tau2)) --last;
    std::fill(row + first, row + last + 1, std::uint8_t{1});
}

/// Varying radius: marks every sample of the row in [xlo, xhi] within its own tau (tau2_row).
inline void fill_row_samples(const edge_tube& t, const tile_raster& r, double ay, int xlo, int xhi,
                             const double* tau2_row, std::uint8_t* row) {
    for (int x = xlo; x <= xhi; ++x)
        row[x] |= static_cast<std::uint8_t>(sample_distance2(t, r, x, ay) <= tau2_row[x]);
}

/// Marks in ws.hits every sample of the tile within tau of one of ws.edges. ConstantTau: tau2 is
/// the squared radius everywhere; else ws.tau2 holds it per sample.
template <bool ConstantTau>
void mark_tile_hits(const tile_raster& r, double tau2, foam_workspace& ws) {
    ws.hits.assign(static_cast<std::size_t>(r.W) * static_cast<std::size_t>(r.H), 0);
    const double tlim = std::sqrt(tau2 > 0 ? tau2 : r.tmax * r.tmax);
    for (const edge_segment& e : ws.edges) {
        const sample_rect fp = edge_footprint(e, r);
        if (fp.empty()) continue;
        const edge_tube t = make_edge_tube(e, r.z, tlim);
        for (int y = fp.ya; y <= fp.yb; ++y) {
            const double ay = r.y0 + y * r.sp - e.a.y;
            int xlo = 0, xhi = 0;
            if (!row_interval(t, ay, fp, r, xlo, xhi)) continue;
            std::uint8_t* row = ws.hits.data() + r.index(0, y);
            if constexpr (ConstantTau) fill_row_run(t, r, ay, xlo, xhi, tau2, row);
            else fill_row_samples(t, r, ay, xlo, xhi, ws.tau2.data() + r.index(0, y), row);
        }
    }
}

/// Writes the tile's pixels into img from ws.hits: 255 / 0 without supersampling, else
/// round(255 * covered fraction of the ss x ss samples).
inline void resolve_tile(const tile_raster& r, const foam_workspace& ws, image8& img) {
    if (r.ss == 1) {  // no supersampling: one sample per pixel
        for (int j = 0; j < r.th; ++j) {
            const std::uint8_t* src = ws.hits.data() + r.index(0, j);
            std::uint8_t* dst = &img.at(r.i0, r.j0 + j);
            for (int i = 0; i < r.tw; ++i) dst[i] = static_cast<std::uint8_t>(src[i] ? 255 : 0);
        }
        return;
    }
    const int s2 = r.ss * r.ss;
    for (int j = 0; j < r.th; ++j)
        for (int i = 0; i < r.tw; ++i) {
            int cnt = 0;
            for (int v = 0; v < r.ss; ++v)
                for (int u = 0; u < r.ss; ++u) cnt += ws.hits[r.index(i * r.ss + u, j * r.ss + v)];
            img.at(r.i0 + i, r.j0 + j) = static_cast<std::uint8_t>((255 * cnt + s2 / 2) / s2);
        }
}

/// The Voronoi edge pieces near a tile column (pixels i0..i0+tw-1, j0..j0+th-1) through the
/// slices at heights z_lo..z_hi, into ws.edges: once for every sample of every slice there.
template <class Foam>
void gather_tile_edges(const Foam& foam, double z_lo, double z_hi, const vec2& origin, double pixel, int i0, int j0, int tw, int th,
                       foam_workspace& ws) {
    const double tmax = foam.max_radius();
    const box3 b(vec3(origin.x + i0 * pixel, origin.y + j0 * pixel, z_lo) - vec3(tmax),
                 vec3(origin.x + (i0 + tw) * pixel, origin.y + (j0 + th) * pixel, z_hi) + vec3(tmax));
    ws.edges.clear();
    foam.for_each_edge(b, ws, [&](const vec3& a, const vec3& c) {
        ws.edges.push_back({a, c});
        return true;
    });
}

/// Renders one tile (pixels i0..i0+tw-1, j0..j0+th-1) of the slice of `foam` at height z into img
/// from the edges of its column in ws.edges (gather_tile_edges over a z range holding z).
/// ConstantTau: the radius is the same everywhere (Radius = constant_field).
template <bool ConstantTau, class Foam>
void render_tile(const Foam& foam, image8& img, double z, const vec2& origin, double pixel, int i0, int j0, int tw,
                 int th, int ss, foam_workspace& ws) {
    const tile_raster r = make_tile_raster(origin, pixel, z, i0, j0, tw, th, ss, foam.max_radius());
    double tau2 = 0;
    if constexpr (ConstantTau) {
        const double t = foam.radius(vec3(origin, z));
        tau2 = t * t;
    } else {
        ws.tau2.resize(static_cast<std::size_t>(r.W) * static_cast<std::size_t>(r.H));
        for (int y = 0; y < r.H; ++y)
            for (int x = 0; x < r.W; ++x) {
                const double t = foam.radius(vec3(r.x0 + x * r.sp, r.y0 + y * r.sp, z));
                ws.tau2[r.index(x, y)] = t * t;
            }
    }
    mark_tile_hits<ConstantTau>(r, tau2, ws);
    resolve_tile(r, ws, img);
}

}  // namespace fabsynth::foam::detail
