// SPDX-License-Identifier: MIT
#pragma once
/// @file space.hpp  Filigree synthesis on a base surface (filigree-synthesis.md §8.1: "all
/// computations are done on a locally parameterized 2D surface patch"): the surface pattern space
/// of the synthesis drivers (placement.hpp's pattern_space concept) and the surface
/// initialization. Part 1's steps run unchanged on pictures: for instance i, a pattern_state in
/// the exponential map around i's reference point (surface/exponential_map.hpp) holding i and
/// every instance whose reference point the map reaches, each rotated and scaled by the surface
/// control field where it sits.
///
/// Usage:
///   fabsynth::surface_patcher patcher(mesh);
///   auto region = fabsynth::filigree::surface_region::whole(patcher);        // or ::of_faces(patcher, ids)
///   fabsynth::filigree::surface_control field{&direction, &scale};           // surface_field.hpp
///   auto init = fabsynth::filigree::initialize_on_surface(classes, weights, region, field, {});
///   fabsynth::filigree::surface_space s(classes, init.instances, field, region);
///   fabsynth::filigree::synthesis_result_on_surface r;
///   fabsynth::filigree::optimize_layout(s, options, r);                       // synthesis.hpp
///
/// Frames. An instance is stored as its class, scale and (deformed) shape with its reference point
/// on the surface (surface_instance). Its element's up axis (+y of the element frame) follows the
/// direction field, so the picture of i is the map with the field direction at i as its v axis;
/// another instance j enters it at the (u, v) of its reference point, turned by the field
/// direction at j carried into the map by the affine map of j's face. On a plane the map is an
/// isometry, so a picture is the planar pattern translated: the surface path and the 2D path agree
/// up to rounding, except near the domain boundary, whose samples (Theta) and skeleton (boundary
/// contacts) are taken along the mesh's border edges in a picture and along the domain's rings in
/// the plane. Elsewhere elements are rigid in the picture of the instance being moved
/// (the paper's approximation; the map's distortion grows with the distance from i).
///
/// Pictures reach `view_reach` = 1.25 x i's covering reach + 2 x the largest covering reach (at
/// the largest scale of the field), so that i's neighbours and theirs are in them. Each instance
/// keeps its last map until it moves (the local parameterization dominates the time, Table 3).
/// A neighbour outside a picture (the map did not reach it) keeps the instance where it is.
///
/// The domain in a picture: the points whose face is in the region; its boundary the region's
/// border edges (mesh borders and the edges between region and other faces) met by the map.
///
/// Determinism: pictures are pure functions of the instances; the drivers' ordering rules apply.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/filigree/domain.hpp"
#include "fabsynth/filigree/element.hpp"
#include "fabsynth/filigree/initialization.hpp"
#include "fabsynth/filigree/matching.hpp"
#include "fabsynth/filigree/pattern.hpp"
#include "fabsynth/filigree/placement.hpp"
#include "fabsynth/filigree/surface/field.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/surface/exponential_map.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/sampling/dart_throwing.hpp"

namespace fabsynth::filigree {

/// The part of a mesh a filigree covers: a face mask, with the region's border edges per face.
struct surface_region {
    const surface_patcher* patcher = nullptr;
    std::vector<std::uint8_t> face_in;  ///< per mesh face: 1 in the region
    std::vector<std::uint8_t> border;   ///< per mesh face: bit k set if edge (corner k, corner k+1) is on the region's boundary
    std::vector<std::uint32_t> faces;   ///< the region's faces, increasing
    double area = 0;                    ///< mm^2
    /// Element sets per region on the mesh (Fig. 1c): whether an instance of class `cls` may have
    /// its reference point on mesh face `face`; empty: every class everywhere (face_label_regions
    /// builds one from a label per face). Initialization draws, placement and boosting moves and
    /// the insertions of §5 keep to it, as planar_domain::class_allowed in the plane.
    std::function<bool(std::uint32_t cls, std::uint32_t face)> class_allowed;

