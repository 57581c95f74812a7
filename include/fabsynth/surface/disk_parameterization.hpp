// SPDX-License-Identifier: MIT
#pragma once
/// @file disk_parameterization.hpp  A bijective map Phi of a disk-topology triangle mesh onto a
/// convex plane domain (the unit circle or square), with point location both ways: the
/// parameterization of Zhou, Jiang & Lefebvre 2014 §6.3 (topology-constrained-vector-patterns.md),
/// used to draw curves on surfaces (surface/curve.hpp).
///
/// Method. The boundary loop is placed on the border by its chord-length parameter, starting at
/// its lowest-index vertex and running in the loop's own direction (so the faces keep their
/// orientation: every face is counter-clockwise in the domain); the interior vertices solve the
/// discrete harmonic equations with cotangent weights (Desbrun, Meyer & Alliez 2002, "Intrinsic
/// parameterizations of surface meshes", the discrete conformal map, lambda = 1), through
/// surface/laplacian.hpp's harmonic_interpolation. That Laplacian clamps negative weights
/// to 0, so each interior vertex is a convex combination of its neighbours and the map is a Tutte
/// embedding: bijective onto the convex domain for a disk (Floater 1997), where raw cotangent
/// weights can fold faces on meshes with obtuse angles. The result is checked: a face that is
/// not strictly counter-clockwise in the domain (a zero weight can flatten one) is an error.
///
/// Point location. locate(x) finds the face holding a domain point through a uniform grid of the
/// faces' domain boxes (about one face per bin); project(p) takes a point in space to its closest
/// point on the mesh (geometry/distance.hpp) and its domain position. surface_point(face, bary)
/// maps back: the same barycentric combination of the face's three vertices, so a point of the
/// domain maps exactly (up to rounding) onto the mesh. neighbour(face, edge) walks across edges.
///
/// Usage:
///   fabsynth::disk_parameterization phi(mesh);                       // disk topology required
///   auto at = phi.project({10, 0, 45});                              // face, barycentrics, domain point
///   auto loc = phi.locate({0.2, -0.1});                              // std::nullopt outside the domain
///   vec3 p = phi.surface_point(loc->face, loc->bary);
///
/// Closed surfaces. A closed genus-0 mesh is not a disk; cut_open(mesh, v) removes the faces
/// around vertex v (and v itself), which leaves a disk whose border is v's link. The harmonic map
/// then squeezes the region far from the cut toward the domain's centre (a conformal map of a
/// sphere less a small cap scales its far side by about cap size / radius), which double precision
/// carries for any mesh size here; cut far from where curves are drawn (farthest_vertex()).
///
/// Errors: invalid_input naming the problem for an invalid mesh, one that is not a single
/// edge-manifold, consistently oriented disk (one component, one boundary loop, Euler
/// characteristic 1) or has a degenerate face; solver_error if the solve fails or a face folds.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/distance.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/surface/laplacian.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth {

/// The mesh less the faces around vertex v and v itself (vertices renumbered in order): a closed
/// genus-0 mesh becomes a disk (see the file comment). Throws invalid_input for an invalid mesh or
/// a vertex out of range or used by no face.
[[nodiscard]] inline triangle_mesh cut_open(const triangle_mesh& m, std::uint32_t v) {
    validate(m, "cut_open input mesh");
    if (v >= m.vertices.size()) throw invalid_input("cut_open: vertex " + std::to_string(v) + " out of range");
    triangle_mesh out;
    std::vector<std::uint32_t> index(m.vertices.size(), UINT32_MAX);
    bool used = false;
    for (const auto& t : m.faces) {
        if (t[0] == v || t[1] == v || t[2] == v) {
            used = true;
            continue;
        }
        std::array<std::uint32_t, 3> f{};
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t w = t[static_cast<std::size_t>(k)];
            if (index[w] == UINT32_MAX) index[w] = 0;  // mark; numbered below in vertex order
            f[static_cast<std::size_t>(k)] = w;
        }
        out.faces.push_back(f);
    }
    if (!used) throw invalid_input("cut_open: no face uses vertex " + std::to_string(v));
    for (std::size_t w = 0; w < m.vertices.size(); ++w)
        if (index[w] != UINT32_MAX) {
            index[w] = static_cast<std::uint32_t>(out.vertices.size());
            out.vertices.push_back(m.vertices[w]);
        }
    for (auto& f : out.faces)
        for (auto& w : f) w = index[w];
    return out;
}

