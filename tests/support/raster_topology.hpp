#pragma once
// Independent topology oracle for planar polygon output (tests only).
//
// Rasterizes polygons with holes by an even-odd scanline fill at pixel centres (no Clipper, no
// library polygon code) and counts
//   - components: connected components of solid pixels, 8-connectivity;
//   - holes: connected components of empty pixels, 4-connectivity, that do not touch the image
//     border (the outside).
// 8/4 is the consistent digital-topology pair: a diagonal contact joins solid pieces and does not
// open a hole. Keep the pixel size well below the thinnest solid bar and the narrowest gap in the
// shapes under test, otherwise the counts are meaningless.
//
// Wrap-around in x (closed band patterns): the columns span exactly [x0, x1] (n columns of width
// (x1 - x0) / n), column n-1 is adjacent to column 0, so a shape cut at x0 and x1 is glued. Only the
// top and bottom rows are then "border"; the caller's y-range is padded automatically by 2 pixels.
// Without wrap-around all four sides are padded by 2 pixels so the outside is one connected region.
//
// Usage:
//   auto t = fabsynth::test::raster_topology(polys, {0, -5}, {100, 5}, 0.05, /*wrap_x=*/true);
//   REQUIRE(t.components == 1); REQUIRE(t.holes == 3);
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth::test {

struct raster_topology_result {
    std::size_t components = 0;  // solid, 8-connected
    std::size_t holes = 0;       // empty, 4-connected, not touching the border
    std::size_t width = 0, height = 0;
    std::vector<std::uint8_t> solid;  // row-major, row 0 at the lowest y; 1 = solid
    double x0 = 0, y0 = 0, pixel_w = 0, pixel_h = 0;
    [[nodiscard]] bool at(std::size_t col, std::size_t row) const { return solid[row * width + col] != 0; }
};

namespace detail_raster {
// Even-odd crossings of the horizontal line y with every ring edge (half-open in y so a vertex
// exactly on the line is counted once).
inline void crossings(const ring2& r, double y, std::vector<double>& xs) {
    const std::size_t n = r.size();
    for (std::size_t i = 0; i < n; ++i) {
        const vec2 a = r[i], b = r[(i + 1) % n];
        if ((a.y <= y) == (b.y <= y)) continue;
        xs.push_back(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
    }
}

// Union-find with path halving.
struct dsu {
    std::vector<std::size_t> p;
    explicit dsu(std::size_t n) : p(n) {
        for (std::size_t i = 0; i < n; ++i) p[i] = i;
    }
    std::size_t find(std::size_t x) {
        while (p[x] != x) x = p[x] = p[p[x]];
        return x;
    }
    void unite(std::size_t a, std::size_t b) { p[find(a)] = find(b); }
};
}  // namespace detail_raster

// lo/hi: the region of interest (must contain all shapes, except that with wrap_x the shapes must
// lie within [lo.x, hi.x] in x). pixel: target pixel size (columns are adjusted so that they span
// [lo.x, hi.x] exactly when wrapping).
inline raster_topology_result raster_topology(const std::vector<polygon_with_holes>& polys, vec2 lo, vec2 hi,
                                              double pixel, bool wrap_x = false) {
    if (!(pixel > 0.0) || !(hi.x > lo.x) || !(hi.y > lo.y)) throw std::invalid_argument("raster_topology: bad region");
    raster_topology_result res;
    const double pad = 2.0 * pixel;
    double x0 = lo.x, x1 = hi.x;
    if (!wrap_x) x0 -= pad, x1 += pad;
    const double y0 = lo.y - pad, y1 = hi.y + pad;
    const std::size_t w = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil((x1 - x0) / pixel)));
    const std::size_t h = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil((y1 - y0) / pixel)));
    if (w * h > std::size_t{200'000'000}) throw std::invalid_argument("raster_topology: image too large");
    const double pw = (x1 - x0) / static_cast<double>(w), ph = (y1 - y0) / static_cast<double>(h);
    res.width = w, res.height = h, res.x0 = x0, res.y0 = y0, res.pixel_w = pw, res.pixel_h = ph;
    res.solid.assign(w * h, 0);

    std::vector<double> xs;
    for (std::size_t row = 0; row < h; ++row) {
        const double y = y0 + (static_cast<double>(row) + 0.5) * ph;
        xs.clear();
        for (const polygon_with_holes& p : polys) {
            detail_raster::crossings(p.outer, y, xs);
            for (const ring2& hole : p.holes) detail_raster::crossings(hole, y, xs);
        }
        std::sort(xs.begin(), xs.end());
        for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
            // pixel centres c with xs[k] <= c < xs[k+1]
            const double a = (xs[k] - x0) / pw - 0.5, b = (xs[k + 1] - x0) / pw - 0.5;
            const long c0 = std::max<long>(0, static_cast<long>(std::ceil(a)));
            long c1 = static_cast<long>(std::ceil(b)) - 1;
            c1 = std::min<long>(c1, static_cast<long>(w) - 1);
            for (long c = c0; c <= c1; ++c) res.solid[row * w + static_cast<std::size_t>(c)] = 1;
        }
    }

    const auto idx = [w](std::size_t c, std::size_t r) { return r * w + c; };
    detail_raster::dsu d(w * h + 1);
    const std::size_t outside = w * h;  // virtual node for the border
    for (std::size_t r = 0; r < h; ++r)
        for (std::size_t c = 0; c < w; ++c) {
            const bool s = res.solid[idx(c, r)] != 0;
            const bool has_right = wrap_x ? w > 1 : c + 1 < w;
            const std::size_t cr = (c + 1) % w;
            if (s) {
                // 8-neighbours ahead: right, up, up-right, up-left
                if (has_right && res.solid[idx(cr, r)]) d.unite(idx(c, r), idx(cr, r));
                if (r + 1 < h) {
                    if (res.solid[idx(c, r + 1)]) d.unite(idx(c, r), idx(c, r + 1));
                    if (has_right && res.solid[idx(cr, r + 1)]) d.unite(idx(c, r), idx(cr, r + 1));
                    const bool has_left = wrap_x ? w > 1 : c > 0;
                    const std::size_t cl = (c + w - 1) % w;
                    if (has_left && res.solid[idx(cl, r + 1)]) d.unite(idx(c, r), idx(cl, r + 1));
                }
            } else {
                if (has_right && !res.solid[idx(cr, r)]) d.unite(idx(c, r), idx(cr, r));
                if (r + 1 < h && !res.solid[idx(c, r + 1)]) d.unite(idx(c, r), idx(c, r + 1));
                const bool border = r == 0 || r + 1 == h || (!wrap_x && (c == 0 || c + 1 == w));
                if (border) d.unite(idx(c, r), outside);
            }
        }
    std::vector<std::uint8_t> seen(w * h + 1, 0);
    const std::size_t outside_root = d.find(outside);
    for (std::size_t i = 0; i < w * h; ++i) {
        const std::size_t root = d.find(i);
        if (seen[root]) continue;
        seen[root] = 1;
        if (res.solid[i]) ++res.components;
        else if (root != outside_root) ++res.holes;
    }
    return res;
}

}  // namespace fabsynth::test