    /// Every face of the patcher's mesh.
    [[nodiscard]] static surface_region whole(const surface_patcher& p) {
        std::vector<std::uint32_t> all(p.mesh().faces.size());
        for (std::uint32_t f = 0; f < all.size(); ++f) all[f] = f;
        return of_faces(p, all);
    }
    /// The faces listed (mesh face ids; repeats allowed). Throws invalid_input for an id out of
    /// range or a region without area.
    [[nodiscard]] static surface_region of_faces(const surface_patcher& p, std::span<const std::uint32_t> ids, const std::string& name = "region") {
        const triangle_mesh& m = p.mesh();
        surface_region r;
        r.patcher = &p;
        r.face_in.assign(m.faces.size(), 0);
        for (const std::uint32_t f : ids) {
            if (f >= m.faces.size())
                throw invalid_input(name + ": face " + std::to_string(f) + " is out of range (the mesh has " + std::to_string(m.faces.size()) + " faces)");
            r.face_in[f] = 1;
        }
        std::unordered_map<std::uint64_t, int> uses;  // undirected edge -> region faces using it
        auto key = [](std::uint32_t a, std::uint32_t b) { return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b); };
        for (std::uint32_t f = 0; f < m.faces.size(); ++f)
            if (r.face_in[f]) {
                r.faces.push_back(f);
                r.area += triangle_area(m, f);
                for (int k = 0; k < 3; ++k) ++uses[key(m.faces[f][k], m.faces[f][(k + 1) % 3])];
            }
        if (!(r.area > 0)) throw invalid_input(name + ": the region has no area");
        r.border.assign(m.faces.size(), 0);
        for (const std::uint32_t f : r.faces)
            for (int k = 0; k < 3; ++k)
                if (uses[key(m.faces[f][k], m.faces[f][(k + 1) % 3])] == 1) r.border[f] |= static_cast<std::uint8_t>(1u << k);
        return r;
    }
    [[nodiscard]] bool contains(std::uint32_t face) const noexcept { return face < face_in.size() && face_in[face]; }
    /// Class `cls` may have an instance's reference point on `face` (see class_allowed).
    [[nodiscard]] bool allows(std::uint32_t cls, std::uint32_t face) const { return !class_allowed || class_allowed(cls, face); }

    [[nodiscard]] static double triangle_area(const triangle_mesh& m, std::uint32_t f) {
        const auto& c = m.faces[f];
        return 0.5 * glm::length(glm::cross(m.vertices[c[1]] - m.vertices[c[0]], m.vertices[c[2]] - m.vertices[c[0]]));
    }
};

/// Element sets per region on a mesh from a label per face (for surface_region::class_allowed;
/// the mesh counterpart of label_regions): `face_labels` holds one label in 0-255 per mesh face
/// (`face_count` of them, e.g. a face group's number); class c may lie on face f when
/// class_labels[c] is empty (everywhere) or holds face_labels[f]. Throws invalid_input, naming
/// `name`, for a count other than face_count, a label outside 0-255, or a class label no face has.
[[nodiscard]] inline std::function<bool(std::uint32_t, std::uint32_t)> face_label_regions(const std::vector<int>& face_labels, std::size_t face_count,
                                                                                         const std::vector<std::vector<int>>& class_labels,
                                                                                         const std::string& name = "face labels") {
    if (face_labels.size() != face_count)
        throw invalid_input(name + ": " + std::to_string(face_labels.size()) + " labels for a mesh of " + std::to_string(face_count) + " faces (one per face)");
    std::array<bool, 256> present{};
    std::vector<std::uint8_t> label(face_labels.size());
    for (std::size_t f = 0; f < face_labels.size(); ++f) {
        const int l = face_labels[f];
        if (l < 0 || l > 255) throw invalid_input(name + ": face " + std::to_string(f) + " has label " + std::to_string(l) + ", outside 0-255");
        present[static_cast<std::size_t>(l)] = true, label[f] = static_cast<std::uint8_t>(l);
    }
    auto allowed = detail::domain::class_label_table(present, class_labels, [&](int g, std::size_t c) {
        return name + ": no face has label " + std::to_string(g) + ", which element class " + std::to_string(c) + " asks for";
    });
    return [label = std::move(label), allowed = std::move(allowed)](std::uint32_t cls, std::uint32_t face) {
        return cls < allowed.size() && face < label.size() && allowed[cls][label[face]];
    };
}

/// One instance on a surface: class, scale and shape (in `shape`; its position and rotation are
/// those of its own picture, (0, 0) and the field's) and its reference point.
struct surface_instance {
    instance shape;
    surface_point anchor;
};