/// The vertex of m farthest from its nearest point of `points` (the first such vertex on ties):
/// where to cut a closed mesh open so that the cut stays away from a curve through the points.
[[nodiscard]] inline std::uint32_t farthest_vertex(const triangle_mesh& m, std::span<const vec3> points) {
    if (points.empty() || m.vertices.empty()) throw invalid_input("farthest_vertex: no points or no vertices");
    std::uint32_t best = 0;
    double best_d = -1.0;
    for (std::uint32_t w = 0; w < m.vertices.size(); ++w) {
        double d = std::numeric_limits<double>::infinity();
        for (const vec3& p : points) d = std::min(d, glm::length(m.vertices[w] - p));
        if (d > best_d) best_d = d, best = w;
    }
    return best;
}

/// The convex border the boundary loop is mapped onto.
enum class parameterization_border {
    circle,  ///< the unit circle centred at the origin
    square,  ///< the square [-1, 1]^2
};

struct disk_parameterization_options {
    parameterization_border border = parameterization_border::circle;
};

/// A face of the mesh and barycentric coordinates in it (sum 1).
struct mesh_location {
    std::uint32_t face = 0;
    vec3 bary{1.0 / 3.0};
};

/// Phi: a disk-topology mesh onto a convex domain, and its inverse (see the file comment).
class disk_parameterization {
public:
    static constexpr std::uint32_t no_face = UINT32_MAX;

    explicit disk_parameterization(triangle_mesh m, const disk_parameterization_options& opt = {})
        : mesh_(checked_disk(std::move(m))), distance_(mesh_) {
        build_adjacency();
        solve(opt.border);
        build_grid();
    }

    [[nodiscard]] const triangle_mesh& mesh() const noexcept { return mesh_; }
    /// Domain position of every vertex.
    [[nodiscard]] const std::vector<vec2>& domain_vertices() const noexcept { return uv_; }
    /// The boundary loop's vertices in order (the domain border's counter-clockwise order).
    [[nodiscard]] const std::vector<std::uint32_t>& boundary() const noexcept { return boundary_; }
    /// The closest-point structure of the mesh.
    [[nodiscard]] const mesh_distance& distance() const noexcept { return distance_; }

    /// The face across edge e (0 = v0v1, 1 = v1v2, 2 = v2v0) of face f, or no_face on the boundary.
    [[nodiscard]] std::uint32_t neighbour(std::uint32_t f, int e) const { return across_[3 * f + static_cast<std::size_t>(e)]; }

    /// Domain position of a point given by face and barycentrics.
    [[nodiscard]] vec2 domain_point(std::uint32_t f, const vec3& b) const {
        const auto& t = mesh_.faces[f];
        return b.x * uv_[t[0]] + b.y * uv_[t[1]] + b.z * uv_[t[2]];
    }
    /// The point of the mesh with these barycentrics in face f.
    [[nodiscard]] vec3 surface_point(std::uint32_t f, const vec3& b) const {
        const auto& t = mesh_.faces[f];
        return b.x * mesh_.vertices[t[0]] + b.y * mesh_.vertices[t[1]] + b.z * mesh_.vertices[t[2]];
    }

    /// The face holding domain point x and x's barycentrics in it (clamped to >= 0 and renormalised
    /// for points within rounding of an edge); nullopt if x is outside the domain.
    [[nodiscard]] std::optional<mesh_location> locate(vec2 x) const {
        if (!all_finite(x)) throw invalid_input("disk parameterization: located point is not finite");
        const ivec2 c = bin_of(x);
        if (c.x < 0 || c.y < 0 || c.x >= bins_ || c.y >= bins_) return std::nullopt;
        std::optional<mesh_location> best;
        double best_min = -std::numeric_limits<double>::infinity();
        const std::size_t cell = static_cast<std::size_t>(c.y) * static_cast<std::size_t>(bins_) + static_cast<std::size_t>(c.x);
        for (std::uint32_t k = bin_start_[cell]; k < bin_start_[cell + 1]; ++k) {
            const std::uint32_t f = bin_faces_[k];
            const auto& t = mesh_.faces[f];
            const vec3 b = barycentric(x, uv_[t[0]], uv_[t[1]], uv_[t[2]]);
            const double lo = std::min({b.x, b.y, b.z});
            if (lo > best_min) best_min = lo, best = mesh_location{f, b};
        }
        if (!best || best_min < -1e-9) return std::nullopt;
        vec3 b = glm::max(best->bary, vec3(0.0));
        best->bary = b / (b.x + b.y + b.z);
        return best;
    }

