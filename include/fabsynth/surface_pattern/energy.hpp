// SPDX-License-Identifier: MIT
#pragma once
/// @file energy.hpp  The synthesis energy of structurally-sound-patterns.md §4.2 on one pyramid level.
///
///   E = sum_v [ (1 / |N(v)|) E_transition(v) + lambda E_distortion(v) + P(v) ]
///   E_transition(v) = sum_{w in N(v)} ||I(M(v, c_v)) - I(M(v, c_w))||^2 + ||I(M(w, c_v)) - I(M(w, c_w))||^2
///   E_distortion(v) = 1 - n(v) . n(psi(v))
///
/// N(v) is the 5x5x5 neighbourhood (shell.hpp), I the Gaussian-stack level of the voxel level
/// (exemplar.hpp), c = (psi, tau) the labels.
///
/// Where this departs from the paper's text, and why:
/// - The paper prints the first transition term as ||I(M(v, c_v)) - I(M(w, c_w))||^2, which compares
///   the colours of two different points and is not zero inside a coherent patch (all c equal), so
///   it would penalise every pattern with detail. §4.2.1 and Fig. 5 describe the intended term:
///   "the colors the neighborhood expects and the color the voxel has, and vice versa", i.e. w's
///   mapping evaluated at v against v's colour. We use that: I(M(v, c_w)). Both terms are then zero
///   for coherent labels and the sum is symmetric in (v, w).
/// - Transitions are averaged over the neighbourhood (1 / |N(v)|) and the distortion is weighted by
///   lambda: with colours in [0, 1] the paper's plain sum lets ~40 neighbour terms drown the
///   distortion, so patches would stretch across curved areas instead of changing plane.
/// - P(v) is the boundary penalty for exemplars that do not tile (§6.1, after Lefebvre & Hoppe
///   2005): a constant added when M(v, c_v) falls within the neighbourhood's footprint of the
///   exemplar's border, so that no chosen neighbourhood straddles the seam. Zero for tileable ones.
///
/// Because S(v, w) = S(w, v), changing c_v alone changes E by exactly the change of
///   L_v(c) = sum_w (1/|N(v)| + 1/|N(w)|) S(v, w; c) + lambda (1 - n(v) . n(psi)) + P
/// which is what local() evaluates: greedy updates of voxels that are not neighbours of each other
/// never increase E.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/surface_pattern/exemplar.hpp"
#include "fabsynth/surface_pattern/labels.hpp"
#include "fabsynth/surface_pattern/shell.hpp"

namespace fabsynth::surface_pattern {

/// Weights of the energy terms.
struct energy_options {
    double distortion_weight = 1.0;  ///< lambda (>= 0)
    double border_penalty = 4.0;     ///< P for non-tileable exemplars (>= 0)
};

namespace detail {

/// Bilinear lookup of C interleaved channels at continuous pixel coordinates (pixel centres at
/// i + 0.5), the image tiled in both directions. Coordinates are shifted by a large multiple of the
/// period so that truncation is floor (valid for |coordinate| < 2^20 periods, far beyond any
/// mapped voxel), and power-of-two sizes wrap by a mask instead of a division.
template <int C>
struct tiled_sampler {
    const float* data = nullptr;
    int w = 1, h = 1;
    tiled_sampler() = default;
    tiled_sampler(const float* d, int width, int height) noexcept
        : data(d), w(width), h(height), shift_x(std::ldexp(static_cast<double>(width), 20) + 0.5),
          shift_y(std::ldexp(static_cast<double>(height), 20) + 0.5), pow2((width & (width - 1)) == 0 && (height & (height - 1)) == 0) {}
    void operator()(vec2 p, float* out) const noexcept {
        const double u = p.x - 0.5 + shift_x, v = p.y - 0.5 + shift_y;  // >= 0 here: truncation is floor
        const auto iu = static_cast<std::int64_t>(u), iv = static_cast<std::int64_t>(v);
        const float ax = static_cast<float>(u - static_cast<double>(iu)), ay = static_cast<float>(v - static_cast<double>(iv));
        int x0, y0;
        if (pow2) {
            x0 = static_cast<int>(iu & (w - 1)), y0 = static_cast<int>(iv & (h - 1));
        } else {
            x0 = static_cast<int>(iu % w), y0 = static_cast<int>(iv % h);
        }
        const int x1 = x0 + 1 == w ? 0 : x0 + 1, y1 = y0 + 1 == h ? 0 : y0 + 1;
        const std::size_t r0 = static_cast<std::size_t>(y0) * static_cast<std::size_t>(w), r1 = static_cast<std::size_t>(y1) * static_cast<std::size_t>(w);
        const float* p00 = data + (r0 + static_cast<std::size_t>(x0)) * C;
        const float* p10 = data + (r0 + static_cast<std::size_t>(x1)) * C;
        const float* p01 = data + (r1 + static_cast<std::size_t>(x0)) * C;
        const float* p11 = data + (r1 + static_cast<std::size_t>(x1)) * C;
        for (int c = 0; c < C; ++c)
            out[c] = (1 - ay) * ((1 - ax) * p00[c] + ax * p10[c]) + ay * ((1 - ax) * p01[c] + ax * p11[c]);
    }

private:
    double shift_x = 0.5, shift_y = 0.5;
    bool pow2 = false;
};

template <int C>
[[nodiscard]] inline float squared_difference(const float* a, const float* b) noexcept {
    float s = 0;
    for (int c = 0; c < C; ++c) s += (a[c] - b[c]) * (a[c] - b[c]);
    return s;
}

}  // namespace detail

/// The energy of one level for C exemplar channels (2 without colour, 5 with): the current colour
/// cache I(M(v, c_v)), the local objective L_v of a candidate and the total E.
template <int C>
class level_energy {
public:
    /// @param labels  the level's labels (one per voxel); read at every call, so updates are seen
    /// @param stack_level  the Gaussian-stack level sampled (normally the voxel level)
    level_energy(const shell_level& lv, const shell_neighbourhood& nb, const label_space& ls, const exemplar& ex, int stack_level,
                 const energy_options& opt, const std::vector<std::uint32_t>& labels)
        : lv_(lv), nb_(nb), ls_(ls), ex_(ex), opt_(opt), labels_(labels) {
        if (ex.channels() != C) throw invalid_input("level energy: exemplar channel count does not match");
        sample_ = detail::tiled_sampler<C>(ex.level(stack_level), ex.width(), ex.height());
        const int side = 2 * nb.radius + 1;
        offsets_.resize(static_cast<std::size_t>(side * side * side));
        for (int code = 0; code < side * side * side; ++code) {
            const ivec3 d(code % side - nb.radius, (code / side) % side - nb.radius, code / (side * side) - nb.radius);
            offsets_[static_cast<std::size_t>(code)] = vec3(d) * lv.geometry.spacing;
        }
        inv_count_.resize(lv.size());
        for (std::size_t v = 0; v < lv.size(); ++v) inv_count_[v] = nb.count(v) ? 1.0f / static_cast<float>(nb.count(v)) : 0.0f;
        colour_.resize(lv.size() * C);
        // the footprint of a neighbourhood in exemplar pixels: kept away from the border of a non-tileable exemplar
        border_margin_px_ = (nb.radius + 1.0) * std::sqrt(3.0) * lv.geometry.spacing.x / ls.options().mm_per_px;
        refresh_all();
    }

