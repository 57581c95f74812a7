// SPDX-License-Identifier: MIT
#pragma once
/// @file svg_path.hpp  Internal: SVG path data and points lists, flattened to polylines in the
/// document's root user space. Not part of the public API.
///
/// Flattening error bounds (distance between the true curve and the emitted polyline, measured
/// after all transforms):
///  - Bezier of degree d, split uniformly into n pieces: error <= d(d-1)/8 * L / n^2 with L the
///    largest second difference of the control points (Wang's formula; see e.g. Goldman,
///    "Pyramid Algorithms", 2003, or Filip, Magedson & Markot, CAGD 3(4), 1986). So
///    n = ceil(sqrt(d(d-1) L / (8 tol))).
///  - Elliptical arc c(t) = C + A (cos t, sin t), split uniformly in t into steps h: the chord
///    error is <= h^2/8 * max|c''| = h^2/8 * sigma_max(A). So h = sqrt(8 tol / sigma_max(A)).
/// Endpoints of every segment are the exact transformed command endpoints (no drift).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/core/types.hpp"
#include "fabsynth/io/detail/svg_scan.hpp"
#include "fabsynth/io/detail/svg_xml.hpp"

namespace fabsynth::io::detail::svg {

/// Builds subpaths from drawing commands given in local coordinates; applies `ctm`, flattens
/// curves to `tol` and charges every emitted point to `budget` (the document-wide point limit).
class flattener {
public:
    std::vector<std::vector<vec2>> subpaths;
    std::vector<bool> closed;
    std::size_t at = 0;  ///< byte offset reported by errors (updated by the caller per command)

    flattener(const source& src, const affine2& ctm, double tol, std::size_t& budget, std::size_t limit)
        : src_(src), ctm_(ctm), tol_(tol), budget_(budget), limit_(limit) {}

    [[nodiscard]] vec2 current() const noexcept { return cur_; }
    [[nodiscard]] vec2 subpath_start() const noexcept { return start_; }

    void move_to(vec2 p) {
        finish_open();
        open_ = true;
        pts_.clear();
        cur_ = start_ = p;
        emit(ctm_.apply(p));
    }
    void line_to(vec2 p) {
        begin_segment();
        cur_ = p;
        emit(ctm_.apply(p));
    }
    void quad_to(vec2 c, vec2 p) {
        begin_segment();
        const vec2 w[3] = {ctm_.apply(cur_), ctm_.apply(c), ctm_.apply(p)};
        bezier(w, 2);
        cur_ = p;
    }
    void cubic_to(vec2 c1, vec2 c2, vec2 p) {
        begin_segment();
        const vec2 w[4] = {ctm_.apply(cur_), ctm_.apply(c1), ctm_.apply(c2), ctm_.apply(p)};
        bezier(w, 3);
        cur_ = p;
    }
    /// Elliptical arc from the current point to p, converted to center form per SVG 1.1
    /// implementation notes F.6.5 (with F.6.6 radius correction).
    void arc_to(double rx, double ry, double phi_deg, bool large, bool sweep, vec2 p) {
        const vec2 p1 = cur_;
        if (p1 == p) return;  // F.6.2: identical endpoints omit the arc
        rx = std::abs(rx);
        ry = std::abs(ry);
        if (rx == 0.0 || ry == 0.0) return line_to(p);  // F.6.2: straight line
        begin_segment();
        const double phi = std::fmod(phi_deg, 360.0) * (std::numbers::pi / 180.0);
        const double cs = std::cos(phi), sn = std::sin(phi);
        const double dx2 = 0.5 * (p1.x - p.x), dy2 = 0.5 * (p1.y - p.y);
        const double x1p = cs * dx2 + sn * dy2, y1p = -sn * dx2 + cs * dy2;
        // Work with X = x1'/rx, Y = y1'/ry: F.6.5.2's radicand divided by rx^2 ry^2 is
        // (1 - L)/L with L = X^2 + Y^2, which avoids overflowing rx^2 ry^2.
        double X = x1p / rx, Y = y1p / ry;
        const double L = X * X + Y * Y;
        if (L > 1.0) {  // F.6.6: radii too small, scale up uniformly
            const double s = std::sqrt(L);
            rx *= s, ry *= s, X /= s, Y /= s;
        }
        const double L2 = X * X + Y * Y;
        double coef = L2 > 0.0 ? std::sqrt(std::max(0.0, (1.0 - L2) / L2)) : 0.0;
        if (large == sweep) coef = -coef;
        const double cxp = coef * rx * Y, cyp = -coef * ry * X;
        const vec2 c{cs * cxp - sn * cyp + 0.5 * (p1.x + p.x), sn * cxp + cs * cyp + 0.5 * (p1.y + p.y)};
        const double ux = (x1p - cxp) / rx, uy = (y1p - cyp) / ry, vx = (-x1p - cxp) / rx, vy = (-y1p - cyp) / ry;
        const double theta1 = std::atan2(uy, ux);
        double dtheta = std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
        if (!sweep && dtheta > 0) dtheta -= 2.0 * std::numbers::pi;
        if (sweep && dtheta < 0) dtheta += 2.0 * std::numbers::pi;
        ellipse_points(c, rx, ry, cs, sn, theta1, dtheta, false);
        cur_ = p;
        emit(ctm_.apply(p));
    }
    /// Whole ellipse (circle/ellipse elements, SVG 2 "equivalent path": starts at (cx + rx, cy)
    /// and runs in the direction of increasing angle) as one closed subpath.
    void ellipse(vec2 c, double rx, double ry) {
        move_to({c.x + rx, c.y});
        ellipse_points(c, rx, ry, 1.0, 0.0, 0.0, 2.0 * std::numbers::pi, true);
        close();
    }
    /// Closes the current subpath; trailing copies of the first point are dropped.
    void close() {
        if (!open_) begin_segment();  // "Z Z" or "Z" right after a closed subpath
        while (pts_.size() >= 2 && pts_.back() == pts_.front()) pts_.pop_back();
        if (pts_.size() >= 2) subpaths.push_back(std::move(pts_)), closed.push_back(true);
        pts_.clear();
        open_ = false;
        cur_ = start_;
    }
    /// Ends the last subpath; call once after the last command.
    void finish() { finish_open(); }

private:
    const source& src_;
    affine2 ctm_;
    double tol_;
    std::size_t& budget_;
    std::size_t limit_;
    std::vector<vec2> pts_;
    vec2 cur_{0, 0}, start_{0, 0};
    bool open_ = false;

