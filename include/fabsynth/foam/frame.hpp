// SPDX-License-Identifier: MIT
#pragma once
/// @file frame.hpp  A foam inside a closed mesh with a solid frame (shell) following its surface
/// (paper §5.3), optionally cut open by planes that get no frame (paper Fig. 17).
///
/// Object O = interior of the mesh intersected with the kept side dot(x - point, normal) <= 0 of
/// every cut plane. A point q of O is solid iff it is within `thickness` of the mesh surface
/// (the frame: -thickness <= signed distance <= 0) or the foam contains it. Outside O nothing is
/// solid. The frame follows the mesh surface only, so a cut face shows the open foam. The join
/// is seamless: every beam reaching the surface runs into the frame, and the union is one
/// connected solid (tests/foam/frame.cpp checks this on a voxelized block).
///
/// Inside/outside: contains() uses the pseudonormal sign of geometry/distance.hpp; slice() uses an
/// exact even-odd scanline of the mesh cross-section (geometry/raster.hpp; vertices on the plane count as above it),
/// which agrees except within rounding (~1e-12 mm) of the surface. A non-watertight mesh throws
/// invalid_input at construction. With supersampling, the object boundary and the frame are
/// decided at pixel centres and the foam inside is graded.
///
/// Usage:
///   fabsynth::mesh_distance md(mesh);
///   fabsynth::foam::framed_foam obj(foam, md, {.thickness = 0.6});
///   fabsynth::image8 s = obj.slice(z, region, 0.05);
#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/evaluator.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/raster.hpp"

namespace fabsynth::foam {

/// Plane through `point` with `normal`; the object keeps dot(x - point, normal) <= 0.
struct cut_plane {
    vec3 point{0};
    vec3 normal{0, 0, 1};
};

/// Frame parameters.
struct frame_options {
    double thickness = 0.5;        ///< shell thickness, mm (> 0); 0 < thickness means frame on
    std::vector<cut_plane> cuts;   ///< planes that cut the object open without a frame
};

/// Foam + surface frame inside a closed mesh. Holds references: foam and surface must outlive it.
template <class Foam>
class framed_foam {
public:
    framed_foam(const Foam& foam, const mesh_distance& surface, frame_options opt)
        : foam_(foam), surface_(surface), opt_(std::move(opt)) {
        surface_.require_watertight();
        if (!(std::isfinite(opt_.thickness) && opt_.thickness >= 0))
            throw invalid_input("foam frame thickness must be finite and >= 0 mm, got " + std::to_string(opt_.thickness));
        for (auto& c : opt_.cuts) {
            if (!all_finite(c.point) || !all_finite(c.normal) || glm::length(c.normal) == 0)
                throw invalid_input("foam cut plane must have a finite point and a non-zero normal");
            c.normal = glm::normalize(c.normal);
        }
    }

    [[nodiscard]] const frame_options& options() const noexcept { return opt_; }
    [[nodiscard]] const Foam& foam() const noexcept { return foam_; }
    [[nodiscard]] const mesh_distance& surface() const noexcept { return surface_; }

    /// True iff q is kept by every cut plane.
    [[nodiscard]] bool kept_by_cuts(const vec3& q) const noexcept {
        for (const auto& c : opt_.cuts)
            if (glm::dot(q - c.point, c.normal) > 0) return false;
        return true;
    }

    /// Solid at q (frame or foam, inside the object).
    [[nodiscard]] bool contains(const vec3& q) const {
        if (!kept_by_cuts(q)) return false;
        const mesh_closest c = surface_.closest(q);
        if (surface_.sign_of(q, c) > 0) return false;
        if (c.dist2 <= opt_.thickness * opt_.thickness) return true;
        return foam_.contains(q);
    }

