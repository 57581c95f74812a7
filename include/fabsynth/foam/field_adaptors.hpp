// SPDX-License-Identifier: MIT
#pragma once
/// @file field_adaptors.hpp  Fields (fields.hpp) built from user data: a grayscale image on a
/// plane, the distance to a mesh surface, and a relative Young's modulus mapped to the seed
/// density that realises it (paper §4.2). Each is a bounded_field: callable as f(vec3 x [mm]) ->
/// double, thread-safe, with max_value() an upper bound of its values.
///
/// Usage:
///   image_field img(io::read_png("grade.png"), {{0, 0}, {40, 40}}, 0.05, 0.6);   // seeds/mm^3
///   surface_distance_field skin(mesh_dist, 0.6, 0.05, 5.0);                      // dense near the surface
///   elasticity_density_field rho(linear_field{2, 0.05, 0.4, 0, 30}, 0.25, 0.05, 0.4);  // E/Es -> seeds/mm^3
///   voronoi_foam foam(rho, constant_field{0.25}, {.cell = 3});
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/elasticity.hpp"
#include "fabsynth/foam/fields.hpp"
#include "fabsynth/geometry/distance.hpp"

namespace fabsynth::foam {

/// A grayscale image stretched over the rectangle [x0, x1] x [y0, y1] (mm) of every plane z = const,
/// as seen from +z: column 0 at x0, row 0 at y1 (the top of the picture). Value at (x, y, z):
/// v0 + (v1 - v0) g / 255, where g is channel 0 of the pixel holding (x, y) (nearest pixel, no
/// interpolation); outside the rectangle, of the nearest border pixel. Copies share the image.
class image_field {
public:
    /// @param image  any size >= 1 x 1, any channel count (channel 0 is read)
    /// @param rect   finite, lo < hi on both axes, mm
    /// @param v0,v1  values at grey 0 and grey 255 (finite; e.g. seeds/mm^3 or E/Es)
    image_field(image8 image, const box2& rect, double v0, double v1)
        : img_(std::make_shared<const image8>(std::move(image))), rect_(rect), v0_(v0), v1_(v1) {
        if (img_->width < 1 || img_->height < 1 || img_->channels < 1)
            throw invalid_input("foam image_field: the image is empty");
        if (!all_finite(rect.lo) || !all_finite(rect.hi) || !(rect.lo.x < rect.hi.x) || !(rect.lo.y < rect.hi.y))
            throw invalid_input("foam image_field: the rectangle must be finite with x0 < x1 and y0 < y1");
        require_finite(v0, "foam image_field value v0"), require_finite(v1, "foam image_field value v1");
    }
    [[nodiscard]] double operator()(const vec3& p) const {
        const double u = std::clamp((p.x - rect_.lo.x) / (rect_.hi.x - rect_.lo.x), 0.0, 1.0);
        const double v = std::clamp((rect_.hi.y - p.y) / (rect_.hi.y - rect_.lo.y), 0.0, 1.0);
        const int i = std::min(img_->width - 1, static_cast<int>(u * img_->width));
        const int j = std::min(img_->height - 1, static_cast<int>(v * img_->height));
        return v0_ + (v1_ - v0_) * img_->at(i, j, 0) / 255.0;
    }
    [[nodiscard]] double max_value() const noexcept { return std::max(v0_, v1_); }
    [[nodiscard]] const image8& image() const noexcept { return *img_; }
    [[nodiscard]] const box2& rect() const noexcept { return rect_; }

private:
    std::shared_ptr<const image8> img_;
    box2 rect_;
    double v0_, v1_;
};

/// Graded by the (unsigned) distance d to a mesh surface: v_near at the surface, linear in d to
/// v_far at d = depth, v_far beyond: v_near + (v_far - v_near) min(d / depth, 1). Unsigned, so it
/// grades both sides of the surface alike. Holds a reference: the mesh_distance must outlive it.
/// Cost: one closest-point query bounded by depth per call.
class surface_distance_field {
public:
    /// @param depth  > 0, mm; v_near, v_far finite
    surface_distance_field(const mesh_distance& surface, double v_near, double v_far, double depth)
        : surface_(&surface), v_near_(v_near), v_far_(v_far), depth_(depth) {
        require_finite(v_near, "foam surface_distance_field value at the surface");
        require_finite(v_far, "foam surface_distance_field value at depth");
        require_positive(depth, "foam surface_distance_field depth");
    }
    [[nodiscard]] double operator()(const vec3& p) const {
        const double d = std::sqrt(surface_->closest(p, depth_).dist2);  // inf beyond depth
        const double t = std::isfinite(d) ? d / depth_ : 1.0;
        return v_near_ + (v_far_ - v_near_) * t;
    }
    [[nodiscard]] double max_value() const noexcept { return std::max(v_near_, v_far_); }

private:
    const mesh_distance* surface_;
    double v_near_, v_far_, depth_;
};

/// Seed density (seeds/mm^3) that gives a foam of beam radius tau the relative Young's modulus
/// E/Es = e(x) of an elasticity field e, through the shipped fit (elasticity.hpp: the inverse
/// inverse_fitted_elasticity(e, tau) of §4.2). The inverse is tabulated at `nodes` evenly spaced
/// moduli over [e_lo, e_hi] (the range the field's values are expected in) and interpolated
/// linearly between them (exact at the nodes); e outside [e_lo, e_hi] is clamped to it, and moduli
/// the fit cannot reach at tau (outside reachable()) map to the ends of the fitted density band.
/// Copies share the table.
template <scalar_field Elasticity>
class elasticity_density_field {
public:
    /// @param e      field of E/Es values
    /// @param tau    beam radius, mm, inside the fit's sampled radii (else invalid_input)
    /// @param e_lo,e_hi  finite, e_lo <= e_hi (equal ends are widened by 1e-12)
    /// @param nodes  table size, >= 2
    elasticity_density_field(Elasticity e, double tau, double e_lo, double e_hi, std::size_t nodes = 257)
        : e_(std::move(e)), tau_(tau), e_lo_(e_lo), e_hi_(e_hi) {
        require_finite(e_lo, "foam elasticity_density_field e_lo"), require_finite(e_hi, "foam elasticity_density_field e_hi");
        if (e_lo > e_hi) throw invalid_input("foam elasticity_density_field: e_lo must be <= e_hi");
        if (nodes < 2) throw invalid_input("foam elasticity_density_field: the table needs >= 2 nodes");
        if (e_hi_ == e_lo_) e_hi_ = e_lo_ + 1e-12;
        auto t = std::make_shared<std::vector<double>>(nodes);
        for (std::size_t i = 0; i < t->size(); ++i) {
            const double target = e_lo_ + (e_hi_ - e_lo_) * static_cast<double>(i) / static_cast<double>(nodes - 1);
            (*t)[i] = inverse_fitted_elasticity(target, tau_).density;  // throws if tau was not sampled
        }
        table_ = std::move(t);
    }
    [[nodiscard]] double operator()(const vec3& p) const {
        const double v = static_cast<double>(e_(p));
        const std::vector<double>& t = *table_;
        const double s = std::clamp((v - e_lo_) / (e_hi_ - e_lo_), 0.0, 1.0) * static_cast<double>(t.size() - 1);
        const auto i = std::min(t.size() - 2, static_cast<std::size_t>(s));
        return t[i] + (t[i + 1] - t[i]) * (s - static_cast<double>(i));
    }
    /// The largest tabulated density (the interpolation never exceeds it).
    [[nodiscard]] double max_value() const noexcept { return *std::max_element(table_->begin(), table_->end()); }
    /// [E(rho_lo), E(rho_hi)] of the fitted density band at tau: the moduli the fit can reach.
    [[nodiscard]] std::pair<double, double> reachable() const {
        const elasticity_polynomial model = fitted_elasticity();
        const auto [rho_lo, rho_hi] = fitted_density_range(tau_);
        return {model(rho_lo, tau_), model(rho_hi, tau_)};
    }
    [[nodiscard]] double radius() const noexcept { return tau_; }
    [[nodiscard]] double e_lo() const noexcept { return e_lo_; }
    [[nodiscard]] double e_hi() const noexcept { return e_hi_; }  ///< after the widening of equal ends
    [[nodiscard]] const Elasticity& elasticity() const noexcept { return e_; }

private:
    Elasticity e_;
    double tau_, e_lo_, e_hi_;
    std::shared_ptr<const std::vector<double>> table_;
};

static_assert(bounded_field<image_field>);
static_assert(bounded_field<surface_distance_field>);
static_assert(bounded_field<elasticity_density_field<constant_field>>);

}  // namespace fabsynth::foam
