// SPDX-License-Identifier: MIT
#pragma once
/// @file exponential_map.hpp  Local parameterizations of surface patches by the discrete
/// exponential map (Schmidt, Grimm & Wyvill, "Interactive decal compositing with discrete
/// exponential maps", SIGGRAPH 2006): geodesic normal coordinates around a point of a triangle
/// mesh, so that 2D work (matching, overlap, deformation of filigree elements,
/// filigree-synthesis.md §8.1: "all computations are done on a locally parameterized 2D surface
/// patch") can run in the plane and its results be mapped back onto the surface.
///
/// Usage:
///   fabsynth::surface_patcher patcher(mesh);                  // adjacency and normals, once per mesh
///   fabsynth::surface_point o{face, {1.0 / 3, 1.0 / 3, 1.0 / 3}};
///   fabsynth::local_patch p = patcher.patch(o, up, 12.0);      // tangent direction, radius (mm)
///   vec2 uv = p.uv_of(o);                                      // (0, 0)
///   if (auto s = p.locate({3, 4})) vec3 x = patcher.position(*s);  // 2D -> surface
///
/// Method (Schmidt et al. 2006, §3): the origin o with unit normal n_o and tangent frame (e1, e2),
/// e1 = the given direction projected into the tangent plane. The vertices of o's face get
/// u(v) = |v - o| * (direction of v - o projected into the tangent plane, in (e1, e2)). A
/// Dijkstra search over the mesh edges (edge lengths, mm) then reaches the other vertices in
/// order of edge-path distance; a vertex q gets the average, weighted by 1 / |q - r|^2, over its already
/// finished neighbours r of u(r) + T_r(q - r), where T_r writes q - r, projected into r's tangent
/// plane and rescaled to its length, in the frame (e1, e2) carried from o to r by the rotation
/// that takes n_o to n_r (the upwind averaging of Schmidt et al.). Vertex normals are area
/// weighted. On a plane the map is exact (an isometry); on a developable surface its error grows
/// with the patch radius over the radius of curvature.
///
/// A patch holds the vertices reached from those whose |u| is at most `radius` plus the longest
/// edge (the search expands only from them: edge paths can be ~40% longer than geodesics on
/// grid-like meshes, so the map's own distance, not the search's, bounds the disk), their (u, v)
/// in mm, and the faces whose three vertices are in it: every face within geodesic distance
/// `radius` of the origin, up to the map's error. Where the discrete map folds (a face's (u, v)
/// triangle is mirrored against its orientation in 3D relative to the vertex normals: around a
/// rim far sharper than the edges, such as a thin ear, or past a turn of the normal towards the
/// opposite side of a closed surface) the search does not expand, and mirrored faces are left
/// out, so every face of a patch keeps its orientation; nor does it expand beyond an edge-path
/// distance of twice the disk's reach (where the map's distances collapse). locate() finds the face whose (u, v)
/// triangle contains a point through a uniform grid over the triangles' boxes (the lowest face id
/// among those containing it, so the answer is deterministic where the map folds).
///
/// Errors: invalid_input naming the input for a face index out of range, barycentric coordinates
/// that are not finite, negative or do not sum to 1 (within 1e-9), a radius that is not finite
/// and > 0, a direction that is not finite or lies along the normal, a mesh with a face indexing
/// a missing vertex or a non-finite vertex (from the constructor).
///
/// Written by hand: no Debian-packaged library offers the exponential map (libigl, CGAL's
/// Surface_mesh_parameterization and OpenMesh parameterize whole disks by global solves). The edge
/// adjacency is built here rather than taken from graph/from_mesh.hpp because geometry/ sits below
/// graph/ in the layers.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth {

/// A point on a triangle mesh: a face and barycentric coordinates over its three vertices.
struct surface_point {
    std::uint32_t face = 0;
    vec3 bary{1.0 / 3, 1.0 / 3, 1.0 / 3};
};

/// One local parameterization (see the file comment).
class local_patch {
public:
    std::vector<std::uint32_t> vertices;           ///< mesh vertex ids in the patch, in the order reached
    std::vector<vec2> uv;                          ///< per patch vertex, mm
    std::vector<std::uint32_t> faces;              ///< mesh faces with all three vertices in the patch, increasing
    std::vector<std::array<std::uint32_t, 3>> corners;  ///< per patch face, its corners as indices into `vertices`

