// SPDX-License-Identifier: MIT
#pragma once
/// @file curve.hpp  A smooth curve drawn on a triangle mesh through points the user picks
/// on it, with smooth frames: the synthesis band of Zhou, Jiang & Lefebvre 2014 §6.3 (Fig. 19, 20;
/// topology-constrained-vector-patterns.md).
///
/// Phases (trace_surface_curve):
///  1. control points: each user point is moved to its closest point on the mesh (refused when
///     farther than max_snap) and mapped into the domain of a disk_parameterization Phi;
///  2. spline: a centripetal Catmull-Rom spline through them in the domain (interpolating, so the
///     curve passes through the user's points; the centripetal knots avoid cusps and self-loops
///     within a span, Yuksel, Schaefer & Keyser 2011); the paper only says "a 2D spline";
///  3. samples: each span is sampled so that consecutive samples are about `spacing` apart on the
///     surface (lengths measured through Phi^-1);
///  4. edge crossings: the domain polyline is walked face by face and every crossing with a mesh
///     edge is inserted (the paper's red dots), so each segment lies inside one face and maps to a
///     straight segment of that face: the polyline S = Phi^-1 lies on the mesh;
///  5. smooth normals (Fig. 20): p points G_j equally spaced along S get the surface normal (area-
///     weighted vertex normals interpolated barycentrically); on the unit sphere, a cubic Bezier
///     spline through the n_j with tangents the forward differences n_{j+1} - n_j projected onto
///     the tangent plane at n_j, projected back onto the sphere, gives the normal at every point of
///     S, which is finally made orthogonal to S's tangent there (the chord over +-frame_spacing / 2:
///     the polyline's own segments kink at every edge crossing, the paper's smooth S does not).
/// band_curve() turns the result into a space_curve whose band lies in the tangent plane (the
/// binormal, the band's thickness direction, is the smoothed normal).
///
/// Usage:
///   fabsynth::disk_parameterization phi(vase);
///   auto s = fabsynth::trace_surface_curve(phi, picked_points, /*closed=*/true);
///   fabsynth::space_curve band = s.band_curve();   // u along S, v across on the surface, w along the normal
///
/// Errors: invalid_input naming the problem for a non-finite option or point, a point farther than
/// max_snap from the mesh, fewer than 2 (closed: 3) distinct control points, a spline that leaves
/// the domain (the curve would cross the mesh's border); solver_error if the walk through the
/// faces cannot advance (a degenerate configuration through a vertex).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/surface/disk_parameterization.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/geometry/space_curve.hpp"

namespace fabsynth {

struct surface_curve_options {
    double spacing = 0.0;        ///< distance between the uniform samples on the surface, mm; 0 = half the mesh's mean edge length
    double frame_spacing = 0.0;  ///< distance between the normal samples G_j, mm; 0 = twice the mesh's mean edge length
    double max_snap = 0.0;       ///< control points farther from the mesh are refused, mm; 0 = 1% of its bounding-box diagonal
};

/// A polyline on a mesh (see the file comment).
struct surface_curve {
    bool closed = false;
    std::vector<vec3> points;                  ///< on the mesh, mm
    std::vector<vec2> domain_points;           ///< the same points in Phi's domain
    std::vector<std::uint32_t> segment_faces;  ///< the face holding segment k (points k, k+1; closed: the last wraps)
    std::vector<vec3> normals;                 ///< smoothed unit normal per point, orthogonal to the curve's tangent
    std::size_t edge_crossings = 0;            ///< points inserted where the curve crosses a mesh edge
    std::vector<vec2> control_domain;          ///< the control points in the domain

