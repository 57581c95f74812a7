// SPDX-License-Identifier: MIT
#pragma once
/// @file field.hpp  Control fields on a base surface (filigree-synthesis.md §7.2, §8.1,
/// Fig. 16): at every surface point, the tangent direction an element's up axis follows and the
/// scale it takes. The surface counterpart of field.hpp (issue 15 builds the surface pipeline on
/// it; the local parameterization of surface/exponential_map.hpp turns a direction into the
/// element's rotation in the patch's (u, v) frame).
///
/// Usage:
///   fabsynth::surface_patcher patcher(mesh);
///   auto dir = fabsynth::filigree::surface_direction_field::from_up_vector(patcher, {0, 0, 1});
///   auto dir2 = fabsynth::filigree::surface_direction_field::from_constraints(patcher, {{v0, {1, 0, 0}}, {v1, {0, 1, 0}}}, {0, 0, 1});
///   fabsynth::filigree::surface_scale_field scale = fabsynth::filigree::surface_scale_field::constant(mesh, 1.0);
///   fabsynth::filigree::surface_control field{&dir, &scale};
///   fabsynth::filigree::surface_field_sample s = field({face, bary});   // s.direction (unit, tangent), s.scale
///
/// Directions are stored per vertex as 3D vectors and blended barycentrically inside a face, then
/// projected into the face's plane and normalised. from_up_vector: the up vector projected into
/// the tangent plane (the paper's default: "each pattern has an up vector"). Where the up vector is
/// (nearly) along the normal, e.g. the top of a vase, the projection vanishes; there the projection
/// of a second axis (the coordinate axis least aligned with up) is used, so every point has a
/// direction, with a visible turn around such a pole (any tangent field on a sphere has one).
/// from_constraints: the per-vertex vectors harmonically interpolated from user directions at
/// vertices (surface/laplacian.hpp, cotangent weights, one solve for the three
/// coordinates): a smooth field through the constraints. The paper uses Diamanti et al. 2014's
/// PolyVector fields, which also handle line (2-fold) symmetries; an element's up axis is a
/// vector, not a line, so a 1-vector field interpolated in 3D and projected suffices here.
/// Vertices of components without a constraint take the up-vector field.
///
/// Scale fields: constant, or per vertex (blended barycentrically), each value finite and > 0.
///
/// Errors: invalid_input naming the input for a constraint vertex out of range, a non-finite or
/// zero constraint direction, a non-finite or zero up vector, a per-vertex scale count that is not
/// the vertex count, or a scale that is not finite and > 0.
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/surface/exponential_map.hpp"
#include "fabsynth/surface/laplacian.hpp"

namespace fabsynth::filigree {

/// Direction (unit vector in the tangent plane of the point's face) and scale (factor) at one point.
struct surface_field_sample {
    vec3 direction{1, 0, 0};
    double scale = 1.0;
};

/// A user direction at a mesh vertex (any vector; its tangent part is what counts).
struct direction_constraint {
    std::uint32_t vertex = 0;
    vec3 direction{1, 0, 0};
};

namespace detail::surface_field {
inline void require_direction(vec3 d, const std::string& what) {
    const double l = glm::length(d);
    if (!(std::isfinite(l) && l > 0)) throw invalid_input(what + " must be finite and non-zero");
}
// u projected into the plane of unit normal n (zero if u is along n).
[[nodiscard]] inline vec3 tangent_part(vec3 u, vec3 n) { return u - glm::dot(u, n) * n; }
}  // namespace detail::surface_field

/// A tangent direction field stored per vertex (see the file comment).
class surface_direction_field {
public:
    /// The up vector projected into each tangent plane, with the fallback axis near poles.
    [[nodiscard]] static surface_direction_field from_up_vector(const surface_patcher& patcher, vec3 up) {
        detail::surface_field::require_direction(up, "surface direction field: the up vector");
        surface_direction_field f(patcher);
        f.up_ = glm::normalize(up);
        f.per_vertex_.assign(patcher.mesh().num_vertices(), f.up_);
        return f;
    }

