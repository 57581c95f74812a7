// SPDX-License-Identifier: MIT
#pragma once
/// @file polytope.hpp  (internal) Convex polytope clipped by half-spaces, tracking which plane
/// made every face and every edge, so Voronoi edges can be read off a clipped cell.
///
/// Written by hand (no library does this with plane tags at this cost): a face is a convex
/// polygon; a polygon edge carries the tag of the *other* face it borders. Clipping a face is
/// Sutherland-Hodgman; the new cap face is closed by sorting the crossing points by angle, each
/// crossing point being identified by the (unordered) pair of face tags it lies on.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth::foam::detail {

inline constexpr int unknown_tag = -1000;  ///< an edge whose neighbour face could not be identified

/// Workspace-backed convex polytope (reuse one object to avoid allocations).
class polytope {
public:
    struct vertex {
        vec3 p;
        int edge_tag;  ///< tag of the face on the other side of the edge from this vertex to the next
    };
    struct face {
        int tag;
        std::uint32_t begin, end;  ///< range in verts_
    };

    /// Resets to box b; box faces get tags -1 (x lo), -2 (x hi), -3, -4 (y), -5, -6 (z).
    void set_box(const box3& b) {
        faces_.clear();
        verts_.clear();
        const vec3 l = b.lo, h = b.hi;
        auto P = [&](int i) { return vec3((i & 1) ? h.x : l.x, (i & 2) ? h.y : l.y, (i & 4) ? h.z : l.z); };
        // each face: 4 corner indices (bit 0 = x hi, bit 1 = y hi, bit 2 = z hi) in cyclic order
        const int quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
        for (int f = 0; f < 6; ++f) {
            face nf{-(f + 1), static_cast<std::uint32_t>(verts_.size()), 0};
            for (int k = 0; k < 4; ++k) {
                const int a = quads[f][k], c = quads[f][(k + 1) % 4];
                // the other face shares both corners: find the axis where a and c agree, other than f's
                int tag = unknown_tag;
                for (int ax = 0; ax < 3; ++ax) {
                    if (ax == f / 2) continue;
                    const int bit = 1 << ax;
                    if ((a & bit) == (c & bit)) tag = -(2 * ax + ((a & bit) ? 1 : 0) + 1);
                }
                verts_.push_back({P(a), tag});
            }
            nf.end = static_cast<std::uint32_t>(verts_.size());
            faces_.push_back(nf);
        }
    }

    [[nodiscard]] bool empty() const noexcept { return faces_.empty(); }
    [[nodiscard]] const std::vector<face>& faces() const noexcept { return faces_; }
    [[nodiscard]] const std::vector<vertex>& verts() const noexcept { return verts_; }

    /// Largest squared distance from x to a vertex.
    [[nodiscard]] double max_dist2(const vec3& x) const noexcept {
        double m = 0;
        for (const vertex& v : verts_) {
            const vec3 d = v.p - x;
            m = std::max(m, glm::dot(d, d));
        }
        return m;
    }

    /// Keeps the part with dot(n, x) <= d; the new face gets `tag`. Returns false if nothing changed.
    bool clip(const vec3& n, double d, int tag) {
        walk_ok_ = true;
        bool any_out = false;
        for (const vertex& v : verts_)
            if (glm::dot(n, v.p) > d) {
                any_out = true;
                break;
            }
        if (!any_out) return false;
        nfaces_.clear();
        nverts_.clear();
        cross_.clear();
        fcross_.clear();
        for (const face& f : faces_) {
            const std::size_t c0 = cross_.size();
            const std::uint32_t m = f.end - f.begin;
            const std::uint32_t start = static_cast<std::uint32_t>(nverts_.size());
            for (std::uint32_t k = 0; k < m; ++k) {
                const vertex& a = verts_[f.begin + k];
                const vertex& b = verts_[f.begin + (k + 1) % m];
                const double da = glm::dot(n, a.p) - d, db = glm::dot(n, b.p) - d;
                const bool ain = da <= 0, bin = db <= 0;
                if (ain) nverts_.push_back(a);
                if (ain != bin) {
                    const vec3 x = a.p + (da / (da - db)) * (b.p - a.p);
                    nverts_.push_back({x, ain ? tag : a.edge_tag});
                    cross_.push_back({x, std::minmax(f.tag, a.edge_tag)});
                }
            }
            if (cross_.size() - c0 == 2) fcross_.push_back({f.tag, static_cast<int>(c0), static_cast<int>(c0 + 1)});
            else if (cross_.size() != c0) walk_ok_ = false;  // (near-)degenerate: use the angle sort
            if (nverts_.size() - start >= 3) {
                nfaces_.push_back({f.tag, start, static_cast<std::uint32_t>(nverts_.size())});
            } else {
                nverts_.resize(start);
            }
        }
        build_cap(n, tag);
        std::swap(faces_, nfaces_);
        std::swap(verts_, nverts_);
        return true;
    }

private:
    struct crossing {
        vec3 p;
        std::pair<int, int> tags;
    };