    /// (u, v) of a surface point on a patch face, mm; nothing if its face is not in the patch.
    [[nodiscard]] std::optional<vec2> uv_of(const surface_point& s) const {
        const auto it = std::lower_bound(faces.begin(), faces.end(), s.face);
        if (it == faces.end() || *it != s.face) return std::nullopt;
        const auto& c = corners[static_cast<std::size_t>(it - faces.begin())];
        return s.bary.x * uv[c[0]] + s.bary.y * uv[c[1]] + s.bary.z * uv[c[2]];
    }

    /// The surface point at (u, v) (mm): a patch face whose (u, v) triangle contains it, or nothing.
    [[nodiscard]] std::optional<surface_point> locate(vec2 p) const {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || faces.empty() || !bounds_.contains(p)) return std::nullopt;
        const int cx = std::clamp(static_cast<int>((p.x - bounds_.lo.x) / cell_), 0, nx_ - 1);
        const int cy = std::clamp(static_cast<int>((p.y - bounds_.lo.y) / cell_), 0, ny_ - 1);
        const std::size_t c = static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(cx);
        for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {  // increasing face order
            const std::uint32_t t = cell_faces_[k];
            const auto& q = corners[t];
            const vec2 a = uv[q[0]], b = uv[q[1]], d = uv[q[2]];
            if (!(std::abs(orient2d(a, b, d)) > 0)) continue;  // folded flat
            const vec3 l = barycentric(p, a, b, d);
            constexpr double slack = -1e-12;  // points on a shared edge belong to both faces
            if (l.x >= slack && l.y >= slack && l.z >= slack) return surface_point{faces[t], l};
        }
        return std::nullopt;
    }

    /// Builds the point-location grid (called once the triangles are set).
    void index() {
        bounds_ = box2();
        for (const vec2& x : uv) bounds_.extend(x);
        const std::size_t n = faces.size();
        if (n == 0) return;
        const vec2 ext = bounds_.size();
        cell_ = std::max({ext.x, ext.y, 1e-12}) / std::max(1.0, std::ceil(std::sqrt(static_cast<double>(n))));
        nx_ = std::max(1, static_cast<int>(std::ceil(ext.x / cell_)));
        ny_ = std::max(1, static_cast<int>(std::ceil(ext.y / cell_)));
        const std::size_t cells = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
        std::vector<std::uint32_t> count(cells + 1, 0);
        auto for_cells = [&](std::size_t t, auto&& f) {
            box2 b;
            for (const std::uint32_t k : corners[t]) b.extend(uv[k]);
            const int x0 = std::clamp(static_cast<int>((b.lo.x - bounds_.lo.x) / cell_), 0, nx_ - 1);
            const int x1 = std::clamp(static_cast<int>((b.hi.x - bounds_.lo.x) / cell_), 0, nx_ - 1);
            const int y0 = std::clamp(static_cast<int>((b.lo.y - bounds_.lo.y) / cell_), 0, ny_ - 1);
            const int y1 = std::clamp(static_cast<int>((b.hi.y - bounds_.lo.y) / cell_), 0, ny_ - 1);
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) f(static_cast<std::size_t>(y) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(x));
        };
        for (std::size_t t = 0; t < n; ++t) for_cells(t, [&](std::size_t c) { ++count[c + 1]; });
        for (std::size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
        cell_start_ = count;
        cell_faces_.assign(count.back(), 0);
        for (std::size_t t = 0; t < n; ++t) for_cells(t, [&](std::size_t c) { cell_faces_[count[c]++] = static_cast<std::uint32_t>(t); });
    }

private:
    box2 bounds_;
    double cell_ = 1;
    int nx_ = 0, ny_ = 0;
    std::vector<std::uint32_t> cell_start_, cell_faces_;
};

