// SPDX-License-Identifier: MIT
#pragma once
/// @file labels.hpp  Labels (psi, tau) and the mapping M(x, psi, tau) from space to exemplar pixels
/// (structurally-sound-patterns.md §4.1).
///
/// Usage:
///   fabsynth::surface_pattern::label_space ls(128, 128, {.mm_per_px = 0.4});
///   std::uint32_t l = ls.make(ls.nearest_plane(n), 0, 3, 7);   // plane, rotation, translation (3, 7)
///   fabsynth::vec2 px = ls.map(x_mm, l);                          // exemplar pixel coordinates
///
/// Planes Psi: the 26 directions (i, j, k) in {-1, 0, 1}^3 \ {0}, normalised ("planes evenly
/// distributed on the unit sphere in all 26 directions", §6.1). Each plane psi has an orthonormal
/// frame (r, b, n): b is the reference 'up' direction projected on the plane (or, for planes facing
/// up or down, the y or x axis projected), r = b x n, so a viewer outside the surface, looking along
/// -n with b up, sees the exemplar upright and not mirrored. Transforms Gamma: T x T translations
/// (t = (i W / T, j H / T) pixels) times R rotations (theta = 2 pi k / R) of the plane (paper: 16 x 16
/// and 64), plus one exemplar scale s (mm per pixel). The mapping is affine:
///   M(x, psi, tau) = R(theta) ((x . r) / s, -(x . b) / s) + t
/// i.e. the orthogonal projection of x on the plane, scaled to pixels with the image's y axis
/// (rows, pointing down) along -b, rotated and translated. Pixel coordinates follow exemplar.hpp
/// (pixel (i, j) covers [i, i+1) x [j, j+1)); lookups tile the exemplar.
///
/// A label is one integer with bit fields: tx in bits 0-7, ty in 8-15, rotation in 16-25, plane in
/// 26-30 (decoded by shifts: labels are decoded once per candidate in the synthesizer's inner loop).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth::surface_pattern {

/// The label set.
struct label_options {
    double mm_per_px = 0;     ///< exemplar scale s: millimetres per exemplar pixel (> 0)
    int translations = 16;    ///< T: translations per axis (1 .. 256)
    int rotations = 64;       ///< R: rotations (1 .. 1024)
    vec3 up{0, 0, 1};         ///< reference direction the planes' b axes follow (non-zero)
};

/// 2x3 affine map from space (mm) to exemplar pixels: px = A x + t.
struct plane_map {
    double a[2][3];
    double t[2];
    [[nodiscard]] vec2 operator()(const vec3& x) const noexcept {
        return {a[0][0] * x.x + a[0][1] * x.y + a[0][2] * x.z + t[0], a[1][0] * x.x + a[1][1] * x.y + a[1][2] * x.z + t[1]};
    }
    /// The linear part applied to a displacement (no translation).
    [[nodiscard]] vec2 linear(const vec3& d) const noexcept {
        return {a[0][0] * d.x + a[0][1] * d.y + a[0][2] * d.z, a[1][0] * d.x + a[1][1] * d.y + a[1][2] * d.z};
    }
};

/// Planes, transforms and the mapping (see the file comment).
class label_space {
public:
    static constexpr int plane_count = 26;

    label_space() = default;
    /// @param width, height  exemplar size in pixels (>= 1)
    label_space(int width, int height, const label_options& opt) : width_(width), height_(height), opt_(opt) {
        if (width < 1 || height < 1) throw invalid_input("label space: exemplar size must be positive");
        if (!(std::isfinite(opt.mm_per_px) && opt.mm_per_px > 0))
            throw invalid_input("label space: exemplar scale must be finite and > 0 mm per pixel, got " + std::to_string(opt.mm_per_px));
        if (opt.translations < 1 || opt.translations > 256) throw invalid_input("label space: translations must be in [1, 256]");
        if (opt.rotations < 1 || opt.rotations > 1024) throw invalid_input("label space: rotations must be in [1, 1024]");
        if (!(std::isfinite(opt.up.x) && std::isfinite(opt.up.y) && std::isfinite(opt.up.z)) || glm::length(opt.up) == 0)
            throw invalid_input("label space: the up direction must be finite and non-zero");
        const vec3 up = glm::normalize(opt.up);
        int k = 0;
        for (int i = -1; i <= 1; ++i)
            for (int j = -1; j <= 1; ++j)
                for (int l = -1; l <= 1; ++l) {
                    if (i == 0 && j == 0 && l == 0) continue;
                    const vec3 n = glm::normalize(vec3(i, j, l));
                    // b: up projected on the plane; for planes (nearly) facing up, fall back to y then x
                    vec3 ref = up;
                    if (std::abs(glm::dot(ref, n)) > 0.99) ref = std::abs(n.y) < 0.9 ? vec3(0, 1, 0) : vec3(1, 0, 0);
                    const vec3 b = glm::normalize(ref - glm::dot(ref, n) * n);
                    normal_[k] = n;
                    b_[k] = b;
                    r_[k] = glm::cross(b, n);
                    ++k;
                }
        for (int t = 0; t < opt.translations; ++t) {
            shift_x_.push_back(static_cast<double>(t) * width / opt.translations);
            shift_y_.push_back(static_cast<double>(t) * height / opt.translations);
        }
        const int R = opt.rotations;
        linear_.resize(static_cast<std::size_t>(plane_count) * static_cast<std::size_t>(R));
        for (int p = 0; p < plane_count; ++p)
            for (int rot = 0; rot < R; ++rot) {
                const double th = 2.0 * std::numbers::pi * rot / R, c = std::cos(th), s = std::sin(th);
                // unrotated pixel coordinates: u = (x . r) / s, v = -(x . b) / s
                const vec3 u = r_[p] / opt.mm_per_px, v = -b_[p] / opt.mm_per_px;
                plane_map& m = linear_[static_cast<std::size_t>(p * R + rot)];
                for (int a = 0; a < 3; ++a) {
                    m.a[0][a] = c * u[a] - s * v[a];
                    m.a[1][a] = s * u[a] + c * v[a];
                }
                m.t[0] = m.t[1] = 0;
            }
    }