    /// The band around the curve: binormal along the smoothed normal, band across on the surface.
    /// min_spacing > 0 skips points closer than that to the previously kept one (the ends are
    /// kept): an edge crossing just beside a sample makes a tiny segment, and the kink the
    /// piecewise-linear surface puts at every crossing then gives the mitred band a tiny radius of
    /// curvature (space_curve.hpp) although the curve is smooth at the band's scale. The kept
    /// points are still on the mesh; the chords between them leave it by about spacing^2 / (8 R).
    [[nodiscard]] space_curve band_curve(double min_spacing = 0.0) const {
        if (!(std::isfinite(min_spacing) && min_spacing >= 0.0)) throw invalid_input("surface curve: min_spacing must be finite and >= 0");
        std::vector<vec3> p, n;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const bool last = i + 1 == points.size();
            if (!p.empty() && glm::length(points[i] - p.back()) < min_spacing && !(last && !closed)) continue;
            if (last && closed && p.size() > 1 && glm::length(points[i] - p.front()) < min_spacing) continue;
            if (last && !closed && p.size() > 1 && glm::length(points[i] - p.back()) < min_spacing) p.pop_back(), n.pop_back();
            p.push_back(points[i]);
            n.push_back(normals[i]);
        }
        return space_curve::with_up_directions(std::move(p), n, closed);
    }
};

namespace detail::surface_curve_impl {

[[nodiscard]] inline double mean_edge_length(const triangle_mesh& m) {
    double sum = 0.0;
    for (const auto& t : m.faces)
        for (int e = 0; e < 3; ++e) sum += glm::length(m.vertices[t[static_cast<std::size_t>((e + 1) % 3)]] - m.vertices[t[static_cast<std::size_t>(e)]]);
    return sum / (3.0 * static_cast<double>(m.faces.size()));
}

// Phase 1: the user's points in the domain (consecutive duplicates dropped).
[[nodiscard]] inline std::vector<vec2> control_domain_points(const disk_parameterization& phi, std::span<const vec3> control, bool closed,
                                                             double max_snap) {
    std::vector<vec2> out;
    for (std::size_t i = 0; i < control.size(); ++i) {
        if (!all_finite(control[i])) throw invalid_input("surface curve: control point " + std::to_string(i) + " is not finite");
        const auto pr = phi.project(control[i]);
        if (pr.distance > max_snap)
            throw invalid_input("surface curve: control point " + std::to_string(i) + " is " + std::to_string(pr.distance) +
                                " mm from the mesh (at most " + std::to_string(max_snap) + " mm)");
        if (out.empty() || glm::length(pr.domain - out.back()) > 1e-12) out.push_back(pr.domain);
    }
    if (closed)
        while (out.size() > 1 && glm::length(out.back() - out.front()) <= 1e-12) out.pop_back();
    if (out.size() < 2 || (closed && out.size() < 3))
        throw invalid_input("surface curve: needs at least " + std::string(closed ? "3" : "2") + " distinct control points on the mesh, got " +
                            std::to_string(out.size()));
    return out;
}

// Phase 2: the centripetal Catmull-Rom span between c[i] and c[i+1] (Barry-Goldman's pyramid).
struct catmull_rom_span {
    vec2 p[4];
    double t[4];
    [[nodiscard]] vec2 at(double a) const {  // a in [0, 1] from p[1] to p[2]
        const double s = t[1] + a * (t[2] - t[1]);
        const auto lerp = [](vec2 x, vec2 y, double t0, double t1, double s) { return ((t1 - s) * x + (s - t0) * y) / (t1 - t0); };
        const vec2 a1 = lerp(p[0], p[1], t[0], t[1], s), a2 = lerp(p[1], p[2], t[1], t[2], s), a3 = lerp(p[2], p[3], t[2], t[3], s);
        const vec2 b1 = lerp(a1, a2, t[0], t[2], s), b2 = lerp(a2, a3, t[1], t[3], s);
        return lerp(b1, b2, t[1], t[2], s);
    }
};

[[nodiscard]] inline std::vector<catmull_rom_span> spline_spans(const std::vector<vec2>& c, bool closed) {
    const std::size_t n = c.size(), spans = closed ? n : n - 1;
    const auto point = [&](long i) -> vec2 {
        if (closed) return c[static_cast<std::size_t>((i % static_cast<long>(n) + static_cast<long>(n)) % static_cast<long>(n))];
        if (i < 0) return 2.0 * c[0] - c[1];  // open ends: the neighbour reflected
        if (i >= static_cast<long>(n)) return 2.0 * c[n - 1] - c[n - 2];
        return c[static_cast<std::size_t>(i)];
    };
    std::vector<catmull_rom_span> out(spans);
    for (std::size_t k = 0; k < spans; ++k) {
        catmull_rom_span& s = out[k];
        for (int j = 0; j < 4; ++j) s.p[j] = point(static_cast<long>(k) - 1 + j);
        s.t[0] = 0.0;
        for (int j = 1; j < 4; ++j) s.t[j] = s.t[j - 1] + std::max(std::sqrt(glm::length(s.p[j] - s.p[j - 1])), 1e-12);
    }
    return out;
}

// The surface point of a domain point, or an error if the spline left the domain.
[[nodiscard]] inline mesh_location located(const disk_parameterization& phi, vec2 x) {
    const auto at = phi.locate(x);
    if (!at) throw invalid_input("surface curve: the spline through the control points leaves the mesh (it would cross the border of the surface)");
    return *at;
}

// Phase 3: domain samples about `spacing` apart on the surface (closed: without the repeated end).
[[nodiscard]] inline std::vector<vec2> sample_spline(const disk_parameterization& phi, const std::vector<catmull_rom_span>& spans, bool closed,
                                                     double spacing) {
    constexpr int probes = 64;  // per span, to measure its length on the surface
    std::vector<vec2> out;
    for (std::size_t k = 0; k < spans.size(); ++k) {
        std::vector<double> len(probes + 1, 0.0);
        vec3 prev{0};
        for (int j = 0; j <= probes; ++j) {
            const mesh_location at = located(phi, spans[k].at(static_cast<double>(j) / probes));
            const vec3 p = phi.surface_point(at.face, at.bary);
            if (j > 0) len[static_cast<std::size_t>(j)] = len[static_cast<std::size_t>(j) - 1] + glm::length(p - prev);
            prev = p;
        }
        const int n = std::max(1, static_cast<int>(std::ceil(len[probes] / spacing)));
        for (int i = 0; i < n; ++i) {  // sample i at surface length i * len / n, by the probes' piecewise-linear inverse
            const double want = len[probes] * i / n;
            const auto it = std::upper_bound(len.begin(), len.end(), want);
            const std::size_t j = std::min<std::size_t>(probes, static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - len.begin())));
            const double seg = len[j] - len[j - 1];
            const double a = (static_cast<double>(j) - 1.0 + (seg > 0.0 ? (want - len[j - 1]) / seg : 0.0)) / probes;
            out.push_back(spans[k].at(a));
        }
    }
    if (!closed) out.push_back(spans.back().at(1.0));
    return out;  // a sample outside the domain stops the walk at the border (walk_faces)
}