namespace detail::surface {

// Index of mesh face f among the patch's faces, or nothing.
[[nodiscard]] inline std::optional<std::size_t> patch_face(const local_patch& P, std::uint32_t f) {
    const auto it = std::lower_bound(P.faces.begin(), P.faces.end(), f);
    if (it == P.faces.end() || *it != f) return std::nullopt;
    return static_cast<std::size_t>(it - P.faces.begin());
}

// The tangent vector t of face f (mesh frame) in the patch's (u, v): the affine map of the face.
[[nodiscard]] inline vec2 carry(const surface_patcher& sp, const local_patch& P, std::size_t pf, vec3 t) {
    const auto& c = sp.mesh().faces[P.faces[pf]];
    const vec3 e1 = sp.mesh().vertices[c[1]] - sp.mesh().vertices[c[0]], e2 = sp.mesh().vertices[c[2]] - sp.mesh().vertices[c[0]];
    const double a11 = glm::dot(e1, e1), a12 = glm::dot(e1, e2), a22 = glm::dot(e2, e2), det = a11 * a22 - a12 * a12;
    if (!(det > 0)) return {0, 0};
    const double b1 = glm::dot(t, e1), b2 = glm::dot(t, e2);
    const double x = (a22 * b1 - a12 * b2) / det, y = (a11 * b2 - a12 * b1) / det;
    const auto& q = P.corners[pf];
    return x * (P.uv[q[1]] - P.uv[q[0]]) + y * (P.uv[q[2]] - P.uv[q[0]]);
}

// Element rotation (radians) whose up axis (+y) follows the picture direction d.
[[nodiscard]] inline double rotation_of_up(vec2 d) { return std::atan2(d.y, d.x) - 0.5 * std::numbers::pi; }

// Largest distance (mm) from an element's reference point to its covering region.
[[nodiscard]] inline double covering_reach(const element& e) {
    double r = 0;
    for (const ring2& ring : e.covering)
        for (const vec2& q : ring) r = std::max(r, glm::length(q));
    return r;
}

}  // namespace detail::surface

/// The surface pattern space (see the file comment). The patcher, region, control field and
/// classes must outlive it.
class surface_space {
public:
    using snapshot_type = std::vector<surface_instance>;

    surface_space(std::span<const element> classes, std::vector<surface_instance> instances, surface_control field, const surface_region& region,
                  double gamma_boundary = 1.0)
        : classes_(classes), field_(field), region_(&region), gamma_boundary_(gamma_boundary) {
        for (const element& e : classes) max_reach_ = std::max(max_reach_, detail::surface::covering_reach(e));
        max_reach_ *= field.scale->max();
        restore(std::move(instances));
    }

    [[nodiscard]] std::span<const element> classes() const noexcept { return classes_; }
    [[nodiscard]] std::size_t size() const noexcept { return instances_.size(); }
    [[nodiscard]] const std::vector<surface_instance>& instances() const noexcept { return instances_; }
    [[nodiscard]] const instance& instance_at(std::size_t i) const noexcept { return instances_[i].shape; }
    [[nodiscard]] const surface_patcher& patcher() const noexcept { return *region_->patcher; }
    [[nodiscard]] const surface_region& region() const noexcept { return *region_; }
    [[nodiscard]] const surface_control& field() const noexcept { return field_; }
    /// 3D position (mm) of instance i's reference point.
    [[nodiscard]] vec3 anchor_position(std::size_t i) const { return positions_[i]; }
    /// Maps built so far (each instance's picture map is built once per position).
    [[nodiscard]] std::size_t maps_built() const noexcept { return maps_built_; }
    /// Seconds spent building maps (summed over threads).
    [[nodiscard]] double map_seconds() const noexcept { return 1e-9 * static_cast<double>(map_nanoseconds_.load()); }