    [[nodiscard]] const label_options& options() const noexcept { return opt_; }
    [[nodiscard]] int width() const noexcept { return width_; }
    [[nodiscard]] int height() const noexcept { return height_; }
    /// True iff every field of the label is in range.
    [[nodiscard]] bool valid(std::uint32_t l) const noexcept {
        return plane(l) < plane_count && rotation(l) < opt_.rotations && tx(l) < opt_.translations && ty(l) < opt_.translations &&
               (l >> 31) == 0;
    }
    [[nodiscard]] static constexpr std::uint32_t make(int plane, int rotation, int tx, int ty) noexcept {
        return static_cast<std::uint32_t>(plane) << 26 | static_cast<std::uint32_t>(rotation) << 16 | static_cast<std::uint32_t>(ty) << 8 |
               static_cast<std::uint32_t>(tx);
    }
    [[nodiscard]] static constexpr int plane(std::uint32_t l) noexcept { return static_cast<int>((l >> 26) & 31u); }
    [[nodiscard]] static constexpr int rotation(std::uint32_t l) noexcept { return static_cast<int>((l >> 16) & 1023u); }
    [[nodiscard]] static constexpr int tx(std::uint32_t l) noexcept { return static_cast<int>(l & 255u); }
    [[nodiscard]] static constexpr int ty(std::uint32_t l) noexcept { return static_cast<int>((l >> 8) & 255u); }

    /// Unit normal n(psi) of a plane.
    [[nodiscard]] const vec3& normal(int plane) const noexcept { return normal_[static_cast<std::size_t>(plane)]; }
    /// The plane's frame: r (image x), b (image up).
    [[nodiscard]] const vec3& right(int plane) const noexcept { return r_[static_cast<std::size_t>(plane)]; }
    [[nodiscard]] const vec3& up(int plane) const noexcept { return b_[static_cast<std::size_t>(plane)]; }

    /// The affine map of a label.
    [[nodiscard]] plane_map map_of(std::uint32_t l) const noexcept {
        plane_map m = linear_[static_cast<std::size_t>(plane(l) * opt_.rotations + rotation(l))];
        m.t[0] = shift_x_[static_cast<std::size_t>(tx(l))];
        m.t[1] = shift_y_[static_cast<std::size_t>(ty(l))];
        return m;
    }
    /// M(x, psi, tau): exemplar pixel coordinates of the point x (mm).
    [[nodiscard]] vec2 map(const vec3& x, std::uint32_t l) const noexcept { return map_of(l)(x); }

    /// The plane whose normal is best aligned with d (largest dot product). Closed form: with the
    /// components sorted by magnitude a >= b >= c, the best face, edge and corner directions score
    /// a, (a + b) / sqrt 2 and (a + b + c) / sqrt 3 (ties to the face, then the edge).
    [[nodiscard]] int nearest_plane(const vec3& d) const noexcept {
        // written with selects rather than a sort: the random candidates call this in the inner loop
        // with unpredictable inputs, where sorting branches mispredict
        const double a = std::abs(d.x), b = std::abs(d.y), c = std::abs(d.z);
        const double mx = std::max(a, std::max(b, c)), mn = std::min(a, std::min(b, c)), sum = a + b + c;
        const double face = mx, edge = (sum - mn) * (std::numbers::sqrt2 / 2), corner = sum * std::numbers::inv_sqrt3;
        const bool use_corner = corner > face && corner > edge, use_edge = !use_corner && edge > face;
        const int imax = a >= b ? (a >= c ? 0 : 2) : (b >= c ? 1 : 2), imin = a <= b ? (a <= c ? 0 : 2) : (b <= c ? 1 : 2);
        int code = 13;  // (0, 0, 0) in the constructor's order (i + 1) * 9 + (j + 1) * 3 + (l + 1)
        constexpr int weight[3] = {9, 3, 1};
        for (int i = 0; i < 3; ++i) {
            const bool in = use_corner || (use_edge ? i != imin : i == imax);
            code += in ? (d[i] < 0 ? -weight[i] : weight[i]) : 0;
        }
        return code > 13 ? code - 1 : code;
    }
    /// The rotation that makes the exemplar's up direction (-y in pixels) follow the tangent
    /// direction `d` (any length, projected on the plane), rounded to the nearest of the R rotations.
    /// d with no component in the plane gives 0.
    [[nodiscard]] int aligned_rotation(int plane, const vec3& d) const noexcept {
        const double dr = glm::dot(d, r_[static_cast<std::size_t>(plane)]), db = glm::dot(d, b_[static_cast<std::size_t>(plane)]);
        if (dr == 0 && db == 0) return 0;
        // pixel direction of d before rotation: (dr, -db); rotate it onto (0, -1)
        const double theta = -0.5 * std::numbers::pi - std::atan2(-db, dr);
        const int R = opt_.rotations;
        long k = std::lround(theta / (2.0 * std::numbers::pi) * R) % R;
        if (k < 0) k += R;
        return static_cast<int>(k);
    }

private:
    int width_ = 1, height_ = 1;
    label_options opt_{};
    std::array<vec3, plane_count> normal_{}, r_{}, b_{};
    std::vector<plane_map> linear_;         // per (plane, rotation), no translation
    std::vector<double> shift_x_, shift_y_;  // translation i -> i W / T, i H / T pixels
};

}  // namespace fabsynth::surface_pattern