// Phase 4: the domain polyline walked through the faces, with every edge crossing inserted.
inline void walk_faces(const disk_parameterization& phi, const std::vector<vec2>& samples, bool closed, surface_curve& out) {
    const triangle_mesh& m = phi.mesh();
    const std::vector<vec2>& uv = phi.domain_vertices();
    const double eps = 1e-12;  // domain units: points this close are one point
    const auto add_point = [&](vec2 x, vec3 p) {
        if (!out.domain_points.empty() && glm::length(x - out.domain_points.back()) <= eps) return false;
        out.domain_points.push_back(x);
        out.points.push_back(p);
        return true;
    };
    mesh_location start = located(phi, samples[0]);
    std::uint32_t f = start.face;
    add_point(samples[0], phi.surface_point(f, start.bary));
    const std::size_t n = samples.size(), segs = closed ? n : n - 1;
    for (std::size_t k = 0; k < segs; ++k) {
        const vec2 a = samples[k], b = samples[(k + 1) % n];
        double t_now = 0.0;
        std::uint32_t came_from = disk_parameterization::no_face;
        for (std::size_t steps = 0;; ++steps) {
            if (steps > m.faces.size() + 8)
                throw solver_error("surface curve: the walk through the faces does not advance near domain point (" + std::to_string(a.x) + ", " +
                                   std::to_string(a.y) + ")");
            const auto& t = m.faces[f];
            int exit_edge = -1;
            double t_exit = 2.0;
            for (int e = 0; e < 3; ++e) {
                const vec2 P = uv[t[static_cast<std::size_t>(e)]], Q = uv[t[static_cast<std::size_t>((e + 1) % 3)]];
                const double gb = orient2d(P, Q, b);
                if (!(gb < 0.0) || phi.neighbour(f, e) == came_from) continue;  // b inside this edge's half-plane, or the edge we entered by
                const double ga = orient2d(P, Q, a);
                const double te = std::max(t_now, ga / (ga - gb));
                if (te < t_exit) t_exit = te, exit_edge = e;
            }
            if (exit_edge < 0) {  // b is in face f
                out.segment_faces.push_back(f);
                vec3 bb = glm::max(barycentric(b, uv[t[0]], uv[t[1]], uv[t[2]]), vec3(0.0));
                bb /= bb.x + bb.y + bb.z;
                if (k + 1 < segs || !closed) {
                    if (!add_point(b, phi.surface_point(f, bb))) out.segment_faces.pop_back();
                }
                break;
            }
            // the crossing, placed on the edge itself so that it maps onto the mesh edge
            const std::uint32_t vp = t[static_cast<std::size_t>(exit_edge)], vq = t[static_cast<std::size_t>((exit_edge + 1) % 3)];
            const vec2 x = a + t_exit * (b - a), d = uv[vq] - uv[vp];
            const double s = std::clamp(glm::dot(x - uv[vp], d) / glm::dot(d, d), 0.0, 1.0);
            const vec2 on_edge = uv[vp] + s * d;
            const std::uint32_t g = phi.neighbour(f, exit_edge);
            if (g == disk_parameterization::no_face)
                throw invalid_input("surface curve: the curve leaves the mesh across its border (domain point (" + std::to_string(x.x) + ", " +
                                    std::to_string(x.y) + "))");
            out.segment_faces.push_back(f);
            if (add_point(on_edge, (1.0 - s) * m.vertices[vp] + s * m.vertices[vq]))
                ++out.edge_crossings;
            else
                out.segment_faces.pop_back();
            came_from = f;
            f = g;
            t_now = t_exit;
        }
    }
    if (closed) {  // the last segment ends at the first point: drop a crossing that coincides with it
        while (out.points.size() > 1 && glm::length(out.domain_points.back() - out.domain_points.front()) <= eps) {
            out.points.pop_back(), out.domain_points.pop_back(), out.segment_faces.pop_back();
        }
    }
}