    /// Harmonic interpolation of the constraints (vertex ids into the patcher's mesh); vertices of
    /// components without a constraint follow `up`.
    [[nodiscard]] static surface_direction_field from_constraints(const surface_patcher& patcher, std::span<const direction_constraint> constraints,
                                                                  vec3 up) {
        const triangle_mesh& m = patcher.mesh();
        surface_direction_field f = from_up_vector(patcher, up);
        std::vector<std::uint32_t> fixed;
        Eigen::MatrixXd values(static_cast<Eigen::Index>(constraints.size()), 3);
        for (std::size_t k = 0; k < constraints.size(); ++k) {
            const direction_constraint& c = constraints[k];
            const std::string who = "surface direction field: constraint " + std::to_string(k);
            if (c.vertex >= m.num_vertices())
                throw invalid_input(who + " names vertex " + std::to_string(c.vertex) + ", out of range for " + std::to_string(m.num_vertices()));
            detail::surface_field::require_direction(c.direction, who + "'s direction");
            const vec3 n = patcher.normals()[c.vertex];
            vec3 t = detail::surface_field::tangent_part(c.direction, n);
            if (!(glm::length(t) > 1e-9 * glm::length(c.direction))) throw invalid_input(who + "'s direction is along the surface normal");
            t = glm::normalize(t);
            fixed.push_back(c.vertex);
            values.row(static_cast<Eigen::Index>(k)) << t.x, t.y, t.z;
        }
        if (fixed.empty()) return f;
        const Eigen::MatrixXd x = harmonic_interpolation(m, fixed, values);
        for (std::size_t v = 0; v < m.num_vertices(); ++v) {
            const auto r = static_cast<Eigen::Index>(v);
            if (std::isfinite(x(r, 0))) f.per_vertex_[v] = vec3(x(r, 0), x(r, 1), x(r, 2));
        }
        return f;
    }

    /// Unit tangent direction at a surface point (in the plane of its face).
    [[nodiscard]] vec3 operator()(const surface_point& s) const {
        const auto& c = patcher_->mesh().faces[s.face];
        const vec3 n = patcher_->face_normal(s.face);
        const vec3 blended = s.bary.x * per_vertex_[c[0]] + s.bary.y * per_vertex_[c[1]] + s.bary.z * per_vertex_[c[2]];
        for (const vec3& u : {blended, up_, second_axis()}) {
            const vec3 t = detail::surface_field::tangent_part(u, n);
            if (glm::length(t) > 1e-6 * std::max(1.0, glm::length(u))) return glm::normalize(t);
        }
        return glm::normalize(detail::surface_field::tangent_part(vec3(0, 0, 1), n) + detail::surface_field::tangent_part(vec3(1, 0, 0), n));
    }

    /// The stored per-vertex vectors (not projected).
    [[nodiscard]] const std::vector<vec3>& per_vertex() const noexcept { return per_vertex_; }

private:
    explicit surface_direction_field(const surface_patcher& p) : patcher_(&p) {}
    // the coordinate axis least aligned with up
    [[nodiscard]] vec3 second_axis() const {
        const vec3 a = glm::abs(up_);
        return a.x <= a.y && a.x <= a.z ? vec3(1, 0, 0) : a.y <= a.z ? vec3(0, 1, 0) : vec3(0, 0, 1);
    }
    const surface_patcher* patcher_;
    vec3 up_{0, 0, 1};
    std::vector<vec3> per_vertex_;
};

/// A scale field on a surface: per-vertex factors blended barycentrically.
class surface_scale_field {
public:
    [[nodiscard]] static surface_scale_field constant(const triangle_mesh& m, double scale) {
        return per_vertex(m, std::vector<double>(m.num_vertices(), scale));
    }
    /// One factor per vertex of m (e.g. read from the CLI's --field-scale-file).
    [[nodiscard]] static surface_scale_field per_vertex(const triangle_mesh& m, std::vector<double> scales) {
        if (scales.size() != m.num_vertices())
            throw invalid_input("surface scale field: " + std::to_string(scales.size()) + " values for " + std::to_string(m.num_vertices()) + " vertices");
        for (std::size_t v = 0; v < scales.size(); ++v)
            if (!(std::isfinite(scales[v]) && scales[v] > 0))
                throw invalid_input("surface scale field: the value at vertex " + std::to_string(v) + " must be finite and > 0");
        surface_scale_field f;
        f.mesh_ = &m;
        f.values_ = std::move(scales);
        return f;
    }
    [[nodiscard]] double operator()(const surface_point& s) const {
        const auto& c = mesh_->faces[s.face];
        return s.bary.x * values_[c[0]] + s.bary.y * values_[c[1]] + s.bary.z * values_[c[2]];
    }
    /// The largest factor anywhere (a vertex value: the blend is convex).
    [[nodiscard]] double max() const { return values_.empty() ? 1.0 : *std::max_element(values_.begin(), values_.end()); }

private:
    const triangle_mesh* mesh_ = nullptr;
    std::vector<double> values_;
};

/// Direction and scale together: the surface control field the synthesis reads.
struct surface_control {
    const surface_direction_field* direction;
    const surface_scale_field* scale;
    [[nodiscard]] surface_field_sample operator()(const surface_point& s) const { return {(*direction)(s), (*scale)(s)}; }
};

}  // namespace fabsynth::filigree