/// The per-mesh data of the exponential map (edge adjacency, vertex normals, vertex-to-face
/// incidence), computed once; patch() is const and may be called from several threads. The mesh
/// must outlive the patcher.
class surface_patcher {
public:
    /// Throws invalid_input for a face indexing a missing vertex or a non-finite vertex.
    explicit surface_patcher(const triangle_mesh& m) : mesh_(&m) {
        const std::size_t nv = m.num_vertices();
        for (std::size_t v = 0; v < nv; ++v) {
            const vec3 x = m.vertices[v];
            if (!(std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z)))
                throw invalid_input("exponential map: vertex " + std::to_string(v) + " is not finite");
        }
        std::vector<std::pair<std::uint32_t, std::uint32_t>> arcs;
        for (std::size_t f = 0; f < m.num_faces(); ++f)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = m.faces[f][k], b = m.faces[f][(k + 1) % 3];
                if (a >= nv || b >= nv)
                    throw invalid_input("exponential map: face " + std::to_string(f) + " indexes a missing vertex (" + std::to_string(std::max(a, b)) + ")");
                if (a != b) arcs.emplace_back(a, b), arcs.emplace_back(b, a);
            }
        std::sort(arcs.begin(), arcs.end());
        arcs.erase(std::unique(arcs.begin(), arcs.end()), arcs.end());
        adj_start_.assign(nv + 1, 0);
        for (const auto& [a, b] : arcs) ++adj_start_[a + 1], adj_.push_back(b);
        for (std::size_t v = 0; v < nv; ++v) adj_start_[v + 1] += adj_start_[v];
        for (const auto& [a, b] : arcs) longest_edge_ = std::max(longest_edge_, glm::distance(m.vertices[a], m.vertices[b]));
        normals_ = vertex_normals(m);
        faces_of_.assign(nv + 1, 0);
        for (const auto& f : m.faces)
            for (const std::uint32_t v : f) ++faces_of_[v + 1];
        for (std::size_t v = 0; v < nv; ++v) faces_of_[v + 1] += faces_of_[v];
        incident_.assign(faces_of_.back(), 0);
        std::vector<std::uint32_t> at(faces_of_.begin(), faces_of_.end() - 1);
        for (std::uint32_t f = 0; f < m.num_faces(); ++f)
            for (const std::uint32_t v : m.faces[f]) incident_[at[v]++] = f;
    }

    [[nodiscard]] const triangle_mesh& mesh() const noexcept { return *mesh_; }
    [[nodiscard]] const std::vector<vec3>& normals() const noexcept { return normals_; }

    /// Position (mm) of a surface point.
    [[nodiscard]] vec3 position(const surface_point& s) const {
        const auto& f = mesh_->faces[s.face];
        return s.bary.x * mesh_->vertices[f[0]] + s.bary.y * mesh_->vertices[f[1]] + s.bary.z * mesh_->vertices[f[2]];
    }
    /// Unit normal of a surface point's face (zero for a face without area).
    [[nodiscard]] vec3 face_normal(std::uint32_t face) const {
        const vec3 n = face_normal_area2(*mesh_, face);
        const double l = glm::length(n);
        return l > 0 ? n / l : vec3(0.0);
    }

    /// The exponential map around `origin` (see the file comment): `direction` (any vector not
    /// along the normal; its tangent projection is the u axis), `radius` in mm.
    [[nodiscard]] local_patch patch(const surface_point& origin, vec3 direction, double radius) const {
        check(origin, direction, radius);
        const triangle_mesh& m = *mesh_;
        const vec3 o = position(origin);
        const vec3 n_o = face_normal(origin.face);
        if (n_o == vec3(0.0)) throw invalid_input("exponential map: the origin's face " + std::to_string(origin.face) + " has no area");
        const vec3 e1 = glm::normalize(direction - glm::dot(direction, n_o) * n_o), e2 = glm::cross(n_o, e1);

        // Per-thread scratch indexed by mesh vertex (distance, patch slot), reset through the
        // touched list, so a small patch costs its own size, not the mesh's.
        thread_local search_scratch sc;
        sc.prepare(m.num_vertices());
        const scratch_reset reset{sc};
        local_patch p;
        std::vector<vec3> frame1, frame2, normal;  // per patch vertex: the carried frame and the normal
        auto finish = [&](std::uint32_t v, vec2 uv) {
            const vec3 n = normals_[v] == vec3(0.0) ? n_o : normals_[v];
            const vec3 a = rotate_between(n_o, n, e1);  // e1 carried by the minimal rotation n_o -> n_v
            sc.slot[v] = static_cast<std::uint32_t>(p.vertices.size());
            p.vertices.push_back(v), p.uv.push_back(uv);
            frame1.push_back(a), frame2.push_back(glm::cross(n, a)), normal.push_back(n);
        };
        auto tangent_step = [&](vec3 from, vec3 n, vec3 to) {  // to - from in from's tangent plane, length kept
            const vec3 d = to - from;
            const vec3 t = d - glm::dot(d, n) * n;
            const double lt = glm::length(t), ld = glm::length(d);
            return lt > 0 ? t * (ld / lt) : vec3(0.0);
        };
        auto relax = [&](std::uint32_t v) {
            for (std::uint32_t a = adj_start_[v]; a < adj_start_[v + 1]; ++a) {
                const std::uint32_t w = adj_[a];
                const double d = sc.dist[v] + glm::distance(m.vertices[v], m.vertices[w]);
                if (sc.slot[w] != none || !(d < sc.dist[w])) continue;
                if (sc.dist[w] == unreached) sc.touched.push_back(w);
                sc.dist[w] = d;
                sc.heap.push({d, w});
            }
        };

        const double reach = radius + longest_edge_, path_limit = 2.0 * reach;
        auto mirrored = [&](std::uint32_t f) {  // face f's (u, v) triangle against its 3D orientation
            const auto& c = m.faces[f];
            const std::uint32_t a = sc.slot[c[0]], b = sc.slot[c[1]], e = sc.slot[c[2]];
            const double turn = orient2d(p.uv[a], p.uv[b], p.uv[e]);
            return turn * glm::dot(face_normal_area2(m, f), normal[std::max({a, b, e})]) < 0;
        };
        auto folds_at = [&](std::uint32_t q) {  // a finished face at q is mirrored
            for (std::uint32_t i = faces_of_[q]; i < faces_of_[q + 1]; ++i) {
                const auto& c = m.faces[incident_[i]];
                if (sc.slot[c[0]] != none && sc.slot[c[1]] != none && sc.slot[c[2]] != none && mirrored(incident_[i])) return true;
            }
            return false;
        };
        for (const std::uint32_t v : m.faces[origin.face]) {
            if (sc.slot[v] != none) continue;  // a degenerate origin face repeats a vertex
            const vec3 t = tangent_step(o, n_o, m.vertices[v]);
            if (sc.dist[v] == unreached) sc.touched.push_back(v);
            sc.dist[v] = glm::distance(o, m.vertices[v]);
            finish(v, {glm::dot(t, e1), glm::dot(t, e2)});
        }
        for (const std::uint32_t v : m.faces[origin.face]) relax(v);
        while (!sc.heap.empty()) {
            const auto [d, q] = sc.heap.top();
            sc.heap.pop();
            if (sc.slot[q] != none || d > sc.dist[q]) continue;
            // upwind average over the finished neighbours
            vec2 sum(0.0);
            double wsum = 0;
            for (std::uint32_t a = adj_start_[q]; a < adj_start_[q + 1]; ++a) {
                const std::uint32_t k = sc.slot[adj_[a]];
                if (k == none) continue;
                const vec3 r = m.vertices[adj_[a]];
                const double len2 = glm::dot(m.vertices[q] - r, m.vertices[q] - r);
                if (!(len2 > 0)) continue;
                const vec3 t = tangent_step(r, normal[k], m.vertices[q]);
                const double w = 1.0 / len2;
                sum += w * (p.uv[k] + vec2(glm::dot(t, frame1[k]), glm::dot(t, frame2[k])));
                wsum += w;
            }
            finish(q, wsum > 0 ? sum / wsum : vec2(0.0));
            // The disk grows by the map's own distances, but not across a fold (where the map
            // mirrors, e.g. around a rim much sharper than the edges) nor along edge paths far
            // longer than the disk (a map whose (u, v) collapse there would take the whole mesh).
            if (glm::length(p.uv.back()) <= reach && d <= path_limit && !folds_at(q)) relax(q);
        }
        // faces with three finished vertices, taken from the corner with the highest slot (the
        // last one finished; a degenerate face repeating it is listed twice, hence unique), then
        // put in face order for uv_of
        std::vector<std::uint32_t> found;
        for (std::uint32_t k = 0; k < p.vertices.size(); ++k) {
            const std::uint32_t v = p.vertices[k];
            for (std::uint32_t i = faces_of_[v]; i < faces_of_[v + 1]; ++i) {
                const auto& c = m.faces[incident_[i]];
                const std::uint32_t a = sc.slot[c[0]], b = sc.slot[c[1]], d = sc.slot[c[2]];
                if (a == none || b == none || d == none || std::max({a, b, d}) != k || mirrored(incident_[i])) continue;
                found.push_back(incident_[i]);
            }
        }
        std::sort(found.begin(), found.end());
        found.erase(std::unique(found.begin(), found.end()), found.end());
        p.faces = std::move(found);
        p.corners.reserve(p.faces.size());
        for (const std::uint32_t f : p.faces) p.corners.push_back({sc.slot[m.faces[f][0]], sc.slot[m.faces[f][1]], sc.slot[m.faces[f][2]]});
        p.index();
        return p;
    }