    void finish_open() {
        if (open_ && pts_.size() >= 2) subpaths.push_back(std::move(pts_)), closed.push_back(false);
        pts_.clear();
        open_ = false;
    }
    // A drawing command after Z starts a new subpath at the current point (SVG 1.1, 8.3.3).
    void begin_segment() {
        if (open_) return;
        open_ = true;
        pts_.clear();
        start_ = cur_;
        emit(ctm_.apply(cur_));
    }
    void emit(vec2 w) {
        if (!all_finite(w)) src_.fail(at, "coordinate overflows the double range after transforms");
        if (budget_ == 0) too_many();
        --budget_;
        pts_.push_back(w);
    }
    [[noreturn]] void too_many() const {
        src_.fail(at, "more than " + std::to_string(limit_) + " points after flattening (raise the tolerance or the point limit)");
    }
    // Number of pieces for a real-valued estimate; NaN and overflow land in too_many().
    std::size_t pieces(double n_real, std::size_t minimum) const {
        if (!(n_real <= static_cast<double>(budget_))) too_many();
        return std::max(minimum, static_cast<std::size_t>(std::ceil(n_real)));
    }
    void bezier(const vec2* w, int degree) {
        double L = 0.0;
        for (int i = 0; i + 2 <= degree; ++i) L = std::max(L, glm::length(w[i + 2] - 2.0 * w[i + 1] + w[i]));
        for (int i = 0; i <= degree; ++i)
            if (!all_finite(w[i])) src_.fail(at, "coordinate overflows the double range after transforms");
        const std::size_t n = pieces(std::sqrt(degree * (degree - 1) * L / (8.0 * tol_)), 1);
        for (std::size_t k = 1; k < n; ++k) {
            const double t = static_cast<double>(k) / static_cast<double>(n), s = 1.0 - t;
            vec2 q = degree == 2 ? s * s * w[0] + 2.0 * s * t * w[1] + t * t * w[2]
                                 : s * s * s * w[0] + 3.0 * s * s * t * w[1] + 3.0 * s * t * t * w[2] + t * t * t * w[3];
            emit(q);
        }
        emit(w[degree]);
    }
    // Emits the interior points of c + R(phi) (rx cos t, ry sin t), t in (t0, t0 + dt), plus
    // t0 itself when the subpath was just started by the caller with it (full ellipses skip it).
    void ellipse_points(vec2 c, double rx, double ry, double cs, double sn, double t0, double dt, bool full) {
        // A = M * R(phi) * diag(rx, ry), M the linear part of the transform.
        const double r00 = cs * rx, r01 = -sn * ry, r10 = sn * rx, r11 = cs * ry;
        const double a00 = ctm_.a * r00 + ctm_.c * r10, a01 = ctm_.a * r01 + ctm_.c * r11;
        const double a10 = ctm_.b * r00 + ctm_.d * r10, a11 = ctm_.b * r01 + ctm_.d * r11;
        const double sigma = max_singular_value(a00, a01, a10, a11);
        const std::size_t n = pieces(std::abs(dt) * std::sqrt(sigma / (8.0 * tol_)), full ? 4 : 1);
        const vec2 wc = ctm_.apply(c);
        for (std::size_t k = 1; k < n; ++k) {
            const double t = t0 + dt * (static_cast<double>(k) / static_cast<double>(n));
            const double ct = std::cos(t), st = std::sin(t);
            emit({wc.x + a00 * ct + a01 * st, wc.y + a10 * ct + a11 * st});
        }
    }
};

/// Interprets SVG path data (M L H V C S Q T A Z, absolute and relative, implicit repetition)
/// into `fl`. Empty data draws nothing. Data must start with M or m.
inline void parse_path_data(scanner& sc, flattener& fl) {
    sc.skip_wsp();
    if (sc.at_end()) return;
    if (sc.peek() != 'M' && sc.peek() != 'm') sc.fail("path data must start with M or m");
    char cmd = 0, prev = 0;
    vec2 ctrl{0, 0};  // last control point of a C/S (for S) or Q/T (for T), local coordinates
    while (true) {
        sc.skip_wsp();
        if (sc.at_end()) break;
        const char c = sc.peek();
        fl.at = sc.base + sc.pos;
        if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z')) {
            if (std::string_view("MmLlHhVvCcSsQqTtAaZz").find(c) == std::string_view::npos)
                sc.fail(std::string("unknown path command '") + c + "'");
            cmd = c;
            ++sc.pos;
            sc.skip_wsp();
            if (cmd != 'Z' && cmd != 'z' && !sc.at_number())
                sc.fail(std::string("expected a number after '") + cmd + "'");
        } else if (sc.at_number()) {
            if (prev == 'Z' || prev == 'z') sc.fail("number after Z (a command letter is needed)");
            if (cmd == 'M') cmd = 'L';
            else if (cmd == 'm') cmd = 'l';
        } else {
            sc.fail(std::string("unexpected character '") + c + "' in path data");
        }
        const bool rel = cmd >= 'a' && cmd <= 'z';
        const vec2 cur = fl.current();
        auto pt = [&](bool first) {
            vec2 p;
            p.x = first ? sc.number() : sc.next_number("expected a number");
            p.y = sc.next_number("expected a number (coordinates come in pairs)");
            return rel ? p + cur : p;  // no "+ 0" for absolute: keeps -0 exact
        };
        switch (cmd) {
            case 'M': case 'm': fl.move_to(pt(true)); break;
            case 'L': case 'l': fl.line_to(pt(true)); break;
            case 'H': case 'h': fl.line_to({rel ? cur.x + sc.number() : sc.number(), cur.y}); break;
            case 'V': case 'v': fl.line_to({cur.x, rel ? cur.y + sc.number() : sc.number()}); break;
            case 'C': case 'c': {
                const vec2 c1 = pt(true), c2 = pt(false), p = pt(false);
                fl.cubic_to(c1, c2, p);
                ctrl = c2;
                break;
            }
            case 'S': case 's': {
                const bool smooth = prev == 'C' || prev == 'c' || prev == 'S' || prev == 's';
                const vec2 c1 = smooth ? 2.0 * cur - ctrl : cur;
                const vec2 c2 = pt(true), p = pt(false);
                fl.cubic_to(c1, c2, p);
                ctrl = c2;
                break;
            }
            case 'Q': case 'q': {
                const vec2 c1 = pt(true), p = pt(false);
                fl.quad_to(c1, p);
                ctrl = c1;
                break;
            }
            case 'T': case 't': {
                const bool smooth = prev == 'Q' || prev == 'q' || prev == 'T' || prev == 't';
                const vec2 c1 = smooth ? 2.0 * cur - ctrl : cur;
                const vec2 p = pt(true);
                fl.quad_to(c1, p);
                ctrl = c1;
                break;
            }
            case 'A': case 'a': {
                const double rx = sc.number();
                const double ry = sc.next_number("expected a number (arc ry)");
                const double rot = sc.next_number("expected a number (arc x-axis-rotation)");
                const bool large = sc.flag();
                const bool sweep = sc.flag();
                const vec2 p = pt(false);
                fl.arc_to(rx, ry, rot, large, sweep, p);
                break;
            }
            case 'Z': case 'z': fl.close(); break;
            default: sc.fail(std::string("unknown path command '") + cmd + "'");  // unreachable
        }
        prev = cmd;
        if (sc.skip_comma_wsp() && !sc.at_number()) sc.fail("expected a number after ','");
    }
    fl.finish();
}

/// Interprets a polygon/polyline points list ("x,y x,y ..."). Empty lists draw nothing.
inline void parse_points(scanner& sc, flattener& fl, bool close) {
    sc.skip_wsp();
    bool first = true;
    while (!sc.at_end()) {
        fl.at = sc.base + sc.pos;
        if (!sc.at_number()) sc.fail("expected a number");
        vec2 p;
        p.x = sc.number();
        p.y = sc.next_number("expected a number (points need an even number of coordinates)");
        if (first) fl.move_to(p);
        else fl.line_to(p);
        first = false;
        if (sc.skip_comma_wsp() && sc.at_end()) sc.fail("expected a number after ','");
    }
    if (!first && close) fl.close();
    fl.finish();
}

}  // namespace fabsynth::io::detail::svg