// Phase 5: smooth normals along the polyline (Fig. 20).
[[nodiscard]] inline std::vector<vec3> smooth_normals(const triangle_mesh& m, const surface_curve& s, double frame_spacing) {
    const std::vector<vec3> vn = vertex_normals(m);
    const std::size_t n = s.points.size(), segs = s.closed ? n : n - 1;
    std::vector<double> arc(segs + 1, 0.0);
    for (std::size_t k = 0; k < segs; ++k) arc[k + 1] = arc[k] + glm::length(s.points[(k + 1) % n] - s.points[k]);
    const double L = arc[segs];
    const auto segment_at = [&](double x) {
        return std::min<std::size_t>(segs - 1, static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), x) - arc.begin()) - 1);
    };
    const auto point_at = [&](double x) {  // arc length wrapped (closed) or clamped (open)
        x = s.closed ? x - L * std::floor(x / L) : std::clamp(x, 0.0, L);
        const std::size_t k = segment_at(x);
        const double len = arc[k + 1] - arc[k];
        return s.points[k] + (len > 0.0 ? (x - arc[k]) / len : 0.0) * (s.points[(k + 1) % n] - s.points[k]);
    };
    // the surface normal at arc length x (in the face of the segment holding it)
    const auto surface_normal = [&](double x) {
        const std::size_t k = segment_at(x);
        const vec3 p = point_at(x);
        const auto& t = m.faces[s.segment_faces[k]];
        vec3 b = glm::max(barycentric(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]), vec3(0.0));
        b /= b.x + b.y + b.z;
        const vec3 nn = b.x * vn[t[0]] + b.y * vn[t[1]] + b.z * vn[t[2]];
        return glm::length(nn) > 0.0 ? glm::normalize(nn) : glm::normalize(face_normal_area2(m, s.segment_faces[k]));
    };
    const std::size_t p = std::max<std::size_t>(s.closed ? 3 : 1, static_cast<std::size_t>(std::llround(L / frame_spacing)));
    const std::size_t count = s.closed ? p : p + 1;  // G_j at arc length j L / p
    std::vector<vec3> g(count), tan(count);
    for (std::size_t j = 0; j < count; ++j) g[j] = surface_normal(L * static_cast<double>(j) / static_cast<double>(p));
    const auto at = [&](std::size_t j) -> const vec3& { return g[s.closed ? j % count : std::min(j, count - 1)]; };
    for (std::size_t j = 0; j < count; ++j) {
        const vec3 d = (s.closed || j + 1 < count) ? at(j + 1) - g[j] : g[j] - g[j - 1];
        tan[j] = d - glm::dot(d, g[j]) * g[j];
    }
    std::vector<vec3> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double x = std::clamp(arc[i] / L * static_cast<double>(p), 0.0, static_cast<double>(p));
        const std::size_t j = std::min<std::size_t>(p - 1, static_cast<std::size_t>(x));
        const double a = x - static_cast<double>(j);
        const vec3 b0 = at(j), b3 = at(j + 1), b1 = b0 + tan[j] / 3.0, b2 = b3 - tan[s.closed ? (j + 1) % count : j + 1] / 3.0;
        const double u = 1.0 - a;
        vec3 nn = u * u * u * b0 + 3.0 * u * u * a * b1 + 3.0 * u * a * a * b2 + a * a * a * b3;
        // the curve's tangent at point i, over a window of half a frame spacing on either side:
        // the polyline kinks at every edge crossing, and its segments' directions would make the
        // projected normal jump there
        vec3 t = point_at(arc[i] + 0.5 * frame_spacing) - point_at(arc[i] - 0.5 * frame_spacing);
        if (glm::length(t) > 0.0) t = glm::normalize(t);
        nn = glm::normalize(nn);
        nn -= glm::dot(nn, t) * t;
        out[i] = glm::normalize(nn);
    }
    return out;
}

}  // namespace detail::surface_curve_impl

