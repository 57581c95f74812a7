// SPDX-License-Identifier: MIT
#pragma once
/// @file surface_decoration.hpp  A band pattern on a surface made printable: embossed onto a shell
/// around the surface, or carved out of it, as one watertight mesh (Zhou, Jiang & Lefebvre 2014
/// §6.3 and Fig. 23, topology-constrained-vector-patterns.md: the embossed vase and the egg stand
/// carved out of a shell).
///
/// Inputs. An open or closed surface mesh, a band curve lying on it (a space_curve, typically
/// surface_curve::band_curve(): u along the curve, v across it in the tangent plane) and the
/// pattern in band coordinates (u, v) in mm, as synthesized along the curve.
///
/// Solid. Every point p near the surface has its closest surface point q, its offset
/// w = +-|p - q| (positive on the side the surface's normals point to: area-weighted vertex
/// normals interpolated at q) and band coordinates of q: u = arc length of q's closest point c on
/// the curve plus (q - c) . t (so ends of open curves are not extended), and v = +-|the rest of
/// q - c| on the side of the band's offset direction. So the pattern is laid on the surface itself,
/// without the tangent-plane band's gap where the surface curves away, and its walls follow the
/// surface normal. With s(u, v) the signed distance to the pattern (< 0 inside):
///   shell   : |w| <= shell / 2 (the surface thickened, centred on it, as thicken_surface does);
///   emboss  : shell union { s <= 0 and 0 <= w <= shell / 2 + height } (relief `height` above the
///             shell's outer side);
///   carve   : shell minus { s <= 0 } (the pattern cut through the shell).
/// The field (min / max of the pieces' signed distances) is sampled on a grid of `cell` over the
/// surface's box and meshed by marching tetrahedra (geometry/marching_cubes.hpp), so the result is
/// watertight and consistently oriented by construction; enclosed voids are filled as in
/// thicken_surface. s(u, v) comes from an exact Euclidean distance transform
/// (geometry/distance_transform.hpp) of the pattern rasterized at `pixel` (nonzero rule, columns
/// wrapped on closed curves), interpolated bilinearly. Why a level set rather than mesh booleans:
/// the union / difference of a relief with a curved shell is robust this way and needs no exact
/// predicates; the price is that edges and corners of the pattern are rounded at the scale of one
/// cell, and the error is the grid's (about one cell).
///
/// Topology. Emboss: one component per shell component (a relief lies on the shell), no added
/// handle. Carve: each component of the pattern punches one hole through the shell (one more
/// handle), each hole of the pattern leaves an island (one more component), and a pattern
/// component winding around a closed curve on a closed band cuts the shell in two.
///
/// Cost: one bounded closest-point query on the surface per grid point (most are far and cheap),
/// one on the curve for points within reach of the surface; the grid size is checked against
/// max_samples before any work.
///
/// Usage:
///   auto s = fabsynth::trace_surface_curve(phi, points, true);
///   fabsynth::triangle_mesh print = fabsynth::decorate_surface(vase, s.band_curve(), pattern,
///       {.mode = fabsynth::decoration_mode::emboss, .shell = 2.0, .height = 1.0, .cell = 0.25});
///
/// Errors: invalid_input naming the input for an empty or invalid mesh, a non-finite or
/// non-positive thickness, height, cell or pixel, an empty pattern or one with a non-finite
/// point; no_solution when the grid or the pattern raster would be too large.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/distance_transform.hpp"
#include "fabsynth/geometry/marching_cubes.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/raster.hpp"
#include "fabsynth/geometry/space_curve.hpp"

