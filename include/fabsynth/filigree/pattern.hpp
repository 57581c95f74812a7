// SPDX-License-Identifier: MIT
#pragma once
/// @file pattern.hpp  Placed element instances and their world geometry (filigree-synthesis.md
/// §4): an instance is an element class at a reference point, rotated and scaled by the control
/// field there, with its own (possibly deformed, §4.3.2) skeleton.
///
/// Usage:
///   fabsynth::filigree::instance in = fabsynth::filigree::make_instance(classes, 0, {10, 20}, field);
///   fabsynth::filigree::placed p = fabsynth::filigree::place(classes[in.cls], in);
///   p.vertices;  p.covering;  p.box;          // mm, domain frame
///   bool inside = p.covers({12, 21});         // in the covering region
///
/// Instance frame: world = position + scale * R(rotation) * local, R counter-clockwise (y up).
/// The covering region follows the rigid transform only (deformations are small, σ_d bounded).
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/filigree/element.hpp"
#include "fabsynth/filigree/field.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth::filigree {

/// One element instance.
struct instance {
    std::uint32_t cls = 0;      ///< element class index
    vec2 position{0, 0};        ///< reference point, mm
    double rotation = 0.0;      ///< radians
    double scale = 1.0;         ///< factor
    std::vector<vec2> shape;    ///< skeleton vertices in the element frame (deformed copy of element::vertices)
};

/// World position of element-frame point `local` of instance `in`.
[[nodiscard]] inline vec2 to_world(const instance& in, vec2 local) noexcept {
    const double c = std::cos(in.rotation), s = std::sin(in.rotation);
    return in.position + in.scale * vec2(c * local.x - s * local.y, s * local.x + c * local.y);
}
/// Element-frame point of world point `world` (inverse of to_world).
[[nodiscard]] inline vec2 to_local(const instance& in, vec2 world) noexcept {
    const double c = std::cos(in.rotation), s = std::sin(in.rotation);
    const vec2 d = (world - in.position) / in.scale;
    return {c * d.x + s * d.y, -s * d.x + c * d.y};
}

/// An instance of class `cls` at `position`, rotated and scaled by `field` there (§4.1), undeformed.
template <control_field F>
[[nodiscard]] instance make_instance(std::span<const element> classes, std::uint32_t cls, vec2 position, const F& field) {
    const field_sample f = field(position);
    return {cls, position, f.rotation, f.scale, classes[cls].vertices};
}

/// World geometry of an instance.
struct placed {
    std::vector<vec2> vertices;   ///< skeleton vertices (mm)
    const std::vector<skeleton_edge>* edges = nullptr;  ///< the element's skeleton edges (indices into vertices); the element outlives this
    std::vector<ring2> covering;  ///< convex covering parts (mm)
    std::vector<box2> part_boxes; ///< one per covering part
    box2 box;                     ///< bounds of the covering region

    /// True if p lies in the covering region (boundary included).
    [[nodiscard]] bool covers(vec2 p) const noexcept {
        if (p.x < box.lo.x || p.y < box.lo.y || p.x > box.hi.x || p.y > box.hi.y) return false;
        for (std::size_t k = 0; k < covering.size(); ++k) {
            const box2& b = part_boxes[k];
            if (p.x < b.lo.x || p.y < b.lo.y || p.x > b.hi.x || p.y > b.hi.y) continue;
            if (convex_contains(covering[k], p)) return true;
        }
        return false;
    }
    // Convex counter-clockwise ring: inside iff left of (or on) every edge.
    [[nodiscard]] static bool convex_contains(const ring2& r, vec2 p) noexcept {
        for (std::size_t i = 0, n = r.size(); i < n; ++i)
            if (orient2d(r[i], r[(i + 1) % n], p) < 0) return false;
        return true;
    }
};

/// The world geometry of `in` (an instance of `e`).
[[nodiscard]] inline placed place(const element& e, const instance& in) {
    placed p;
    p.edges = &e.edges;
    p.vertices.reserve(in.shape.size());
    for (const vec2& v : in.shape) p.vertices.push_back(to_world(in, v));
    for (const ring2& r : e.covering) {
        ring2 w;
        box2 b;
        for (const vec2& q : r) w.push_back(to_world(in, q)), b.extend(w.back());
        p.covering.push_back(std::move(w));
        p.part_boxes.push_back(b);
        p.box.extend(b);
    }
    return p;
}

/// Area (mm^2) of the overlap of the covering regions of a and b, summed over pairs of convex
/// parts: exact for one-part regions, an upper bound when parts of one element overlap each other.
[[nodiscard]] inline double covering_overlap(const placed& a, const placed& b) {
    double sum = 0;
    for (std::size_t i = 0; i < a.covering.size(); ++i)
        for (std::size_t j = 0; j < b.covering.size(); ++j)
            if (a.part_boxes[i].intersects(b.part_boxes[j])) sum += convex_intersection_area(a.covering[i], b.covering[j]);
    return sum;
}

/// True if the boxes of two placed instances intersect (a cheap necessary test for overlap).
[[nodiscard]] inline bool boxes_meet(const placed& a, const placed& b) noexcept {
    return !(a.box.hi.x < b.box.lo.x || b.box.hi.x < a.box.lo.x || a.box.hi.y < b.box.lo.y || b.box.hi.y < a.box.lo.y);
}

}  // namespace fabsynth::filigree