    [[nodiscard]] snapshot_type snapshot() const { return instances_; }
    void restore(snapshot_type in) {
        instances_ = std::move(in);
        positions_.clear();
        for (const surface_instance& s : instances_) positions_.push_back(patcher().position(s.anchor));
        maps_.assign(instances_.size(), {});
    }
    /// Adds an instance (the maps of the others are kept).
    void append(surface_instance in) {
        positions_.push_back(patcher().position(in.anchor));
        instances_.push_back(std::move(in));
        maps_.emplace_back();
    }
    void pop_back() { instances_.pop_back(), positions_.pop_back(), maps_.pop_back(); }
    void set_spacing(double max_pair_overlap, double same_class_penalty) {
        if (!(max_pair_overlap > 0 && max_pair_overlap <= 1) || !(same_class_penalty >= 1))
            throw invalid_input("pattern spacing: max_pair_overlap must be in (0, 1] and same_class_penalty >= 1");
        max_pair_overlap_ = max_pair_overlap, same_class_penalty_ = same_class_penalty;
    }
    /// The crossing term of every picture (pattern_state::set_crossing_penalty).
    void set_crossing_penalty(double mm_per_crossing, double min_angle_deg = 30.0) {
        pattern_state::check_crossing_penalty(mm_per_crossing, min_angle_deg);
        crossing_penalty_ = mm_per_crossing, crossing_angle_deg_ = min_angle_deg;
    }

    /// Radius (mm) of instance i's picture.
    [[nodiscard]] double view_reach(std::size_t i) const {
        const instance& in = instances_[i].shape;
        return 1.25 * detail::surface::covering_reach(classes_[in.cls]) * in.scale + 2 * max_reach_;
    }

    /// Instance i's neighbourhood in its local parameterization.
    class view_type {
    public:
        [[nodiscard]] const pattern_state& state() const noexcept { return *picture_; }
        [[nodiscard]] std::size_t index() const noexcept { return self_; }
        [[nodiscard]] const local_patch& patch() const noexcept { return *patch_; }
        /// Pattern-wide id of picture instance k.
        [[nodiscard]] std::uint32_t global(std::size_t k) const noexcept { return ids_[k]; }
        [[nodiscard]] std::optional<std::vector<std::uint32_t>> to_local(std::span<const std::uint32_t> ids) const {
            std::vector<std::uint32_t> out;
            for (const std::uint32_t j : ids) {
                const auto it = std::lower_bound(ids_.begin(), ids_.end(), j);
                if (it == ids_.end() || *it != j) return std::nullopt;
                out.push_back(static_cast<std::uint32_t>(it - ids_.begin()));
            }
            return out;
        }

    private:
        friend class surface_space;
        std::shared_ptr<const local_patch> patch_;
        std::vector<std::uint32_t> ids_;
        std::size_t self_ = 0;
        std::shared_ptr<const pattern_state> picture_;
    };

    [[nodiscard]] view_type view(std::size_t i) const {
        view_type v;
        v.patch_ = map_of(i);
        const local_patch& P = *v.patch_;
        const double reach = view_reach(i);
        std::vector<instance> inst;
        for (std::size_t j = 0; j < instances_.size(); ++j) {
            if (j != i && glm::distance(positions_[j], positions_[i]) > reach) continue;  // the map cannot reach it
            auto in = in_picture(P, instances_[j]);
            if (!in) {
                if (j == i) throw solver_error("surface synthesis: the local parameterization lost its own origin");
                continue;
            }
            if (j == i) v.self_ = v.ids_.size();
            v.ids_.push_back(static_cast<std::uint32_t>(j));
            inst.push_back(std::move(*in));
        }
        auto picture = std::make_shared<pattern_state>(classes_, std::move(inst), picture_field(v.patch_), picture_domain(v.patch_), gamma_boundary_);
        picture->set_spacing(max_pair_overlap_, same_class_penalty_);
        picture->set_crossing_penalty(crossing_penalty_, crossing_angle_deg_);
        v.picture_ = std::move(picture);
        return v;
    }

    /// Instance i becomes `in` (given in the frame of v, a view of i): its reference point is where
    /// in.position lies on the surface; its shape is kept, its scale re-read from the field there.
    void adopt(std::size_t i, const view_type& v, instance in) {
        const auto at = v.patch().locate(in.position);
        if (!at) return;  // the steps only propose points of the picture's domain
        surface_instance s{std::move(in), *at};
        s.shape.position = {0, 0};
        s.shape.scale = field_(*at).scale;
        s.shape.rotation = 0;
        instances_[i] = std::move(s);
        positions_[i] = patcher().position(*at);
        maps_[i] = {};
    }

