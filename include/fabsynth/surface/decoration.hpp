// SPDX-License-Identifier: MIT
#pragma once
/// @file decoration.hpp  A band pattern on a surface made printable: embossed onto a shell
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
/// normals interpolated at q) and band coordinates of q: u from the plane through q of a family
/// sweeping the curve (the mitre planes at its vertices, interpolated in between, so u is
/// continuous in q, which the closest point on a polyline is not), and v = +-q's distance from
/// the curve in that plane, on the side of the band's offset direction. So the pattern is laid on the surface itself,
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
        std::vector<bool> feature(n);
        for (int j = 0; j < nv_; ++j)
            for (int i = 0; i < nu_; ++i) {
                const int src = closed ? ((i - margin_) % width_ + width_) % width_ : i;
                feature[index(i, j)] = in[static_cast<std::size_t>(j) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(src)] != 0;
            }
        const std::array<std::size_t, 3> dims{static_cast<std::size_t>(nu_), static_cast<std::size_t>(nv_), 1};
        const std::vector<double> to_in = squared_distance_transform(dims, feature);  // 0 exactly on inside pixels
        feature.flip();
        const std::vector<double> to_out = squared_distance_transform(dims, feature);
        sd_.resize(n);
        for (std::size_t k = 0; k < n; ++k)  // pixel centres; the boundary is half a pixel from the last inside centre
            sd_[k] = static_cast<float>(px_ * (to_in[k] == 0.0 ? 0.5 - std::sqrt(to_out[k]) : std::sqrt(to_in[k]) - 0.5));
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

// Band coordinates (u, v) of a point q near the curve, continuous in q. The closest point on the
// polyline is not: on the inner side of each vertex's bend (in the band, or toward the surface the
// curve bends with) it jumps from one segment to the next, and so would u, by about the offset
// times the bend angle. Instead q is cut by a family of planes that sweeps the curve: at each vertex
// the mitre plane (normal: the mean of the two segments' tangents, the plane the mitred band map
// puts the vertex's cross-section in), in between the plane whose normal interpolates the two ends'
// linearly. The plane through q gives u; v is q's distance from the curve within that plane, signed
// by the band's offset direction. On segment k with ends P, P + D and plane normals T0, T1, q's
// plane is at the root a in [0, 1] of (q - P - a D) . (T0 + a (T1 - T0)), a quadratic.
class band_coordinates {
public:
    explicit band_coordinates(const space_curve& c) : curve_(c) {
        const std::vector<vec3>& p = c.vertices();
        const std::size_t n = p.size(), segs = c.closed() ? n : n - 1;
        std::vector<vec3> t(segs);
        for (std::size_t k = 0; k < segs; ++k) t[k] = glm::normalize(p[(k + 1) % n] - p[k]);
        plane_.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const bool has_prev = c.closed() || i > 0, has_next = c.closed() || i + 1 < n;
            const vec3 a = has_prev ? t[(i + segs - 1) % segs] : t[0], b = has_next ? t[i % segs] : t[segs - 1];
            plane_[i] = glm::normalize(a + b);
        }
        segs_ = segs;
    }

    /// (u, v) of q, starting the search at segment `k` (the segment of q's closest point).
    [[nodiscard]] vec2 operator()(const vec3& q, std::size_t k) const {
        const std::vector<vec3>& p = curve_.vertices();
        const std::vector<double>& arc = curve_.vertex_arc_lengths();
        const std::size_t n = p.size();
        for (int steps = 0; steps < 8; ++steps) {
            const vec3 P = p[k], D = p[(k + 1) % n] - P, T0 = plane_[k], T1 = plane_[(k + 1) % n];
            const vec3 r = q - P;
            const double g0 = glm::dot(r, T0), g1 = glm::dot(r - D, T1);
            if (g0 < 0.0 && (curve_.closed() || k > 0)) {  // q's plane is before this segment
                k = (k + segs_ - 1) % segs_;
                continue;
            }
            if (g1 > 0.0 && (curve_.closed() || k + 1 < segs_)) {  // after it
                k = (k + 1) % segs_;
                continue;
            }
            // g(a) = g0 + a (r . (T1 - T0) - D . T0) - a^2 D . (T1 - T0): its root in [0, 1] (beyond
            // the ends of an open curve, the end plane moved along the end tangent)
            double a;
            if (g0 < 0.0) {
                a = g0 / glm::dot(D, T0);
            } else if (g1 > 0.0) {
                a = 1.0 + g1 / glm::dot(D, T1);
            } else {
                const double A = -glm::dot(D, T1 - T0), B = glm::dot(r, T1 - T0) - glm::dot(D, T0), C = g0;
                a = root_in_unit(A, B, C);
            }
            const double len = arc[k + 1] - arc[k];
            const vec3 across = q - (P + a * D);
            const double u0 = arc[k] + a * len;
            const double v = std::copysign(glm::length(across), glm::dot(across, curve_.offset_direction(std::clamp(u0, 0.0, curve_.length()))));
            return {curve_.closed() ? curve_.wrap(u0) : u0, v};
        }
        return {std::numeric_limits<double>::infinity(), 0.0};  // in a fold of the band: no coordinates
    }

private:
    // The root in [0, 1] of A a^2 + B a + C with C >= 0 >= A + B + C (it exists by continuity).
    [[nodiscard]] static double root_in_unit(double A, double B, double C) {
        if (std::abs(A) <= 1e-12 * (std::abs(B) + std::abs(C))) return std::clamp(B != 0.0 ? -C / B : 0.0, 0.0, 1.0);
        const double disc = std::max(0.0, B * B - 4 * A * C), sq = std::sqrt(disc);
        const double q = -0.5 * (B + std::copysign(sq, B));  // stable pair of roots q / A and C / q
        const double r1 = q / A, r2 = q != 0.0 ? C / q : r1;
        const auto inside = [](double x) { return x >= -1e-9 && x <= 1 + 1e-9; };
        return std::clamp(inside(r1) && (!inside(r2) || std::abs(r1 - 0.5) <= std::abs(r2 - 0.5)) ? r1 : r2, 0.0, 1.0);
    }

    const space_curve& curve_;
    std::vector<vec3> plane_;  // mitre-plane normal per vertex
    std::size_t segs_ = 0;
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
    double v_reach = 0.0;  // the farthest a pattern point is from the curve, plus the raster's margin
    for (const auto& p : pattern)
        for (const vec2& x : p.outer) v_reach = std::max(v_reach, std::abs(x.y));
    v_reach += 4 * cell;

    // s at the band coordinates of surface point q; +inf away from the band
    const detail::decoration::band_coordinates coords(curve);
    const auto pattern_distance = [&](const vec3& q) {
        const mesh_closest c = on_curve.closest(q, v_reach);
        if (!c.found()) return std::numeric_limits<double>::infinity();
        const vec2 uv = coords(q, c.face);
        return s(uv.x, uv.y);
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
