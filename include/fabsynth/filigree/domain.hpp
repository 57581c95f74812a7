// SPDX-License-Identifier: MIT
#pragma once
/// @file domain.hpp  The planar region a filigree fills (filigree-synthesis.md §3.2, §7.2
/// "boundary-aware synthesis"): a rectangle, or the filled shapes of an SVG drawing (polygons with
/// holes), in mm.
///
/// Usage:
///   auto d = fabsynth::filigree::planar_domain::rectangle(80, 60);
///   auto e = fabsynth::filigree::planar_domain::from_svg(fabsynth::io::read_svg("frame.svg"));  // the driver reads
///   d.contains({10, 10});  d.area;  d.boundary_samples(0.5);
///
/// SVG domains: every filled shape (fill not "none") contributes its rings with its fill rule, the
/// shapes are united; SVG user units are taken as mm. Throws invalid_input for a rectangle that is
/// not finite and > 0, or a drawing without filled area.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/filigree/element.hpp"

namespace fabsynth::filigree {

/// The domain as the synthesis steps see it in one 2D frame (mm): a membership test and the
/// boundary as polylines. A planar domain is its own frame (planar_domain::frame()); on a surface
/// every instance's neighbourhood gets one, in its local parameterization (surface_space.hpp).
struct local_domain {
    std::function<bool(vec2)> inside;           ///< true for points of the domain
    std::vector<std::vector<vec2>> boundary;    ///< boundary polylines (mm)
    std::vector<bool> closed;                   ///< per polyline: a closed ring
    /// Element sets per region: whether an instance of class `cls` may have its reference point at
    /// p (mm, this frame); empty: every class everywhere.
    std::function<bool(std::uint32_t cls, vec2 p)> class_allowed;

    [[nodiscard]] bool contains(vec2 p) const { return inside(p); }
    /// p lies in the domain and class `cls` may be placed there.
    [[nodiscard]] bool admits(std::uint32_t cls, vec2 p) const { return inside(p) && (!class_allowed || class_allowed(cls, p)); }

    /// Points along every boundary polyline, at most `spacing` mm apart (its vertices included).
    [[nodiscard]] std::vector<vec2> boundary_samples(double spacing) const {
        std::vector<vec2> out;
        for (std::size_t r = 0; r < boundary.size(); ++r) {
            const auto& line = boundary[r];
            const std::size_t n = line.size(), segs = closed[r] ? n : (n ? n - 1 : 0);
            for (std::size_t i = 0; i < segs; ++i) {
                const vec2 a = line[i], b = line[(i + 1) % n];
                const int k = std::max(1, static_cast<int>(std::ceil(glm::distance(a, b) / spacing)));
                for (int t = 0; t < k; ++t) out.push_back(a + (b - a) * (static_cast<double>(t) / k));
            }
            if (!closed[r] && n) out.push_back(line.back());
        }
        return out;
    }
};

/// A region of the plane (mm): polygons with holes, outer rings counter-clockwise.
struct planar_domain {
    std::vector<polygon_with_holes> region;
    box2 bounds;
    double area = 0.0;  ///< mm^2
    /// Element sets per region (e.g. from a label picture): whether class `cls` may have an
    /// instance's reference point at p (mm); empty: every class everywhere. Initialization draws,
    /// placement and boosting moves and the insertions of §5 keep to it.
    std::function<bool(std::uint32_t cls, vec2 p)> class_allowed;

    /// [0, width] x [0, height] (mm).
    [[nodiscard]] static planar_domain rectangle(double width, double height) {
        if (!(std::isfinite(width) && std::isfinite(height) && width > 0 && height > 0))
            throw invalid_input("domain: the rectangle must have a finite, positive width and height (mm)");
        return from_polygons({polygon_with_holes{ring2{{0, 0}, {width, 0}, {width, height}, {0, height}}, {}}});
    }

    /// The union of the filled shapes of `doc` (user units = mm).
    template <svg_like_document Doc>
    [[nodiscard]] static planar_domain from_svg(const Doc& doc, const std::string& name = "domain") {
        std::vector<polygon_with_holes> all;
        bool any_filled = false;
        for (const auto& s : doc.shapes) {
            if (!s.filled()) continue;
            any_filled = true;
            std::vector<ring2> r;
            for (const auto& sp : s.subpaths)
                if (sp.size() >= 3) r.emplace_back(sp.begin(), sp.end());
            if (r.empty()) continue;
            const auto u = polygon_union(r, s.rule);
            all.insert(all.end(), u.begin(), u.end());
        }
        if (all.empty())
            throw invalid_input(name + (any_filled ? ": the domain has zero area" : ": the SVG has no filled shape to use as the domain"));
        return from_polygons(polygon_union(all, {}));
    }