namespace fabsynth {

enum class decoration_mode {
    emboss,  ///< the pattern stands `height` above the shell
    carve,   ///< the pattern is cut out of the shell
};

struct surface_decoration_options {
    decoration_mode mode = decoration_mode::emboss;
    double shell = 2.0;         ///< thickness of the shell around the surface, mm (centred on it)
    double height = 1.0;        ///< emboss: relief above the shell's outer side, mm
    double cell = 0.0;          ///< grid spacing, mm; 0 = a quarter of min(shell, height) (emboss) or of shell (carve)
    double pixel = 0.0;         ///< pattern raster pixel, mm; 0 = cell / 4
    double max_samples = 4e8;   ///< refuse grids (and pattern rasters) with more points than this
    bool fill_cavities = true;  ///< drop inner shells of enclosed voids (geometry/mesh_topology.hpp's without_cavities)
};

namespace detail::decoration {

// Signed distance (mm, < 0 inside) to the pattern in band coordinates, from a raster of it.
class band_distance {
public:
    band_distance(const std::vector<polygon_with_holes>& pattern, double length, bool closed, double pixel, double reach, double max_samples) {
        box2 b;
        for (const auto& p : pattern) {
            for (const vec2& x : p.outer) {
                if (!all_finite(x)) throw invalid_input("decorate_surface: a pattern point is not finite");
                b.extend(x);
            }
        }
        if (b.empty()) throw invalid_input("decorate_surface: the pattern is empty");
        closed_ = closed;
        width_ = closed ? std::max(1, static_cast<int>(std::ceil(length / pixel))) : 0;
        px_ = closed ? length / width_ : pixel;
        margin_ = static_cast<int>(std::ceil(reach / px_)) + 2;
        u0_ = closed ? 0.0 : std::min(0.0, b.lo.x) - margin_ * px_;
        const double u1 = closed ? length : std::max(length, b.hi.x) + margin_ * px_;
        v0_ = b.lo.y - margin_ * px_;
        nv_ = static_cast<int>(std::ceil((b.hi.y + margin_ * px_ - v0_) / px_)) + 1;
        if (!closed) width_ = static_cast<int>(std::ceil((u1 - u0_) / px_)) + 1;
        nu_ = closed ? width_ + 2 * margin_ : width_;  // closed: margin columns copied across the seam
        if (!(static_cast<double>(nu_) * nv_ <= max_samples))
            throw no_solution("decorate_surface: a pattern raster of " + std::to_string(nu_) + " x " + std::to_string(nv_) + " pixels exceeds max_samples (a larger pixel)");
        polygon_rasterizer r({fill_rule::nonzero, closed});
        for (polygon_with_holes p : pattern) {
            orient(p);
            r.add_polygon(p);
        }
        std::vector<std::uint8_t> in(static_cast<std::size_t>(width_) * static_cast<std::size_t>(nv_), 0);
        r.for_each_run({{u0_, v0_}, px_, width_, nv_}, [&](int j, int i0, int i1) {
            for (int i = i0; i < i1; ++i) in[static_cast<std::size_t>(j) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(i)] = 1;
        });
        const std::size_t n = static_cast<std::size_t>(nu_) * static_cast<std::size_t>(nv_);
        std::vector<bool> inside(n), outside(n);
        for (int j = 0; j < nv_; ++j)
            for (int i = 0; i < nu_; ++i) {
                const int src = closed ? ((i - margin_) % width_ + width_) % width_ : i;
                const bool v = in[static_cast<std::size_t>(j) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(src)] != 0;
                inside[index(i, j)] = v;
                outside[index(i, j)] = !v;
            }
        const std::array<std::size_t, 3> dims{static_cast<std::size_t>(nu_), static_cast<std::size_t>(nv_), 1};
        const std::vector<double> to_in = squared_distance_transform(dims, inside), to_out = squared_distance_transform(dims, outside);
        sd_.resize(n);
        for (std::size_t k = 0; k < n; ++k)  // pixel centres; the boundary is half a pixel from the last inside centre
            sd_[k] = static_cast<float>(px_ * (inside[k] ? 0.5 - std::sqrt(to_out[k]) : std::sqrt(to_in[k]) - 0.5));
    }

