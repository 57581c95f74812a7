#pragma once
// Independent explicit Voronoi-edge construction used as the oracle of the foam evaluator.
// Enumerates seed triples (i < j < k); the equidistant line of a triple is clipped by the
// half-spaces of every other seed within 2 Rb of s_i and by |x - s_i| <= Rb, where Rb bounds the
// nearest-seed distance over the region E (measured on a grid with a Lipschitz margin). An edge
// point p of E is equidistant to its nearest seeds at distance r(p) <= Rb, so no other seed
// matters and nothing outside is needed. Nothing is shared with the evaluator but the seeds.
#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/foam/evaluator.hpp"

namespace reftest {

using fabsynth::box3;
using fabsynth::vec3;
using fabsynth::foam::edge_segment;

struct cloud {
    std::vector<vec3> pts;
    [[nodiscard]] std::size_t kdtree_get_point_count() const { return pts.size(); }
    [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t d) const { return pts[i][static_cast<int>(d)]; }
    template <class B>
    bool kdtree_get_bbox(B&) const {
        return false;
    }
};
using kd_tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, cloud>, cloud, 3>;

class reference_edges {
public:
    /// seeds: every seed in a generous box around E; E: region where edges must be exact.
    reference_edges(std::vector<vec3> seeds, const box3& E, double grid_step = 0.1) : E_(E) {
        pc_.pts = std::move(seeds);
        kd_tree tree(3, pc_, nanoflann::KDTreeSingleIndexAdaptorParams(10));
        tree.buildIndex();
        // Rb: max nearest-seed distance over E (grid samples + half the grid diagonal)
        double rb = 0;
        const vec3 sz = E.size();
        const int nx = static_cast<int>(std::ceil(sz.x / grid_step)), ny = static_cast<int>(std::ceil(sz.y / grid_step)),
                  nz = static_cast<int>(std::ceil(sz.z / grid_step));
        const vec3 st = sz / vec3(nx, ny, nz);
        for (int z = 0; z <= nz; ++z)
            for (int y = 0; y <= ny; ++y)
                for (int x = 0; x <= nx; ++x) {
                    const vec3 p = E.lo + st * vec3(x, y, z);
                    unsigned idx;
                    double d2;
                    nanoflann::KNNResultSet<double, unsigned> rs(1);
                    rs.init(&idx, &d2);
                    const double q[3] = {p.x, p.y, p.z};
                    tree.findNeighbors(rs, q, nanoflann::SearchParams(10));
                    rb = std::max(rb, std::sqrt(d2));
                }
        rb += 0.5 * glm::length(st) + 1e-9;
        rb_ = rb;
        const auto& S = pc_.pts;
        std::vector<std::pair<unsigned, double>> nb;
        std::vector<std::size_t> N;
        for (std::size_t i = 0; i < S.size(); ++i) {
            const vec3 si = S[i];
            const vec3 cl = glm::clamp(si, E.lo, E.hi);
            if (glm::length(cl - si) > rb) continue;
            const double q[3] = {si.x, si.y, si.z};
            nb.clear();
            tree.radiusSearch(q, 4 * rb * rb * (1 + 1e-9), nb, nanoflann::SearchParams(10, 0, true));  // sorted
            N.clear();
            for (const auto& [j, d2] : nb)
                if (j != i) N.push_back(j);
            for (std::size_t a = 0; a < N.size(); ++a) {
                const std::size_t j = N[a];
                if (j < i) continue;
                for (std::size_t b = 0; b < N.size(); ++b) {
                    const std::size_t k = N[b];
                    if (k <= j) continue;
                    edge_for(i, j, k, N);
                }
            }
        }
        // bucket the segments
        cell_ = 0.5;
        gdim_ = glm::ivec3(glm::ceil(sz / cell_)) + 1;
        buckets_.assign(static_cast<std::size_t>(gdim_.x * gdim_.y * gdim_.z), {});
        for (std::size_t s = 0; s < segs_.size(); ++s) {
            const glm::ivec3 lo = bucket(glm::min(segs_[s].a, segs_[s].b)), hi = bucket(glm::max(segs_[s].a, segs_[s].b));
            for (int z = lo.z; z <= hi.z; ++z)
                for (int y = lo.y; y <= hi.y; ++y)
                    for (int x = lo.x; x <= hi.x; ++x) buckets_[index({x, y, z})].push_back(s);
        }
    }