    /// From polygons (united first).
    [[nodiscard]] static planar_domain from_polygons(std::vector<polygon_with_holes> polys, const std::string& name = "domain") {
        planar_domain d;
        d.region = std::move(polys);
        d.area = fabsynth::area(d.region);
        if (!(d.area > 0)) throw invalid_input(name + ": the domain has zero area");
        d.bounds = bounding_box(d.region);
        return d;
    }

    /// True for points inside (or on the boundary of) the region.
    [[nodiscard]] bool contains(vec2 p) const noexcept {
        if (p.x < bounds.lo.x || p.y < bounds.lo.y || p.x > bounds.hi.x || p.y > bounds.hi.y) return false;
        for (const polygon_with_holes& poly : region)
            if (point_in_polygon(poly, p)) return true;
        return false;
    }

    /// This domain as its own synthesis frame (the region is copied into the membership test).
    [[nodiscard]] local_domain frame() const {
        local_domain f;
        f.inside = [d = std::make_shared<const planar_domain>(*this)](vec2 p) { return d->contains(p); };
        f.class_allowed = class_allowed;
        for (const polygon_with_holes& p : region) {
            f.boundary.emplace_back(p.outer.begin(), p.outer.end()), f.closed.push_back(true);
            for (const ring2& h : p.holes) f.boundary.emplace_back(h.begin(), h.end()), f.closed.push_back(true);
        }
        return f;
    }
};

namespace detail::domain {

// Per class the labels (0-255) it may lie on: every label when its list is empty, else those
// listed. `present[g]`: some pixel or face has label g; a listed label outside 0-255 or absent
// throws invalid_input with missing(g, c).
template <class Missing>
[[nodiscard]] std::vector<std::array<bool, 256>> class_label_table(const std::array<bool, 256>& present, const std::vector<std::vector<int>>& class_labels,
                                                                   Missing&& missing) {
    std::vector<std::array<bool, 256>> allowed(class_labels.size());
    for (std::size_t c = 0; c < class_labels.size(); ++c) {
        allowed[c].fill(class_labels[c].empty());
        for (const int g : class_labels[c]) {
            if (g < 0 || g > 255 || !present[static_cast<std::size_t>(g)]) throw invalid_input(missing(g, c));
            allowed[c][static_cast<std::size_t>(g)] = true;
        }
    }
    return allowed;
}

}  // namespace detail::domain

/// Element sets per region from a label picture (for planar_domain::class_allowed): `labels` is a
/// grayscale picture stretched over `extent` (mm; pixel row 0 at extent.lo.y, nearest pixel,
/// clamped outside); class c may lie at p when class_labels[c] is empty (everywhere) or holds the
/// grey level there. Throws invalid_input, naming `name`, for a picture that is empty or not
/// grayscale, an empty extent, or a grey level outside 0-255 or absent from the picture.
[[nodiscard]] inline std::function<bool(std::uint32_t, vec2)> label_regions(image8 labels, const box2& extent,
                                                                            const std::vector<std::vector<int>>& class_labels,
                                                                            const std::string& name = "label picture") {
    if (labels.empty() || labels.channels != 1) throw invalid_input(name + ": the label picture must be a non-empty grayscale image");
    if (extent.empty() || !(extent.hi.x > extent.lo.x && extent.hi.y > extent.lo.y)) throw invalid_input(name + ": the extent is empty");
    std::array<bool, 256> present{};
    for (const std::uint8_t v : labels.data) present[v] = true;
    auto allowed = detail::domain::class_label_table(present, class_labels, [&](int g, std::size_t c) {
        return name + ": no pixel has grey level " + std::to_string(g) + ", which element class " + std::to_string(c) + " asks for";
    });
    return [labels = std::move(labels), extent, allowed = std::move(allowed)](std::uint32_t cls, vec2 p) {
        const vec2 f = (p - extent.lo) / (extent.hi - extent.lo);
        const int x = std::clamp(static_cast<int>(std::floor(f.x * labels.width)), 0, labels.width - 1);
        const int y = std::clamp(static_cast<int>(std::floor(f.y * labels.height)), 0, labels.height - 1);
        return cls < allowed.size() && allowed[cls][labels.at(x, y)];
    };
}

}  // namespace fabsynth::filigree