private:
    static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    static constexpr double unreached = std::numeric_limits<double>::infinity();
    struct search_scratch {
        std::vector<double> dist;
        std::vector<std::uint32_t> slot, touched;
        std::priority_queue<std::pair<double, std::uint32_t>, std::vector<std::pair<double, std::uint32_t>>, std::greater<>> heap;
        void prepare(std::size_t n) {
            if (dist.size() < n) dist.resize(n, unreached), slot.resize(n, none);
        }
    };
    struct scratch_reset {  // clears what a search touched, also when it throws
        search_scratch& sc;
        ~scratch_reset() {
            for (const std::uint32_t v : sc.touched) sc.dist[v] = unreached, sc.slot[v] = none;
            sc.touched.clear();
            while (!sc.heap.empty()) sc.heap.pop();
        }
    };

    // The rotation about n_from x n_to taking n_from to n_to, applied to x (Rodrigues); identity
    // when the normals agree, a half turn about x's own axis when they are opposite.
    [[nodiscard]] static vec3 rotate_between(vec3 n_from, vec3 n_to, vec3 x) {
        const vec3 k = glm::cross(n_from, n_to);
        const double s = glm::length(k), c = glm::dot(n_from, n_to);
        if (s < 1e-15) return c > 0 ? x : -x;
        const vec3 a = k / s;
        return x * c + glm::cross(a, x) * s + a * glm::dot(a, x) * (1 - c);
    }

    void check(const surface_point& s, vec3 direction, double radius) const {
        if (s.face >= mesh_->num_faces())
            throw invalid_input("exponential map: origin face " + std::to_string(s.face) + " out of range for " + std::to_string(mesh_->num_faces()) +
                                " faces");
        const vec3 b = s.bary;
        if (!(std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z)) || b.x < 0 || b.y < 0 || b.z < 0 || std::abs(b.x + b.y + b.z - 1) > 1e-9)
            throw invalid_input("exponential map: barycentric coordinates of the origin must be >= 0 and sum to 1");
        if (!(std::isfinite(radius) && radius > 0)) throw invalid_input("exponential map: radius must be finite and > 0 mm, got " + std::to_string(radius));
        const vec3 n = face_normal(s.face);
        const double l = glm::length(direction);
        if (!(std::isfinite(l) && l > 0) || glm::length(direction - glm::dot(direction, n) * n) <= 1e-9 * l)
            throw invalid_input("exponential map: the direction must be finite and not along the origin's normal");
    }

    const triangle_mesh* mesh_;
    std::vector<std::uint32_t> adj_start_, adj_;  // vertex -> neighbours (CSR, increasing)
    std::vector<vec3> normals_;
    std::vector<std::uint32_t> faces_of_, incident_;  // vertex -> incident faces (CSR)
    double longest_edge_ = 0;
};

}  // namespace fabsynth