    // Monotone in the true angle atan2(y, x) over (-pi, pi], without calling atan2.
    static double pseudo_angle(double x, double y) noexcept {
        const double p = x / (std::abs(x) + std::abs(y) + 1e-300);  // in [-1, 1]
        return y >= 0 ? 1 - p : p - 1;                              // in (-2, 2]
    }

    void build_cap(const vec3& n, int tag) {
        if (walk_ok_ && fcross_.size() >= 3 && walk_cap(tag)) return;
        // every crossing is found twice (once from each face through it): keep one per tag pair
        std::sort(cross_.begin(), cross_.end(), [](const crossing& a, const crossing& b) { return a.tags < b.tags; });
        cross_.erase(std::unique(cross_.begin(), cross_.end(),
                                 [](const crossing& a, const crossing& b) { return a.tags == b.tags; }),
                     cross_.end());
        if (cross_.size() < 3) return;
        vec3 c(0);
        for (const crossing& x : cross_) c += x.p;
        c /= static_cast<double>(cross_.size());
        const vec3 u = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, vec3(1, 0, 0)) : glm::cross(n, vec3(0, 1, 0)));
        const vec3 v = glm::cross(n, u);
        angle_.clear();
        for (std::size_t i = 0; i < cross_.size(); ++i) {
            const vec3 d = cross_[i].p - c;
            angle_.push_back({pseudo_angle(glm::dot(d, u), glm::dot(d, v)), static_cast<int>(i)});
        }
        std::sort(angle_.begin(), angle_.end());
        const std::uint32_t start = static_cast<std::uint32_t>(nverts_.size());
        const std::size_t m = angle_.size();
        for (std::size_t k = 0; k < m; ++k) {
            const crossing& a = cross_[static_cast<std::size_t>(angle_[k].second)];
            const crossing& b = cross_[static_cast<std::size_t>(angle_[(k + 1) % m].second)];
            int shared = unknown_tag;
            const int at[2] = {a.tags.first, a.tags.second}, bt[2] = {b.tags.first, b.tags.second};
            int hits = 0;
            for (int i : at)
                for (int j : bt)
                    if (i == j) shared = i, ++hits;
            nverts_.push_back({a.p, hits == 1 ? shared : unknown_tag});
        }
        nfaces_.push_back({tag, start, static_cast<std::uint32_t>(nverts_.size())});
    }

    std::vector<face> faces_, nfaces_;
    std::vector<vertex> verts_, nverts_;
    // Closes the cap by walking: crossing {f, g} is shared by faces f and g; each cut face holds
    // exactly two crossings, so from a crossing, the other crossing of its second face is the next
    // cap vertex and that face tags the cap edge. Exact (no angles); false if inconsistent.
    bool walk_cap(int tag) {
        const std::size_t m = fcross_.size();
        const std::uint32_t start = static_cast<std::uint32_t>(nverts_.size());
        int cur = fcross_[0].a;  // a crossing index
        int face_tag = fcross_[0].tag;  // the face we arrived through
        for (std::size_t step = 0; step < m; ++step) {
            const crossing& c = cross_[static_cast<std::size_t>(cur)];
            const int other = c.tags.first == face_tag ? c.tags.second : c.tags.first;
            // find face `other` and its crossing that is not at the same tag pair as cur
            int next = -1;
            for (const fc& f : fcross_)
                if (f.tag == other) {
                    next = cross_[static_cast<std::size_t>(f.a)].tags == c.tags ? f.b : f.a;
                    break;
                }
            if (next < 0) {
                nverts_.resize(start);
                return false;
            }
            nverts_.push_back({c.p, other});
            face_tag = other;
            cur = next;
            if (cross_[static_cast<std::size_t>(cur)].tags == cross_[static_cast<std::size_t>(fcross_[0].a)].tags) {
                if (step + 1 != m) break;
                nfaces_.push_back({tag, start, static_cast<std::uint32_t>(nverts_.size())});
                return true;
            }
        }
        nverts_.resize(start);
        return false;
    }

    struct fc {
        int tag, a, b;  // face tag and its two crossings (indices into cross_)
    };
    std::vector<fc> fcross_;
    bool walk_ok_ = true;
    std::vector<crossing> cross_;
    std::vector<std::pair<double, int>> angle_;
};

}  // namespace fabsynth::foam::detail