    /// Signed implicit of the solid (mm), negative inside, positive outside, for meshing
    /// (frame_mesh.hpp):
    ///   g(q) = max(sd(q), max_c n_c.(q - p_c), min(frame(q), foam(q)))
    /// with sd the signed distance to the mesh (< 0 inside), n_c the unit normal of cut c,
    /// frame(q) = -(sd(q) + thickness) (1e9 without a frame) and foam(q) = min(d(q), reach) - tau(q),
    /// d the distance to the foam's Voronoi edges. g(q) < 0 agrees with contains(q) except on ties
    /// (g = 0) and within rounding of the surface. `reach` (mm, tau(q) < reach <= cell) caps the
    /// edge search: beyond reach from every edge the foam term is the constant reach - tau.
    [[nodiscard]] double implicit(const vec3& q, double reach) const {
        const double sd = surface_.signed_distance(q);
        double v = sd;
        for (const auto& c : opt_.cuts) v = std::max(v, glm::dot(q - c.point, c.normal));  // unit normals
        const double fd = foam_.distance_to_edges(q, reach);
        const double foam_v = (std::isfinite(fd) ? fd : reach) - foam_.radius(q);
        const double frame_v = opt_.thickness > 0 ? -(sd + opt_.thickness) : 1e9;
        return std::max(v, std::min(frame_v, foam_v));
    }

    /// Slice at height z (same pixel layout as voronoi_foam::slice).
    [[nodiscard]] image8 slice(double z, const box2& region, double pixel, slice_options so = {}) const {
        const auto [w, h] = Foam::slice_size(region, pixel);
        image8 img(w, h, 1, 0);
        slice_into(img, z, region.lo, pixel, so);
        return img;
    }

    void slice_into(image8& img, double z, const vec2& origin, double pixel, slice_options so = {}) const {
        foam_.slice_into(img, z, origin, pixel, so);
        add_section(img, z, origin, pixel);
    }

    /// A stack of slices at the increasing heights zs (mm), each as slice() gives it, handed to
    /// emit(k, img) in order (the foam's for_each_slice: its edges built once per slab).
    template <class Emit>
    void for_each_slice(std::span<const double> zs, const box2& region, double pixel, Emit&& emit, slice_options so = {}) const {
        foam_.for_each_slice(zs, region, pixel, [&](std::size_t k, image8& img) {
            add_section(img, zs[k], region.lo, pixel);
            emit(k, img);
        }, so);
    }

private:
    // Keeps the foam of img inside the mesh (and its cuts) and adds the frame shell.
    void add_section(image8& img, double z, const vec2& origin, double pixel) const {
        // cross-section of the mesh: segments where faces straddle the plane, filled even-odd
        polygon_rasterizer section;
        const auto& m = surface_.mesh();
        for (const auto& t : m.faces) {
            vec2 pts[2];
            int n = 0;
            for (int k = 0; k < 3 && n < 2; ++k) {
                const vec3 p = m.vertices[t[static_cast<std::size_t>(k)]];
                const vec3 q = m.vertices[t[static_cast<std::size_t>((k + 1) % 3)]];
                if ((p.z > z) != (q.z > z)) {
                    const double s = (z - p.z) / (q.z - p.z);
                    pts[n++] = vec2(p.x + s * (q.x - p.x), p.y + s * (q.y - p.y));
                }
            }
            if (n == 2) section.add_edge(pts[0], pts[1]);
        }
        const raster_grid grid{origin, pixel, img.width, img.height};
        const double th = opt_.thickness;
        parallel_for(0, static_cast<std::size_t>(img.height), [&](std::size_t row) {
            const int j = static_cast<int>(row);
            const double y = grid.row_y(j);
            std::vector<polygon_rasterizer::crossing> scratch;
            int outside_from = 0;  // columns before the next inside run are outside the object
            auto inside_run = [&](int i0, int i1) {
                for (int i = outside_from; i < i0; ++i) img.at(i, j) = 0;
                for (int i = i0; i < i1; ++i) {
                    const vec3 q(origin.x + (i + 0.5) * pixel, y, z);
                    if (!kept_by_cuts(q)) img.at(i, j) = 0;
                    else if (th > 0 && surface_.closest(q, th).found()) img.at(i, j) = 255;
                }
                outside_from = i1;
            };
            section.row_runs(grid, j, scratch, inside_run);
            for (int i = outside_from; i < img.width; ++i) img.at(i, j) = 0;
        }, {.grain = 4});
    }

    const Foam& foam_;
    const mesh_distance& surface_;
    frame_options opt_;
};

}  // namespace fabsynth::foam
