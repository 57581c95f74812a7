// SPDX-License-Identifier: MIT
#pragma once
/// @file raster.hpp  Scanline rasterization of planar regions bounded by directed edges (closed
/// rings, polygons with holes, or the segments of a mesh cross-section), with the even-odd or the
/// nonzero fill rule and an optional wrap of the columns (for bands glued at a seam).
///
/// Pixel convention: pixel (i, j) of a `raster_grid` has its centre at
/// origin + ((i + 0.5) pixel, (j + 0.5) pixel); a pixel is inside iff its centre is. An edge
/// crosses row j iff exactly one endpoint has y <= y_j (a vertex on the scanline counts as above
/// it, so a vertex shared by two edges is crossed once); a row's crossings are sorted by x and
/// the centres x with x0 <= x < x1 of every inside interval [x0, x1) are reported as one run of
/// columns [i0, i1). Runs come in increasing x and never overlap within a row, unless wrapping
/// folds a run onto another.
///
/// Usage:
///   fabsynth::polygon_rasterizer r;
///   for (const auto& p : polygons) r.add_polygon(p);                 // rings of vec2, mm
///   r.for_each_run({origin, 0.1, 200, 100}, [&](int j, int i0, int i1) { ... });
///   // or, one row at a time from a parallel loop:
///   std::vector<fabsynth::polygon_rasterizer::crossing> scratch;
///   r.row_runs(grid, j, scratch, [&](int i0, int i1) { ... });
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth {

/// A regular raster: `width` x `height` square pixels of side `pixel` (mm), lower-left corner
/// `origin` (mm).
struct raster_grid {
    vec2 origin{0};
    double pixel = 1.0;
    int width = 0;
    int height = 0;

    /// y of the centres of row j (mm).
    [[nodiscard]] double row_y(int j) const noexcept { return origin.y + (j + 0.5) * pixel; }
};

/// Options of the rasterizer.
struct raster_options {
    fill_rule rule = fill_rule::evenodd;  ///< geometry/polygon.hpp
    /// false: runs are clipped to [0, width). true: columns are periodic with period `width`,
    /// so a run reaching past either side is folded back (a run covering >= width columns is the
    /// whole row).
    bool wrap_x = false;
};

/// Scanline rasterizer over a set of directed edges (see the file comment).
class polygon_rasterizer {
public:
    /// A directed edge a -> b (mm); the direction only matters for the nonzero rule.
    struct edge {
        vec2 a, b;
    };
    /// Where an edge crosses a scanline, with the edge's winding contribution (+1 upward).
    struct crossing {
        double x;
        int winding;
        friend bool operator<(const crossing& l, const crossing& r) noexcept { return l.x < r.x; }
    };

    polygon_rasterizer() = default;
    explicit polygon_rasterizer(raster_options opt) : opt_(opt) {}

    /// Adds segment a -> b.
    void add_edge(vec2 a, vec2 b) {
        edges_.push_back({a, b});
        lo_ = std::min(lo_, std::min(a.y, b.y));
        hi_ = std::max(hi_, std::max(a.y, b.y));
    }
    /// Adds a closed ring (last vertex joined to the first).
    void add_ring(const ring2& r) {
        for (std::size_t i = 0; i < r.size(); ++i) add_edge(r[i], r[(i + 1) % r.size()]);
    }
    /// Adds the outer ring and the holes of a polygon.
    void add_polygon(const polygon_with_holes& p) {
        add_ring(p.outer);
        for (const ring2& h : p.holes) add_ring(h);
    }

    [[nodiscard]] const std::vector<edge>& edges() const noexcept { return edges_; }
    [[nodiscard]] const raster_options& options() const noexcept { return opt_; }

    /// Sorted crossings of the scanline at height y (into `out`, which is cleared first).
    void crossings(double y, std::vector<crossing>& out) const {
        out.clear();
        if (!(y >= lo_ && y < hi_)) return;
        for (const edge& e : edges_)
            if ((e.a.y <= y) != (e.b.y <= y))
                out.push_back({e.a.x + (y - e.a.y) * (e.b.x - e.a.x) / (e.b.y - e.a.y), e.b.y > e.a.y ? 1 : -1});
        std::sort(out.begin(), out.end());
    }

    /// Calls run(x0, x1) for every inside interval [x0, x1) of the scanline at height y (mm),
    /// in increasing x; `scratch` holds the crossings.
    template <class Run>
    void intervals(double y, std::vector<crossing>& scratch, Run&& run) const {
        crossings(y, scratch);
        if (opt_.rule == fill_rule::evenodd) {
            for (std::size_t k = 0; k + 1 < scratch.size(); k += 2) run(scratch[k].x, scratch[k + 1].x);
            return;
        }
        int w = 0;
        double start = 0;
        for (const crossing& c : scratch) {
            const int before = w;
            w += c.winding;
            if (before == 0 && w != 0) start = c.x;
            else if (before != 0 && w == 0) run(start, c.x);
        }
    }

    /// Calls run(i0, i1) for every run of inside columns [i0, i1) of row j of grid g.
    template <class Run>
    void row_runs(const raster_grid& g, int j, std::vector<crossing>& scratch, Run&& run) const {
        intervals(g.row_y(j), scratch, [&](double x0, double x1) {
            // column i is inside iff x0 <= origin.x + (i + 0.5) pixel < x1
            const double f0 = std::ceil((x0 - g.origin.x) / g.pixel - 0.5), f1 = std::ceil((x1 - g.origin.x) / g.pixel - 0.5);
            if (!(f1 > f0)) return;
            if (!opt_.wrap_x) {
                const int i0 = static_cast<int>(std::max(0.0, f0)), i1 = static_cast<int>(std::min<double>(g.width, f1));
                if (i1 > i0) run(i0, i1);
                return;
            }
            if (g.width <= 0) return;
            if (f1 - f0 >= g.width) {
                run(0, g.width);
                return;
            }
            const double wd = g.width;
            const int i0 = static_cast<int>(f0 - wd * std::floor(f0 / wd));  // f0 mod width, in [0, width)
            const int len = static_cast<int>(f1 - f0);
            if (i0 + len <= g.width) {
                run(i0, i0 + len);
            } else {
                run(i0, g.width);
                run(0, i0 + len - g.width);
            }
        });
    }

    /// Calls run(j, i0, i1) for every run of every row, rows in increasing j (serial).
    template <class Run>
    void for_each_run(const raster_grid& g, Run&& run) const {
        std::vector<crossing> scratch;
        for (int j = 0; j < g.height; ++j) row_runs(g, j, scratch, [&](int i0, int i1) { run(j, i0, i1); });
    }

private:
    raster_options opt_{};
    std::vector<edge> edges_;
    double lo_ = 1e300, hi_ = -1e300;  // y range of the edges: rows outside it have no crossings
};

}  // namespace fabsynth