    /// The region as seen in v's map (for the initialization's domain rule): nothing when no map
    /// face meeting `box` is outside the region or has a border edge (the box lies inside the
    /// region); else the region faces of the map as polygons, from the loops of their boundary
    /// edges (even-odd; linear in the edges, where a union of the triangles, thousands on a fine
    /// mesh, makes Clipper's edge joining quadratic). Both are computed once per map.
    [[nodiscard]] std::optional<std::vector<polygon_with_holes>> region_near(const view_type& v, const box2& box) const {
        const std::size_t i = v.global(v.index());
        cached_map& c = maps_[i];
        if (c.patch.get() != &v.patch()) return region_polygons(v.patch(), box).second;  // a view older than the cache
        if (!c.region_ready) {
            auto [edges, polys] = region_polygons(v.patch(), std::nullopt);
            c.edge_boxes = std::move(edges), c.region_polys = std::move(polys), c.region_ready = true;
        }
        for (const box2& b : c.edge_boxes)
            if (b.intersects(box)) return c.region_polys;
        return std::nullopt;
    }

    /// The connectivity graph: i and j connected when they overlap (matching.hpp) in the picture
    /// of the lower id.
    [[nodiscard]] std::vector<std::vector<std::uint32_t>> connectivity() const {
        std::vector<std::vector<std::uint32_t>> higher(size());
        parallel_for(0, size(), [&](std::size_t i) {
            const view_type v = view(i);
            const pattern_state& p = v.state();
            for (std::size_t k = 0; k < p.size(); ++k)
                if (v.global(k) > i && overlapping(p.geometry()[v.index()], p.geometry()[k])) higher[i].push_back(v.global(k));
        });
        std::vector<std::vector<std::uint32_t>> adj(size());
        for (std::uint32_t i = 0; i < size(); ++i)
            for (const std::uint32_t j : higher[i]) adj[i].push_back(j), adj[j].push_back(i);
        for (auto& a : adj) std::sort(a.begin(), a.end());
        return adj;
    }

    /// PME (eq. 3): per instance its Theta and eq. 2 with each higher-id neighbour, in its picture.
    [[nodiscard]] double pattern_energy() const {
        std::vector<double> part(size(), 0.0);
        parallel_for(0, size(), [&](std::size_t i) {
            const view_type v = view(i);
            const pattern_state& p = v.state();
            const placed& gi = p.geometry()[v.index()];
            double e = p.theta(gi);
            for (std::size_t k = 0; k < p.size(); ++k)
                if (v.global(k) > i && overlapping(gi, p.geometry()[k])) e += p.pair_energy(gi, p.geometry()[k]);
            part[i] = e;
        });
        double e = 0;
        for (const double x : part) e += x;  // in instance order: the same sum for any thread count
        return e;
    }

private:
    struct cached_map {
        std::shared_ptr<const local_patch> patch;
        bool region_ready = false;                  // region_near's data below computed
        std::vector<box2> edge_boxes;               // (u, v) boxes of the map faces outside the region or on its border
        std::optional<std::vector<polygon_with_holes>> region_polys;  // the region in the map
    };

    // The boxes of the map faces outside the region or with a border edge (those meeting `only`
    // when given), and the region faces of the map as polygons (nothing if there is no such face).
    [[nodiscard]] std::pair<std::vector<box2>, std::optional<std::vector<polygon_with_holes>>> region_polygons(const local_patch& P,
                                                                                                          std::optional<box2> only) const {
        std::vector<box2> edges;
        for (std::size_t t = 0; t < P.faces.size(); ++t) {
            if (region_->contains(P.faces[t]) && !region_->border[P.faces[t]]) continue;
            box2 b;
            for (const std::uint32_t k : P.corners[t]) b.extend(P.uv[k]);
            if (!only || b.intersects(*only)) edges.push_back(b);
        }
        if (edges.empty()) return {std::move(edges), std::nullopt};
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;  // of the map's region faces
        for (std::size_t t = 0; t < P.faces.size(); ++t) {
            if (!region_->contains(P.faces[t])) continue;
            for (int k = 0; k < 3; ++k) ++directed[{P.corners[t][static_cast<std::size_t>(k)], P.corners[t][static_cast<std::size_t>((k + 1) % 3)]}];
        }
        std::multimap<std::uint32_t, std::uint32_t> next;  // boundary edges: their reverse is not there
        for (const auto& [e, n] : directed)
            if (!directed.count({e.second, e.first})) next.emplace(e.first, e.second);
        std::vector<ring2> loops;
        while (!next.empty()) {  // chain into closed loops (any continuation at a pinch: the parity is the same)
            ring2 loop;
            auto it = next.begin();
            const std::uint32_t start = it->first;
            while (it != next.end()) {
                loop.push_back(P.uv[it->first]);
                const std::uint32_t to = it->second;
                next.erase(it);
                if (to == start) break;
                it = next.find(to);
            }
            if (loop.size() >= 3) loops.push_back(std::move(loop));
        }
        return {std::move(edges), polygon_union(loops, fill_rule::evenodd)};
    }