    [[nodiscard]] std::size_t size() const noexcept { return lv_.size(); }
    [[nodiscard]] const shell_level& level() const noexcept { return lv_; }
    [[nodiscard]] const shell_neighbourhood& neighbours() const noexcept { return nb_; }
    [[nodiscard]] const label_space& labels_space() const noexcept { return ls_; }
    [[nodiscard]] const exemplar& source() const noexcept { return ex_; }

    /// I(M(v, c_v)) for every voxel (after labels changed wholesale).
    void refresh_all() {
        parallel_for(0, lv_.size(), [&](std::size_t v) { refresh(v); }, {.grain = 1024});
    }
    /// I(M(v, c_v)) for one voxel (after its label changed).
    void refresh(std::size_t v) noexcept { sample_(ls_.map(lv_.center(v), labels_[v]), &colour_[v * C]); }
    [[nodiscard]] const float* colour(std::size_t v) const noexcept { return &colour_[v * C]; }

    /// Weighted moments of the expected colours e_k with pair weights w_k: sum w_k, sum w_k e_k and
    /// sum w_k |e_k|^2. The terms at v, sum_k w_k |I(M(v, c)) - e_k|^2, are then
    /// W |i|^2 - 2 i . S1 + S2 for i = I(M(v, c)): O(C) per candidate instead of O(|N(v)| C).
    struct moments {
        double w = 0, s2 = 0;
        double s1[C]{};
    };
    /// Scratch size per voxel for expected(): C floats per neighbour plus one weight.
    [[nodiscard]] std::size_t expected_size(std::size_t v) const noexcept { return static_cast<std::size_t>(nb_.count(v)) * (C + 1); }
    /// What local() needs about v's neighbours, computed once per voxel and pass: out[k C + c] =
    /// I(M(v, c_w)) for the k-th neighbour w (what its mapping expects at v), then the pair weights
    /// 1/|N(v)| + 1/|N(w)|; their moments in `m`.
    void expected(std::size_t v, float* out, moments& m) const noexcept {
        const vec3 x = lv_.center(v);
        const std::uint32_t n = nb_.count(v);
        m = moments{};
        for (std::uint32_t k = nb_.offset[v], j = 0; k < nb_.offset[v + 1]; ++k, ++j) {
            float* e = out + j * C;
            if (labels_[nb_.index[k]] == labels_[v]) std::copy_n(&colour_[v * C], C, e);  // the same lookup, already cached
            else sample_(ls_.map(x, labels_[nb_.index[k]]), e);
            const float w = inv_count_[v] + inv_count_[nb_.index[k]];
            out[n * C + j] = w;
            m.w += w;
            for (int c = 0; c < C; ++c) {
                m.s1[c] += static_cast<double>(w) * e[c];
                m.s2 += static_cast<double>(w) * e[c] * e[c];
            }
        }
    }