    /// s(u, v), mm; far outside the raster: +inf.
    [[nodiscard]] double operator()(double u, double v) const {
        double x = (u - u0_) / px_ - 0.5 + (closed_ ? margin_ : 0), y = (v - v0_) / px_ - 0.5;
        if (!(y >= 0.0 && y <= nv_ - 1.0 && x >= 0.0 && x <= nu_ - 1.0)) return std::numeric_limits<double>::infinity();
        const int i = std::min(nu_ - 2, static_cast<int>(x)), j = std::min(nv_ - 2, static_cast<int>(y));
        const double a = x - i, b = y - j;
        return (1 - b) * ((1 - a) * sd_[index(i, j)] + a * sd_[index(i + 1, j)]) + b * ((1 - a) * sd_[index(i, j + 1)] + a * sd_[index(i + 1, j + 1)]);
    }

private:
    [[nodiscard]] std::size_t index(int i, int j) const noexcept { return static_cast<std::size_t>(j) * static_cast<std::size_t>(nu_) + static_cast<std::size_t>(i); }
    bool closed_ = false;
    int width_ = 0, nu_ = 0, nv_ = 0, margin_ = 0;
    double px_ = 1, u0_ = 0, v0_ = 0;
    std::vector<float> sd_;
};

// The curve's polyline as a mesh of degenerate triangles (k, k+1, k+1): mesh_distance then finds
// the closest point on the polyline, with the segment as the face.
[[nodiscard]] inline triangle_mesh polyline_mesh(const space_curve& c) {
    triangle_mesh m;
    m.vertices = c.vertices();
    const std::size_t n = m.vertices.size(), segs = c.closed() ? n : n - 1;
    for (std::size_t k = 0; k < segs; ++k) {
        const auto a = static_cast<std::uint32_t>(k), b = static_cast<std::uint32_t>((k + 1) % n);
        m.faces.push_back({a, b, b});
    }
    return m;
}

}  // namespace detail::decoration

/// The decorated solid (see the file comment): `pattern` in band coordinates of `curve`, which lies
/// on `surface`.
[[nodiscard]] inline triangle_mesh decorate_surface(const triangle_mesh& surface, const space_curve& curve, const std::vector<polygon_with_holes>& pattern,
                                                    const surface_decoration_options& opt = {}) {
    validate(surface, "decorate_surface input mesh");
    if (surface.faces.empty()) throw invalid_input("decorate_surface: the surface has no faces");
    const bool emboss = opt.mode == decoration_mode::emboss;
    if (!(std::isfinite(opt.shell) && opt.shell > 0)) throw invalid_input("decorate_surface: shell thickness must be finite and > 0 mm");
    if (emboss && !(std::isfinite(opt.height) && opt.height > 0)) throw invalid_input("decorate_surface: emboss height must be finite and > 0 mm");
    if (!(std::isfinite(opt.cell) && opt.cell >= 0) || !(std::isfinite(opt.pixel) && opt.pixel >= 0))
        throw invalid_input("decorate_surface: cell and pixel must be finite and >= 0 mm (0 = default)");
    const double cell = opt.cell > 0 ? opt.cell : 0.25 * (emboss ? std::min(opt.shell, opt.height) : opt.shell);
    const double pixel = opt.pixel > 0 ? opt.pixel : 0.25 * cell;
    const double top = 0.5 * opt.shell + (emboss ? opt.height : 0.0);  // the solid's largest offset from the surface
    const double reach = top + 2 * cell;

    box3 box = bounding_box(surface);
    box = box3(box.lo - vec3(reach), box.hi + vec3(reach));
    const ivec3 dims = ivec3(glm::ceil(box.size() / cell)) + 1;
    const double samples = static_cast<double>(dims.x) * dims.y * dims.z;
    if (!(samples <= opt.max_samples))
        throw no_solution("decorate_surface: a grid of " + std::to_string(dims.x) + " x " + std::to_string(dims.y) + " x " + std::to_string(dims.z) +
                          " points exceeds max_samples = " + std::to_string(opt.max_samples) + " (a larger cell)");

    const detail::decoration::band_distance s(pattern, curve.length(), curve.closed(), pixel, 2 * cell, opt.max_samples);
    const mesh_distance on_surface(surface);
    const std::vector<vec3> normals = vertex_normals(surface);
    const mesh_distance on_curve(detail::decoration::polyline_mesh(curve));
    const std::vector<double>& arc = curve.vertex_arc_lengths();
    const std::vector<vec3>& cv = curve.vertices();
    double v_reach = 0.0;  // the farthest a pattern point is from the curve, plus the raster's margin
    for (const auto& p : pattern)
        for (const vec2& x : p.outer) v_reach = std::max(v_reach, std::abs(x.y));
    v_reach += 4 * cell;

    // s at the band coordinates of surface point q; +inf away from the band
    const auto pattern_distance = [&](const vec3& q) {
        const mesh_closest c = on_curve.closest(q, v_reach);
        if (!c.found()) return std::numeric_limits<double>::infinity();
        const std::size_t k = c.face;
        const vec3 a = cv[k], b = cv[(k + 1) % cv.size()];
        const vec3 t = glm::normalize(b - a), d = q - c.point;
        const double along = glm::dot(d, t);
        const double u0 = arc[k] + glm::length(c.point - a);
        const vec3 across = d - along * t;
        const double v = std::copysign(glm::length(across), glm::dot(across, curve.offset_direction(u0)));
        return s(curve.closed() ? curve.wrap(u0 + along) : u0 + along, v);
    };
    const auto field = [&](ivec3 ip) -> double {
        const vec3 p = box.lo + cell * vec3(ip);
        const mesh_closest c = on_surface.closest(p, reach);
        if (!c.found()) return reach;  // outside
        const double d = std::sqrt(c.dist2);
        const double shell = d - 0.5 * opt.shell;
        if (!emboss) return std::max(shell, -pattern_distance(c.point));
        const auto& f = surface.faces[c.face];
        const vec3 bq = barycentric(c.point, surface.vertices[f[0]], surface.vertices[f[1]], surface.vertices[f[2]]);
        const vec3 n = bq.x * normals[f[0]] + bq.y * normals[f[1]] + bq.z * normals[f[2]];
        const double w = glm::dot(p - c.point, n) >= 0.0 ? d : -d;
        const double relief = std::max({pattern_distance(c.point), -w, w - top});
        return std::min(shell, relief);
    };
    triangle_mesh solid = marching_cubes(field, dims, box.lo, vec3(cell));
    return opt.fill_cavities ? without_cavities(solid) : solid;
}

}  // namespace fabsynth