    // The exponential map around instance i (v axis along the field direction), built once per position.
    [[nodiscard]] std::shared_ptr<const local_patch> map_of(std::size_t i) const {
        if (maps_[i].patch) return maps_[i].patch;
        const surface_point& a = instances_[i].anchor;
        const vec3 up = field_(a).direction;
        const vec3 u_axis = glm::cross(up, patcher().face_normal(a.face));
        const auto t0 = std::chrono::steady_clock::now();
        auto P = std::make_shared<const local_patch>(patcher().patch(a, u_axis, view_reach(i)));
        map_nanoseconds_ += std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
        maps_[i].patch = P;
        ++maps_built_;
        return P;
    }

    // Instance s as seen in patch P (position, rotation from the field at its reference point, scale, shape).
    [[nodiscard]] std::optional<instance> in_picture(const local_patch& P, const surface_instance& s) const {
        const auto pf = detail::surface::patch_face(P, s.anchor.face);
        if (!pf) return std::nullopt;
        const auto uv = P.uv_of(s.anchor);
        const vec2 d = detail::surface::carry(patcher(), P, *pf, field_(s.anchor).direction);
        instance in = s.shape;
        in.position = *uv;
        in.rotation = detail::surface::rotation_of_up(d);
        return in;
    }

    [[nodiscard]] any_field picture_field(std::shared_ptr<const local_patch> P) const {
        return [P, f = field_, sp = region_->patcher](vec2 p) -> field_sample {
            const auto at = P->locate(p);
            if (!at) return {0.0, 1.0};  // outside the map: the steps discard such points (not in the domain)
            const surface_field_sample s = f(*at);
            const auto pf = detail::surface::patch_face(*P, at->face);
            return {detail::surface::rotation_of_up(detail::surface::carry(*sp, *P, *pf, s.direction)), s.scale};
        };
    }

    [[nodiscard]] local_domain picture_domain(std::shared_ptr<const local_patch> P) const {
        local_domain d;
        const surface_region* r = region_;
        d.inside = [P, r](vec2 p) {
            const auto at = P->locate(p);
            return at && r->contains(at->face);
        };
        if (r->class_allowed)
            d.class_allowed = [P, r](std::uint32_t cls, vec2 p) {
                const auto at = P->locate(p);
                return at && r->class_allowed(cls, at->face);
            };
        for (std::size_t t = 0; t < P->faces.size(); ++t) {
            const std::uint8_t bits = r->border[P->faces[t]];
            if (!bits || !r->contains(P->faces[t])) continue;
            for (int k = 0; k < 3; ++k)
                if (bits & (1u << k)) d.boundary.push_back({P->uv[P->corners[t][k]], P->uv[P->corners[t][(k + 1) % 3]]}), d.closed.push_back(false);
        }
        return d;
    }

    std::span<const element> classes_;
    surface_control field_;
    const surface_region* region_;
    double gamma_boundary_;
    double max_pair_overlap_ = 1.0, same_class_penalty_ = 1.5;
    double crossing_penalty_ = 0.0, crossing_angle_deg_ = 30.0;
    double max_reach_ = 0;
    std::vector<surface_instance> instances_;
    std::vector<vec3> positions_;
    mutable std::vector<cached_map> maps_;  // one slot per instance; a view of i only touches slot i
    mutable std::atomic<std::size_t> maps_built_{0};
    mutable std::atomic<std::int64_t> map_nanoseconds_{0};
};

/// What initialize_on_surface produced.
struct surface_initialization_result {
    std::vector<surface_instance> instances;
    std::size_t attempts = 0;
    std::size_t maps_built = 0;  ///< local parameterizations built
    double map_seconds = 0;      ///< time in them
};