    /// Border penalty P of a label at voxel v.
    [[nodiscard]] double penalty(std::size_t v, std::uint32_t label) const noexcept {
        if (ex_.tileable() || opt_.border_penalty == 0) return 0.0;
        const vec2 p = ls_.map(lv_.center(v), label);
        const double W = ex_.width(), H = ex_.height();
        const double x = p.x - W * std::floor(p.x / W), y = p.y - H * std::floor(p.y / H);
        const double d = std::min({x, W - x, y, H - y});
        return d < border_margin_px_ ? opt_.border_penalty : 0.0;
    }
    /// lambda (1 - n(v) . n(psi)): a lower bound of L_v for every label on plane psi.
    [[nodiscard]] double distortion(std::size_t v, int plane) const noexcept {
        return opt_.distortion_weight * (1.0 - glm::dot(lv_.normals[v], ls_.normal(plane)));
    }
    /// lambda (1 - n(v) . n(psi)) + P.
    [[nodiscard]] double unary(std::size_t v, std::uint32_t label) const noexcept {
        return distortion(v, ls_.plane(label)) + penalty(v, label);
    }

    /// L_v(label) (file comment) given expected(v) in `exp` and `mom`; stops once the sum reaches
    /// `bound` and returns a value >= bound then (branch and bound over the candidates). The terms at
    /// v, which need one lookup, come first (through the moments); the lookups at the neighbours follow.
    [[nodiscard]] double local(std::size_t v, std::uint32_t label, const float* exp, const moments& mom,
                               double bound = std::numeric_limits<double>::infinity()) const noexcept {
        double e = unary(v, label);
        if (e >= bound) return e;
        const plane_map m = ls_.map_of(label);
        const vec2 px = m(lv_.center(v));
        float iv[C], iw[C];
        sample_(px, iv);
        double ii = 0, is1 = 0;
        for (int c = 0; c < C; ++c) ii += static_cast<double>(iv[c]) * iv[c], is1 += static_cast<double>(iv[c]) * mom.s1[c];
        e += std::max(0.0, mom.w * ii - 2 * is1 + mom.s2);  // the terms at v (moments; >= 0 up to rounding)
        if (e >= bound) return e;
        const std::uint32_t n = nb_.count(v), first = nb_.offset[v];
        const float* weight = exp + static_cast<std::size_t>(n) * C;
        for (std::uint32_t j = 0; j < n; ++j) {
            const std::uint32_t k = first + j;
            if (labels_[nb_.index[k]] == label) continue;  // I(M(w, c)) is w's own colour: the term is 0
            sample_(px + m.linear(offsets_[nb_.code[k]]), iw);
            e += static_cast<double>(weight[j] * detail::squared_difference<C>(iw, &colour_[static_cast<std::size_t>(nb_.index[k]) * C]));
            if (e >= bound) return e;
        }
        return e;
    }

    /// Contribution of voxel v to E: (1/|N(v)|) E_transition(v) + lambda E_distortion(v) + P(v).
    [[nodiscard]] double voxel_energy(std::size_t v) const noexcept {
        const vec3 x = lv_.center(v);
        const std::uint32_t cv = labels_[v];
        const plane_map mv = ls_.map_of(cv);
        const vec2 pv = mv(x);
        double t = 0;
        float a[C], b[C];
        for (std::uint32_t k = nb_.offset[v]; k < nb_.offset[v + 1]; ++k) {
            const std::uint32_t w = nb_.index[k];
            if (labels_[w] == cv) continue;  // coherent pair: both terms are 0
            sample_(ls_.map(x, labels_[w]), a);  // I(M(v, c_w)) against I(M(v, c_v))
            t += detail::squared_difference<C>(colour(v), a);
            sample_(pv + mv.linear(offsets_[nb_.code[k]]), b);  // I(M(w, c_v)) against I(M(w, c_w))
            t += detail::squared_difference<C>(b, colour(w));
        }
        return inv_count_[v] * t + unary(v, cv);
    }
    /// E over the level (deterministic sum for any thread count).
    [[nodiscard]] double total() const {
        return parallel_reduce(std::size_t{0}, lv_.size(), 0.0, [&](std::size_t v) { return voxel_energy(v); },
                               [](double a, double b) { return a + b; });
    }

private:
    const shell_level& lv_;
    const shell_neighbourhood& nb_;
    const label_space& ls_;
    const exemplar& ex_;
    energy_options opt_;
    const std::vector<std::uint32_t>& labels_;
    detail::tiled_sampler<C> sample_;
    std::vector<vec3> offsets_;  // neighbour offset per code (mm)
    std::vector<float> inv_count_;
    std::vector<float> colour_;
    double border_margin_px_ = 0;
};

}  // namespace fabsynth::surface_pattern