    [[nodiscard]] double rb() const { return rb_; }
    [[nodiscard]] std::size_t size() const { return segs_.size(); }

    /// Distance from q (inside E shrunk by r) to the edges, if <= r; else +inf.
    [[nodiscard]] double distance(const vec3& q, double r) const {
        double best = std::numeric_limits<double>::infinity();
        const glm::ivec3 lo = bucket(q - vec3(r)), hi = bucket(q + vec3(r));
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x)
                    for (std::size_t s : buckets_[index({x, y, z})])
                        best = std::min(best, point_segment_distance(q, segs_[s].a, segs_[s].b));
        return best <= r ? best : std::numeric_limits<double>::infinity();
    }

private:
    // The oracle's own point-segment distance (shares no code with the evaluator).
    static double point_segment_distance(const vec3& q, const vec3& a, const vec3& b) {
        const vec3 d = b - a;
        double t = glm::dot(q - a, d) / std::max(glm::dot(d, d), 1e-300);
        t = t < 0 ? 0 : (t > 1 ? 1 : t);
        return glm::distance(q, a + t * d);
    }
    void edge_for(std::size_t i, std::size_t j, std::size_t k, const std::vector<std::size_t>& N) {
        const auto& S = pc_.pts;
        const vec3 si = S[i], sj = S[j], sk = S[k];
        if (glm::length(sj - sk) > 2 * rb_) return;
        const vec3 n1 = sj - si, n2 = sk - si, d = glm::cross(n1, n2);
        const double dl = glm::length(d);
        if (dl < 1e-12) return;
        const vec3 u = d / dl;
        const double r1 = 0.5 * (glm::dot(sj, sj) - glm::dot(si, si)), r2 = 0.5 * (glm::dot(sk, sk) - glm::dot(si, si)),
                     r3 = glm::dot(u, si);
        // rows n1, n2, u; Cramer's rule
        const double det = glm::dot(n1, glm::cross(n2, u));
        const vec3 p0 = (r1 * glm::cross(n2, u) + r2 * glm::cross(u, n1) + r3 * glm::cross(n1, n2)) / det;
        // |p0 + t u - si| <= rb
        const vec3 w = p0 - si;
        const double bq = glm::dot(w, u), disc = bq * bq - glm::dot(w, w) + rb_ * rb_;
        if (disc < 0) return;
        double lo = -bq - std::sqrt(disc), hi = -bq + std::sqrt(disc);
        for (std::size_t m : N) {
            if (m == j || m == k) continue;
            const vec3 sm = S[m];
            const vec3 a = sm - si;
            const double c = 0.5 * (glm::dot(sm, sm) - glm::dot(si, si)) - glm::dot(a, p0);  // a.(p0 + t u) <= ...
            const double au = glm::dot(a, u);
            if (au > 0) hi = std::min(hi, c / au);
            else if (au < 0) lo = std::max(lo, c / au);
            else if (c < 0) return;
            if (lo > hi) return;
        }
        segs_.push_back({p0 + lo * u, p0 + hi * u});
    }
    [[nodiscard]] glm::ivec3 bucket(const vec3& p) const {
        return glm::clamp(glm::ivec3(glm::floor((p - E_.lo) / cell_)), glm::ivec3(0), gdim_ - 1);
    }
    [[nodiscard]] std::size_t index(const glm::ivec3& b) const {
        return static_cast<std::size_t>((b.z * gdim_.y + b.y) * gdim_.x + b.x);
    }

    box3 E_;
    cloud pc_;
    double rb_ = 0;
    std::vector<edge_segment> segs_;
    double cell_ = 0.5;
    glm::ivec3 gdim_{1};
    std::vector<std::vector<std::size_t>> buckets_;
};

}  // namespace reftest