namespace detail::surface {

// The region point nearest p (brute force over the region's faces).
[[nodiscard]] inline surface_point nearest_region_point(const surface_region& r, vec3 p) {
    const triangle_mesh& m = r.patcher->mesh();
    surface_point best{r.faces.front(), {1.0 / 3, 1.0 / 3, 1.0 / 3}};
    double best_d = std::numeric_limits<double>::infinity();
    for (const std::uint32_t f : r.faces) {
        const auto& t = m.faces[f];
        const vec3 q = closest_point_on_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]).point;
        const double d = glm::distance(q, p);
        if (d < best_d) best_d = d, best = {f, barycentric(q, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]])};
    }
    // a point on an edge of a sliver face may come out a rounding below 0 (or NaN on a face without
    // area): clamp to the face, as the exponential map and the anchors need valid coordinates
    vec3& b = best.bary;
    if (!(b.x >= 0 && b.y >= 0 && b.z >= 0 && std::abs(b.x + b.y + b.z - 1) <= 1e-12)) {
        b = vec3(std::isfinite(b.x) ? std::max(b.x, 0.0) : 0.0, std::isfinite(b.y) ? std::max(b.y, 0.0) : 0.0, std::isfinite(b.z) ? std::max(b.z, 0.0) : 0.0);
        const double sum = b.x + b.y + b.z;
        b = sum > 0 ? b / sum : vec3(1.0 / 3, 1.0 / 3, 1.0 / 3);
    }
    return best;
}

// The region point nearest the centre of the region's bounding box (the first element's place).
[[nodiscard]] inline surface_point central_point(const surface_region& r) {
    const triangle_mesh& m = r.patcher->mesh();
    box3 b;
    for (const std::uint32_t f : r.faces)
        for (const std::uint32_t v : m.faces[f]) b.extend(m.vertices[v]);
    return nearest_region_point(r, 0.5 * (b.lo + b.hi));
}

// A uniform random point of the region (faces by area, then uniform barycentric coordinates).
[[nodiscard]] inline surface_point random_point(const surface_region& r, std::span<const double> cumulative, counter_rng& rng) {
    const double x = rng.uniform() * cumulative.back();
    const std::size_t k = std::min(static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin()), r.faces.size() - 1);
    double a = rng.uniform(), b = rng.uniform();
    if (a + b > 1) a = 1 - a, b = 1 - b;
    return {r.faces[k], {1 - a - b, a, b}};
}

}  // namespace detail::surface