/// The curve through `control` (points on or near the mesh of phi, mm) as described in the file
/// comment; closed: the last point joins the first.
[[nodiscard]] inline surface_curve trace_surface_curve(const disk_parameterization& phi, std::span<const vec3> control, bool closed,
                                                       const surface_curve_options& opt = {}) {
    namespace impl = detail::surface_curve_impl;
    for (double v : {opt.spacing, opt.frame_spacing, opt.max_snap})
        if (!(std::isfinite(v) && v >= 0.0)) throw invalid_input("surface curve: spacing, frame_spacing and max_snap must be finite and >= 0");
    const triangle_mesh& m = phi.mesh();
    const double edge = impl::mean_edge_length(m);
    const double spacing = opt.spacing > 0.0 ? opt.spacing : 0.5 * edge;
    const double frame_spacing = opt.frame_spacing > 0.0 ? opt.frame_spacing : 2.0 * edge;
    const double max_snap = opt.max_snap > 0.0 ? opt.max_snap : 0.01 * glm::length(bounding_box(m).size());

    surface_curve s;
    s.closed = closed;
    s.control_domain = impl::control_domain_points(phi, control, closed, max_snap);
    const std::vector<impl::catmull_rom_span> spans = impl::spline_spans(s.control_domain, closed);
    const std::vector<vec2> samples = impl::sample_spline(phi, spans, closed, spacing);
    impl::walk_faces(phi, samples, closed, s);
    if (s.points.size() < 2 || (closed && s.points.size() < 3)) throw invalid_input("surface curve: the curve has no length on the mesh");
    s.normals = impl::smooth_normals(m, s, frame_spacing);
    return s;
}

}  // namespace fabsynth