    /// The closest point of the mesh to p: its face and barycentrics, and the distance (mm).
    struct projection {
        mesh_location at;
        vec2 domain{0};
        double distance = 0;
    };
    [[nodiscard]] projection project(const vec3& p) const {
        const mesh_closest c = distance_.closest(p);
        const auto& t = mesh_.faces[c.face];
        vec3 b = glm::max(barycentric(c.point, mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]), vec3(0.0));
        b /= b.x + b.y + b.z;
        return {{c.face, b}, domain_point(c.face, b), std::sqrt(c.dist2)};
    }

private:
    [[nodiscard]] static triangle_mesh checked_disk(triangle_mesh m) {
        validate(m, "disk parameterization input mesh");
        if (m.faces.empty()) throw invalid_input("disk parameterization: the mesh has no faces");
        const mesh_topology_info info = analyze_topology(m);
        if (info.degenerate_faces) throw invalid_input("disk parameterization: the mesh has " + std::to_string(info.degenerate_faces) + " degenerate faces");
        if (!info.is_edge_manifold()) throw invalid_input("disk parameterization: the mesh is not edge-manifold");
        if (!info.is_oriented()) throw invalid_input("disk parameterization: the mesh is not consistently oriented");
        if (info.components != 1 || info.boundary_loops != 1 || info.euler != 1)
            throw invalid_input("disk parameterization: the mesh must be a disk (one component, one boundary loop, Euler characteristic 1), got " +
                                std::to_string(info.components) + " components, " + std::to_string(info.boundary_loops) +
                                " boundary loops, Euler characteristic " + std::to_string(info.euler) +
                                (info.boundary_loops == 0 ? " (a closed mesh must be cut open first)" : ""));
        if (info.vertices != m.vertices.size()) throw invalid_input("disk parameterization: the mesh has vertices no face uses");
        for (std::size_t f = 0; f < m.faces.size(); ++f)
            if (!(glm::length(face_normal_area2(m, f)) > 0.0))
                throw invalid_input("disk parameterization: face " + std::to_string(f) + " has zero area");
        return m;
    }

    // Face across each edge, and the boundary loop in the direction of its faces' edges.
    void build_adjacency() {
        struct directed {
            std::uint64_t key;
            std::uint32_t slot;  // 3 * face + edge
            bool operator<(const directed& o) const noexcept { return key != o.key ? key < o.key : slot < o.slot; }
        };
        const std::size_t F = mesh_.faces.size();
        std::vector<directed> he;
        he.reserve(3 * F);
        for (std::uint32_t f = 0; f < F; ++f)
            for (std::uint32_t e = 0; e < 3; ++e) {
                const std::uint32_t a = mesh_.faces[f][e], b = mesh_.faces[f][(e + 1) % 3];
                he.push_back({(static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b), 3 * f + e});
            }
        std::sort(he.begin(), he.end());
        across_.assign(3 * F, no_face);
        std::vector<std::uint32_t> next_on_boundary(mesh_.vertices.size(), no_face);
        for (std::size_t i = 0; i < he.size();) {
            if (i + 1 < he.size() && he[i + 1].key == he[i].key) {
                across_[he[i].slot] = he[i + 1].slot / 3;
                across_[he[i + 1].slot] = he[i].slot / 3;
                i += 2;
            } else {
                const std::uint32_t f = he[i].slot / 3, e = he[i].slot % 3;
                next_on_boundary[mesh_.faces[f][e]] = mesh_.faces[f][(e + 1) % 3];
                i += 1;
            }
        }
        std::uint32_t start = no_face;
        for (std::uint32_t v = 0; v < next_on_boundary.size() && start == no_face; ++v)
            if (next_on_boundary[v] != no_face) start = v;
        for (std::uint32_t v = start;;) {
            boundary_.push_back(v);
            v = next_on_boundary[v];
            if (v == start) break;
            if (v == no_face || boundary_.size() > mesh_.vertices.size())
                throw invalid_input("disk parameterization: the boundary is not a simple loop (a vertex where the surface is pinched)");
        }
    }

    void solve(parameterization_border border) {
        const std::size_t nb = boundary_.size();
        if (nb < 3) throw invalid_input("disk parameterization: the boundary loop has fewer than 3 vertices");
        std::vector<double> s(nb + 1, 0.0);  // chord-length parameter along the loop
        for (std::size_t i = 0; i < nb; ++i)
            s[i + 1] = s[i] + glm::length(mesh_.vertices[boundary_[(i + 1) % nb]] - mesh_.vertices[boundary_[i]]);
        Eigen::MatrixXd at(static_cast<Eigen::Index>(nb), 2);
        for (std::size_t i = 0; i < nb; ++i) {
            const vec2 x = border_point(border, s[i] / s[nb]);
            at(static_cast<Eigen::Index>(i), 0) = x.x;
            at(static_cast<Eigen::Index>(i), 1) = x.y;
        }
        const Eigen::MatrixXd x = harmonic_interpolation(mesh_, boundary_, at);
        uv_.resize(mesh_.vertices.size());
        for (std::size_t v = 0; v < uv_.size(); ++v) uv_[v] = {x(static_cast<Eigen::Index>(v), 0), x(static_cast<Eigen::Index>(v), 1)};
        for (std::size_t f = 0; f < mesh_.faces.size(); ++f) {
            const auto& t = mesh_.faces[f];
            if (!(orient2d(uv_[t[0]], uv_[t[1]], uv_[t[2]]) > 0.0))
                throw solver_error("disk parameterization: face " + std::to_string(f) +
                                   " is folded or flat in the domain (a vertex whose cotangent weights are all clamped to 0?)");
        }
    }

    // The point at fraction a in [0, 1) of the border, counter-clockwise from (1, 0) / (1, -1).
    [[nodiscard]] static vec2 border_point(parameterization_border border, double a) {
        if (border == parameterization_border::circle) {
            const double phi = 2.0 * std::numbers::pi * a;
            return {std::cos(phi), std::sin(phi)};
        }
        const double q = 4.0 * a;  // sides: right (up), top (left), left (down), bottom (right)
        const int side = std::min(3, static_cast<int>(q));
        const double r = 2.0 * (q - side) - 1.0;
        switch (side) {
            case 0: return {1.0, r};
            case 1: return {-r, 1.0};
            case 2: return {-1.0, -r};
            default: return {r, -1.0};
        }
    }

    [[nodiscard]] ivec2 bin_of(vec2 x) const {
        const vec2 c = glm::floor((x - lo_) / bin_size_);
        // far-away points: clamp before the integer conversion (then rejected as outside)
        return {static_cast<int>(std::clamp(c.x, -1.0, static_cast<double>(bins_))), static_cast<int>(std::clamp(c.y, -1.0, static_cast<double>(bins_)))};
    }

    void build_grid() {
        lo_ = vec2(-1.0 - 1e-9);
        bins_ = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(mesh_.faces.size())))));
        bin_size_ = (2.0 + 2e-9) / bins_;
        const std::size_t cells = static_cast<std::size_t>(bins_) * static_cast<std::size_t>(bins_);
        std::vector<std::array<ivec2, 2>> range(mesh_.faces.size());
        bin_start_.assign(cells + 1, 0);
        for (std::size_t f = 0; f < mesh_.faces.size(); ++f) {
            const auto& t = mesh_.faces[f];
            const vec2 a = glm::min(uv_[t[0]], glm::min(uv_[t[1]], uv_[t[2]])), b = glm::max(uv_[t[0]], glm::max(uv_[t[1]], uv_[t[2]]));
            const ivec2 i0 = glm::clamp(bin_of(a - vec2(1e-9)), ivec2(0), ivec2(bins_ - 1)), i1 = glm::clamp(bin_of(b + vec2(1e-9)), ivec2(0), ivec2(bins_ - 1));
            range[f] = {i0, i1};
            for (int y = i0.y; y <= i1.y; ++y)
                for (int x = i0.x; x <= i1.x; ++x) ++bin_start_[static_cast<std::size_t>(y) * static_cast<std::size_t>(bins_) + static_cast<std::size_t>(x) + 1];
        }
        for (std::size_t c = 0; c < cells; ++c) bin_start_[c + 1] += bin_start_[c];
        bin_faces_.resize(bin_start_[cells]);
        std::vector<std::uint32_t> fill(bin_start_.begin(), bin_start_.end() - 1);
        for (std::uint32_t f = 0; f < mesh_.faces.size(); ++f)
            for (int y = range[f][0].y; y <= range[f][1].y; ++y)
                for (int x = range[f][0].x; x <= range[f][1].x; ++x)
                    bin_faces_[fill[static_cast<std::size_t>(y) * static_cast<std::size_t>(bins_) + static_cast<std::size_t>(x)]++] = f;
    }

    triangle_mesh mesh_;
    mesh_distance distance_;
    std::vector<std::uint32_t> across_;    // 3 per face
    std::vector<std::uint32_t> boundary_;  // the loop, in order
    std::vector<vec2> uv_;                 // domain position per vertex
    vec2 lo_{0};
    double bin_size_ = 1;
    int bins_ = 1;
    std::vector<std::uint32_t> bin_start_, bin_faces_;  // CSR: faces whose domain box touches each bin
};

}  // namespace fabsynth