/// Initialization (§4.1, initialization.hpp's rules, class draw and host exhaustion) on a surface
/// region: candidates are thrown around a host in the host's picture, the rules are checked there
/// against the instances the picture holds and the region's faces in it; the first element sits
/// at the region point nearest the centre of the region's bounding box. Throws as initialize().
[[nodiscard]] inline surface_initialization_result initialize_on_surface(std::span<const element> classes, std::span<const double> weights,
                                                                         const surface_region& region, const surface_control& field,
                                                                         const initialization_options& opt = {}) {
    namespace di = detail::init;
    namespace ds = detail::surface;
    di::class_picker picker(classes, weights);
    initialization_options rules = opt;  // the same-class factor only for a mix (initialization.hpp)
    rules.same_class_penalty = effective_same_class_penalty(weights, opt.same_class_penalty);
    if (!(opt.same_class_penalty >= 1)) throw invalid_input("initialization: same_class_penalty must be >= 1");
    const surface_point centre = ds::central_point(region);
    {
        const double s0 = field(centre).scale;
        for (std::size_t c = 0; c < classes.size(); ++c)
            if (weights[c] > 0 && classes[c].covering_area * s0 * s0 > region.area)
                throw no_solution("initialization: element " + classes[c].name + " (covering " + std::to_string(classes[c].covering_area * s0 * s0) +
                                  " mm^2) is larger than the region (" + std::to_string(region.area) + " mm^2)");
    }
    std::vector<double> cumulative;
    for (const std::uint32_t f : region.faces) cumulative.push_back((cumulative.empty() ? 0.0 : cumulative.back()) + surface_region::triangle_area(region.patcher->mesh(), f));

    surface_space s(classes, {}, field, region);
    di::host_pool hosts(opt.attempts_per_host);
    struct candidate {
        std::uint32_t cls = 0;
        std::size_t host = SIZE_MAX;  // SIZE_MAX: the first element, at `at`
        vec2 position{0, 0};          // in the host's picture
        surface_point at;
    };
    std::optional<surface_space::view_type> host_view;

    // The class drawn for a candidate on face f: the most underfilled one, or with element sets per
    // region the most underfilled of those allowed there (UINT32_MAX: none is), as in the plane.
    auto class_at = [&](std::uint32_t current, std::uint32_t f) {
        if (region.allows(current, f)) return current;
        return picker.pick([&](std::uint32_t c) { return region.class_allowed(c, f); });
    };
    auto generate = [&](counter_rng& rng) -> std::optional<candidate> {
        const std::uint32_t current = picker.pick();
        hosts.host = SIZE_MAX;
        if (s.size() == 0) {
            if (hosts.first_failures >= opt.attempts_per_host) return std::nullopt;
            const surface_point at = hosts.first_failures == 0 ? centre : ds::random_point(region, cumulative, rng);
            const std::uint32_t cls = class_at(current, at.face);
            if (cls == UINT32_MAX) return ++hosts.first_failures, std::nullopt;
            return candidate{cls, SIZE_MAX, {0, 0}, at};
        }
        if (!hosts.draw(rng)) return std::nullopt;
        host_view.emplace(s.view(hosts.host));
        const pattern_state& pic = host_view->state();
        const vec2 p = di::position_near(pic.geometry()[host_view->index()], classes[current].size, [&](vec2 q) { return pic.field()(q).scale; }, rng);
        std::uint32_t cls = UINT32_MAX;
        if (pic.domain().contains(p)) {
            if (!region.class_allowed) cls = current;
            else if (const auto at = host_view->patch().locate(p)) cls = class_at(current, at->face);
        }
        if (cls == UINT32_MAX) {
            hosts.failed();
            return std::nullopt;
        }
        return candidate{cls, hosts.host, p, {}};
    };

    auto accept = [&](const candidate& c, std::span<const candidate>) {
        std::optional<surface_space::view_type> own;
        if (c.host == SIZE_MAX) {  // the first element: judged in its own picture
            s.append(surface_instance{instance{c.cls, {0, 0}, 0, field(c.at).scale, classes[c.cls].vertices}, c.at});
            own.emplace(s.view(0));
        }
        const surface_space::view_type& v = own ? *own : *host_view;
        const pattern_state& pic = v.state();
        const instance in = pic.moved(instance{c.cls, c.position, 0, 1, classes[c.cls].vertices}, c.position);
        const placed pc = place(classes[c.cls], in);
        std::vector<placed> geo;
        std::vector<std::uint32_t> cls_of;
        for (std::size_t k = 0; k < pic.size(); ++k)
            if (!own) geo.push_back(pic.geometry()[k]), cls_of.push_back(pic.instances()[k].cls);
        const auto region_here = s.region_near(v, pc.box);
        const auto at = own ? std::optional<surface_point>(c.at) : v.patch().locate(c.position);
        if (!at || !di::admissible(pc, c.cls, geo, cls_of, region_here ? &*region_here : nullptr, rules)) {
            if (own) s.pop_back();
            hosts.failed();
            return false;
        }
        if (!own) s.append(surface_instance{instance{c.cls, {0, 0}, 0, field(*at).scale, classes[c.cls].vertices}, *at});
        ++picker.count[c.cls];
        hosts.added();
        return true;
    };

    const auto r = sampling::dart_throwing(generate, accept, di::dart_options_of(opt));
    if (s.size() == 0) throw no_solution("initialization: no element fits in the region (is an element larger than the region?)");
    return {s.instances(), r.attempts, s.maps_built(), s.map_seconds()};
}

/// Removes instances whose reference points lie within `tolerance` x their size of an earlier
/// one's of the same class (3D distance; the field sets both rotations, so they agree) (§3.5).
inline std::size_t remove_duplicates(surface_space& s, double tolerance = 0.05) {
    std::vector<surface_instance> kept;
    std::vector<vec3> at;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const instance& a = s.instance_at(i);
        bool dup = false;
        for (std::size_t k = 0; k < kept.size() && !dup; ++k)
            dup = kept[k].shape.cls == a.cls && glm::distance(at[k], s.anchor_position(i)) < tolerance * s.classes()[a.cls].size * a.scale;
        if (!dup) kept.push_back(s.instances()[i]), at.push_back(s.anchor_position(i));
    }
    const std::size_t removed = s.size() - kept.size();
    if (removed) s.restore(std::move(kept));
    return removed;
}

}  // namespace fabsynth::filigree
