// SPDX-License-Identifier: MIT
#pragma once
/// @file synthesis.hpp  The on-surface texture synthesizer (structurally-sound-patterns.md §4.3,
/// Algorithms 2-3) and the constrained resynthesis of §4.4.
///
/// Usage:
///   namespace sp = fabsynth::surface_pattern;
///   sp::synthesizer syn(pyramid, std::move(ex), {.mm_per_px = 0.4, .seed = 7});
///   sp::synthesis_result r = syn.synthesize();        // labels on every level, r.solid on level 0
///   syn.resynthesize(r, forced, allowed, 6.0);         // part 2's structural loop (§4.4)
///
/// SYNTHESIZETEXTURE: labels start as label 0 on the coarsest level; going from the coarsest to the
/// finest level, each level is UPSAMPLEd (children copy their parent's label), JITTERed (a user
/// fraction of the voxels takes a random label) and OPTIMIZEd. Unlike Algorithm 2 the coarsest level
/// is optimized too (its upsample is the initial label), so planes follow the normals from the start.
///
/// OPTIMIZE (Algorithm 3): per voxel, the candidates are the current label, the distinct labels of the
/// 5x5x5 neighbours (coherent candidates) and random labels up to `candidates` in total: a direction
/// drawn uniformly in a cone of `cone_degrees` around the voxel normal snapped to the best-aligned
/// plane, a uniform translation, and a rotation that is uniform or, with orientation control, the
/// one that makes the exemplar's up direction follow the user's 'up' projected on the surface (the
/// paper's "naive vector field around the 'up' direction"; §4.3: tau "biased towards a predefined
/// orientation"). The candidate of lowest local energy (energy.hpp) wins; ties keep the current one.
/// Candidates are evaluated by branch and bound against the best so far, and a random candidate
/// whose plane's distortion alone reaches it is discarded before its transform is drawn (it could
/// not win), so most of the 128 cost a plane draw and one exemplar lookup.
///
/// Parallel sub-passes (after Lefebvre & Hoppe 2005): a pass visits the 27 classes
/// (x mod 3, y mod 3, z mod 3) in order and updates each class in parallel. Two voxels of one class
/// are at least 3 apart along some axis, so neither is in the other's 5x5x5 neighbourhood: the
/// updates of a class are independent, the result does not depend on the thread count, and no pass
/// increases the energy. Every random number is a counter-based hash of (seed, round, level, pass,
/// voxel) (core/rng.hpp).
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <functional>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/surface_pattern/energy.hpp"
#include "fabsynth/surface_pattern/exemplar.hpp"
#include "fabsynth/surface_pattern/labels.hpp"
#include "fabsynth/surface_pattern/shell.hpp"

namespace fabsynth::surface_pattern {

/// Parameters of the synthesizer (defaults: the paper's §6.1 settings where it gives them).
struct synthesis_options {
    double mm_per_px = 0;        ///< exemplar scale (mm per exemplar pixel); 0 = one finest voxel per pixel
    int translations = 16;       ///< translations per axis
    int rotations = 64;          ///< rotations per plane
    int candidates = 128;        ///< coherent + random candidates per voxel and pass (>= 1)
    double cone_degrees = 35;    ///< half-angle of the cone around the normal for random planes (0 .. 180)
    double jitter = 0.1;         ///< fraction of voxels given a random label after upsampling, per level ([0, 1])
    vec3 up{0, 0, 1};            ///< orientation control: the pattern's up follows this direction projected on the surface
    bool orient = true;          ///< false: random rotations are uniform
    int passes = 2;              ///< optimization passes per level (>= 1)
    int radius = 2;              ///< neighbourhood half-size: 2 = the paper's 5x5x5
    energy_options energy{};
    std::uint64_t seed = 1;
    /// Non-empty: the only labels allowed (label_space::make). Random candidates and jitter draw
    /// from it uniformly and the coarsest level starts at its first entry (fixed mappings, tests).
    std::vector<std::uint32_t> allowed_labels{};
};

/// What happened on one level.
struct level_report {
    int level = 0;
    std::size_t voxels = 0;
    double spacing_mm = 0;
    double sigma_px = 0;                ///< Gaussian-stack blur used on this level
    double energy_initial = 0;          ///< after upsample + jitter
    std::vector<double> energy_passes;  ///< after each pass
    std::uint64_t candidates = 0;       ///< candidate labels evaluated
    double seconds = 0;
};

/// Labels of every level, the finest level's states, and the per-level reports.
struct synthesis_result {
    std::vector<std::vector<std::uint32_t>> labels;  ///< labels[l][v], l = 0 finest
    std::vector<std::uint8_t> solid;                 ///< state s of every level-0 voxel (1 = solid)
    std::vector<level_report> levels;                ///< finest first
    double seconds = 0;
};

/// What a constrained resynthesis did.
struct resynthesis_report {
    int start_level = 0;                     ///< log2(r_pattern) levels up (clamped to the pyramid)
    std::vector<std::size_t> updated;        ///< voxels re-synthesized per level (finest first)
    std::size_t forced = 0;                  ///< forced level-0 voxels
    std::size_t unsatisfied = 0;             ///< forced voxels no examined label maps to solid (kept solid anyway)
    std::vector<level_report> levels;
};

/// The synthesizer over a shell pyramid and an exemplar (both kept; see the file comment).
class synthesizer {
public:
    /// Builds the exemplar's Gaussian stack for the pyramid (sigma_l = 0.5 sqrt(d_l^2 - 1) for a
    /// level whose voxels are d_l exemplar pixels apart, 0 where d_l <= 1) and the neighbourhoods.
    /// Throws invalid_input for bad options.
    synthesizer(const shell_pyramid& pyramid, exemplar ex, const synthesis_options& opt)
        : pyr_(pyramid), ex_(std::move(ex)), opt_(opt) {
        if (pyramid.levels.empty()) throw invalid_input("synthesizer: empty pyramid");
        const double h = pyramid.levels[0].geometry.spacing.x;
        if (opt_.mm_per_px == 0) opt_.mm_per_px = h;
        if (!(std::isfinite(opt_.mm_per_px) && opt_.mm_per_px > 0))
            throw invalid_input("synthesizer: exemplar scale must be finite and > 0 mm per pixel, got " + std::to_string(opt_.mm_per_px));
        if (opt_.candidates < 1 || opt_.candidates > 4096) throw invalid_input("synthesizer: candidates must be in [1, 4096]");
        if (!(opt_.cone_degrees >= 0 && opt_.cone_degrees <= 180)) throw invalid_input("synthesizer: cone angle must be in [0, 180] degrees");
        if (!(opt_.jitter >= 0 && opt_.jitter <= 1)) throw invalid_input("synthesizer: jitter must be in [0, 1], got " + std::to_string(opt_.jitter));
        if (opt_.passes < 1 || opt_.passes > 64) throw invalid_input("synthesizer: passes must be in [1, 64]");
        if (!(opt_.energy.distortion_weight >= 0 && std::isfinite(opt_.energy.distortion_weight)) ||
            !(opt_.energy.border_penalty >= 0 && std::isfinite(opt_.energy.border_penalty)))
            throw invalid_input("synthesizer: energy weights must be finite and >= 0");
        if (ex_.channels() != 2 && ex_.channels() != 5) throw invalid_input("synthesizer: exemplar must have 2 or 5 channels");
        const vec3 up = opt_.up;
        if (!(std::isfinite(up.x) && std::isfinite(up.y) && std::isfinite(up.z))) throw invalid_input("synthesizer: up direction is not finite");
        if (glm::length(up) == 0) opt_.orient = false;
        one_minus_cos_ = 1.0 - std::cos(opt_.cone_degrees * std::numbers::pi / 180.0);
        labels_ = label_space(ex_.width(), ex_.height(),
                              {.mm_per_px = opt_.mm_per_px, .translations = opt_.translations, .rotations = opt_.rotations,
                               .up = glm::length(up) > 0 ? up : vec3(0, 0, 1)});
        for (std::uint32_t l : opt_.allowed_labels)
            if (!labels_.valid(l)) throw invalid_input("synthesizer: allowed label " + std::to_string(l) + " is out of range");
        std::vector<double> sigmas;
        for (const shell_level& lv : pyramid.levels) {
            const double d = lv.geometry.spacing.x / opt_.mm_per_px;
            sigmas.push_back(d > 1 ? 0.5 * std::sqrt(d * d - 1) : 0.0);
        }
        ex_.build_stack(sigmas);
        for (const shell_level& lv : pyramid.levels) {
            nbs_.push_back(build_neighbourhood(lv, opt_.radius));
            std::vector<std::vector<std::uint32_t>> cls(27);
            for (std::size_t v = 0; v < lv.size(); ++v) {
                const ivec3 p = lv.voxels[v];
                cls[static_cast<std::size_t>(p.x % 3 + 3 * (p.y % 3) + 9 * (p.z % 3))].push_back(static_cast<std::uint32_t>(v));
            }
            classes_.push_back(std::move(cls));
        }
    }

    [[nodiscard]] const shell_pyramid& pyramid() const noexcept { return pyr_; }
    [[nodiscard]] const exemplar& source() const noexcept { return ex_; }
    [[nodiscard]] const label_space& labels() const noexcept { return labels_; }
    [[nodiscard]] const synthesis_options& options() const noexcept { return opt_; }
    [[nodiscard]] const shell_neighbourhood& neighbours(int level) const { return nbs_.at(static_cast<std::size_t>(level)); }

    /// Initial synthesis (Algorithm 2). `progress(fraction, stage)` is called per level.
    template <progress_callback P = no_progress>
    [[nodiscard]] synthesis_result synthesize(P&& progress = {}) const {
        return ex_.channels() == 2 ? run_synthesis<2>(progress) : run_synthesis<5>(progress);
    }

    /// Constrained resynthesis (§4.4). `forced` and `allowed` have one flag per level-0 voxel:
    /// forced voxels may only take labels that map them to solid; parents of forced voxels are
    /// forced; synthesis resumes ceil(log2(r_pattern_voxels)) levels up (r_pattern in finest voxels),
    /// restricted to the voxels below the forced parents on that level that are (or have a
    /// descendant) in `allowed` (forced voxels are always allowed). Every other label, on every
    /// level, is left as it was. `round` keys the random numbers (one per call of a loop).
    /// Updates r.labels and r.solid; forced voxels end solid (r.solid = 1) in any case, and the
    /// report counts those whose label could not be made to map them to solid.
    template <progress_callback P = no_progress>
    resynthesis_report resynthesize(synthesis_result& r, std::span<const std::uint8_t> forced, std::span<const std::uint8_t> allowed,
                                    double r_pattern_voxels, std::uint64_t round = 1, P&& progress = {}) const {
        return ex_.channels() == 2 ? run_resynthesis<2>(r, forced, allowed, r_pattern_voxels, round, progress)
                                   : run_resynthesis<5>(r, forced, allowed, r_pattern_voxels, round, progress);
    }

    /// State s (1 = solid) of each voxel of `level` under `labels`: the exemplar mask at M(v, c_v).
    [[nodiscard]] std::vector<std::uint8_t> states(int level, const std::vector<std::uint32_t>& labels) const {
        const shell_level& lv = pyr_.levels.at(static_cast<std::size_t>(level));
        check_labels(level, labels);
        std::vector<std::uint8_t> s(lv.size());
        parallel_for(0, lv.size(), [&](std::size_t v) { s[v] = solid_at(labels_.map(lv.center(v), labels[v])) ? 1 : 0; }, {.grain = 1024});
        return s;
    }
    /// Colour of each voxel of `level` (the colour image, or grey mask, at M(v, c_v)): previews.
    [[nodiscard]] std::array<std::uint8_t, 3> colour_at(int level, const std::vector<std::uint32_t>& labels, std::size_t v) const {
        const shell_level& lv = pyr_.levels.at(static_cast<std::size_t>(level));
        const vec2 p = labels_.map(lv.center(v), labels.at(v));
        return ex_.colour_at(p.x, p.y);
    }
    /// Energy E of `level` under `labels` (energy.hpp).
    [[nodiscard]] double energy(int level, const std::vector<std::uint32_t>& labels) const {
        check_labels(level, labels);
        if (ex_.channels() == 2) return level_energy<2>(lv(level), nbs_[static_cast<std::size_t>(level)], labels_, ex_, level, opt_.energy, labels).total();
        return level_energy<5>(lv(level), nbs_[static_cast<std::size_t>(level)], labels_, ex_, level, opt_.energy, labels).total();
    }
    /// What random candidates of one voxel are drawn from: the cone's frame around the normal and,
    /// with orientation control, the oriented rotation per plane (computed on first use).
    struct candidate_source {
        vec3 n{0}, t1{0}, t2{0}, field{0};
        bool oriented = false;
        std::array<std::int16_t, label_space::plane_count> rotation{};
    };
    [[nodiscard]] candidate_source source_of(int level, std::size_t v) const {
        candidate_source s;
        s.n = lv(level).normals.at(v);
        s.t1 = glm::normalize(std::abs(s.n.x) < 0.9 ? glm::cross(s.n, vec3(1, 0, 0)) : glm::cross(s.n, vec3(0, 1, 0)));
        s.t2 = glm::cross(s.n, s.t1);
        s.rotation.fill(-1);
        if (opt_.orient) {
            const vec3 up = glm::normalize(opt_.up);
            s.field = up - glm::dot(up, s.n) * s.n;  // 'up' projected on the tangent plane
            s.oriented = glm::length(s.field) > 0.1;  // near the poles of the field: uniform rotations
        }
        return s;
    }
    /// One random label (cone-snapped plane, uniform translation, uniform or oriented rotation).
    /// The direction is uniform on the spherical cap: a uniform point of the unit disk at radius r
    /// maps to cos(theta) = 1 - r^2 (1 - cos(alpha)), which is uniform in [cos(alpha), 1].
    [[nodiscard]] std::uint32_t draw(candidate_source& s, counter_rng& rng) const {
        if (!opt_.allowed_labels.empty()) return opt_.allowed_labels[rng.uniform_int(opt_.allowed_labels.size())];
        return complete(s, draw_plane(s, rng), rng);
    }
    /// The plane of a random candidate (first half of draw()).
    [[nodiscard]] int draw_plane(const candidate_source& s, counter_rng& rng) const {
        constexpr double unit26 = 1.0 / (1 << 25);  // 26-bit halves of one draw, mapped to [-1, 1)
        double x, y, r2;
        do {
            const std::uint64_t a = rng.next_u64();
            x = static_cast<double>(a & 0x3ffffffu) * unit26 - 1;
            y = static_cast<double>((a >> 26) & 0x3ffffffu) * unit26 - 1;
            r2 = x * x + y * y;
        } while (r2 > 1 || r2 == 0);
        const double c = 1.0 - r2 * one_minus_cos_, sin_over_r = std::sqrt(std::max(0.0, 1.0 - c * c) / r2);
        return labels_.nearest_plane(c * s.n + sin_over_r * (x * s.t1 + y * s.t2));
    }
    /// The translation and rotation of a random candidate on `plane` (second half of draw()).
    [[nodiscard]] std::uint32_t complete(candidate_source& s, int plane, counter_rng& rng) const {
        const std::uint64_t b = rng.next_u64();  // translations from its two 32-bit halves (multiply-shift)
        const auto T = static_cast<std::uint64_t>(opt_.translations);
        const int tx = static_cast<int>(((b & 0xffffffffu) * T) >> 32), ty = static_cast<int>(((b >> 32) * T) >> 32);
        int rot;
        if (s.oriented) {
            auto& cached = s.rotation[static_cast<std::size_t>(plane)];
            if (cached < 0) cached = static_cast<std::int16_t>(labels_.aligned_rotation(plane, s.field));
            rot = cached;
        } else {
            rot = static_cast<int>(rng.uniform_int(static_cast<std::uint64_t>(opt_.rotations)));
        }
        return label_space::make(plane, rot, tx, ty);
    }
    /// A random label for voxel v of `level` as OPTIMIZE and JITTER draw it, from the stream `rng`.
    [[nodiscard]] std::uint32_t random_label(int level, std::size_t v, counter_rng& rng) const {
        candidate_source s = source_of(level, v);
        return draw(s, rng);
    }

private:
    static constexpr std::uint64_t tag_jitter = 0x6a69747465ULL, tag_candidates = 0x63616e64ULL;

    [[nodiscard]] bool solid_at(vec2 p) const { return ex_.solid_at(p.x, p.y); }
    [[nodiscard]] const shell_level& lv(int level) const { return pyr_.levels.at(static_cast<std::size_t>(level)); }
    void check_labels(int level, const std::vector<std::uint32_t>& labels) const {
        if (labels.size() != lv(level).size()) throw invalid_input("synthesizer: label count does not match the level's voxels");
        for (std::uint32_t l : labels)
            if (!labels_.valid(l)) throw invalid_input("synthesizer: label " + std::to_string(l) + " is out of range");
    }

    /// One OPTIMIZE pass over the voxels of `level` with active[v] (all when active is empty),
    /// forced voxels (forced[v]) restricted to solid-mapping labels. Returns candidates evaluated.
    template <int C>
    std::uint64_t optimize_pass(int level, std::vector<std::uint32_t>& labels, level_energy<C>& en, std::span<const std::uint8_t> active,
                                std::span<const std::uint8_t> forced, std::uint64_t round, int pass, const std::function<void()>& tick) const {
        const shell_level& l = lv(level);
        const shell_neighbourhood& nb = nbs_[static_cast<std::size_t>(level)];
        std::atomic<std::uint64_t> evaluated{0};
        for (const std::vector<std::uint32_t>& all : classes_[static_cast<std::size_t>(level)]) {
            if (tick) tick();  // between sub-pass classes: a cancelling progress callback stops here
            std::vector<std::uint32_t> subset;
            const std::vector<std::uint32_t>* list = &all;
            if (!active.empty()) {
                for (std::uint32_t v : all)
                    if (active[v]) subset.push_back(v);
                list = &subset;
            }
            constexpr std::size_t chunk = 64;
            const std::size_t chunks = (list->size() + chunk - 1) / chunk;
            parallel_for(0, chunks, [&](std::size_t ci) {
                std::vector<float> exp;
                std::vector<std::uint32_t> cand;
                std::vector<std::pair<std::uint32_t, std::uint32_t>> runs;  // (count, label)
                std::uint64_t count = 0;
                for (std::size_t i = ci * chunk; i < std::min(list->size(), (ci + 1) * chunk); ++i) {
                    const std::uint32_t v = (*list)[i];
                    const bool is_forced = !forced.empty() && forced[v];
                    auto valid = [&](std::uint32_t label) { return !is_forced || solid_at(labels_.map(l.center(v), label)); };
                    exp.resize(en.expected_size(v));
                    typename level_energy<C>::moments mom;
                    en.expected(v, exp.data(), mom);
                    std::uint32_t best = labels[v];
                    double e_best = valid(best) ? en.local(v, best, exp.data(), mom) : std::numeric_limits<double>::infinity();
                    // coherent candidates: the distinct labels of the neighbours
                    cand.clear();
                    for (std::uint32_t k = nb.offset[v]; k < nb.offset[v + 1]; ++k) cand.push_back(labels[nb.index[k]]);
                    std::sort(cand.begin(), cand.end());
                    // distinct labels, the most frequent first: the likely winners tighten the bound early
                    runs.clear();
                    for (std::size_t a = 0; a < cand.size();) {
                        std::size_t b = a;
                        while (b < cand.size() && cand[b] == cand[a]) ++b;
                        runs.push_back({static_cast<std::uint32_t>(b - a), cand[a]});
                        a = b;
                    }
                    std::stable_sort(runs.begin(), runs.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
                    cand.clear();
                    for (const auto& r : runs) cand.push_back(r.second);
                    if (cand.size() > static_cast<std::size_t>(opt_.candidates)) cand.resize(static_cast<std::size_t>(opt_.candidates));
                    counter_rng rng(opt_.seed, tag_candidates, round, static_cast<std::uint64_t>(level), static_cast<std::uint64_t>(pass),
                                    static_cast<std::uint64_t>(v));
                    candidate_source src = source_of(level, v);
                    auto consider = [&](std::uint32_t c) {
                        if (c == best || !valid(c)) return;
                        const double e = en.local(v, c, exp.data(), mom, e_best);
                        if (e < e_best) e_best = e, best = c;
                    };
                    for (std::uint32_t c : cand) consider(c);
                    count += cand.size();
                    // random candidates up to the total; a plane whose distortion alone reaches the best energy
                    // cannot win, so its transform is not drawn (the energy is never below the distortion term)
                    const std::size_t random = static_cast<std::size_t>(opt_.candidates) - cand.size();
                    for (std::size_t i = 0; i < random; ++i) {
                        ++count;
                        if (!opt_.allowed_labels.empty()) {
                            consider(draw(src, rng));
                            continue;
                        }
                        const int plane = draw_plane(src, rng);
                        if (en.distortion(v, plane) >= e_best) continue;
                        consider(complete(src, plane, rng));
                    }
                    // a forced voxel whose candidates all map it to empty keeps looking (bounded)
                    for (int extra = 0; !std::isfinite(e_best) && extra < 4 * opt_.candidates; ++extra, ++count) consider(draw(src, rng));
                    if (best != labels[v]) {
                        labels[v] = best;
                        en.refresh(v);
                    }
                }
                evaluated += count;
            });
        }
        return evaluated.load();
    }

    template <int C>
    void optimize_level(int level, std::vector<std::uint32_t>& labels, level_report& rep, std::span<const std::uint8_t> active,
                        std::span<const std::uint8_t> forced, std::uint64_t round, const std::function<void()>& tick) const {
        level_energy<C> en(lv(level), nbs_[static_cast<std::size_t>(level)], labels_, ex_, level, opt_.energy, labels);
        rep.energy_initial = en.total();
        for (int pass = 0; pass < opt_.passes; ++pass) {
            rep.candidates += optimize_pass<C>(level, labels, en, active, forced, round, pass, tick);
            rep.energy_passes.push_back(en.total());
        }
    }

    [[nodiscard]] level_report start_report(int level) const {
        level_report rep;
        rep.level = level;
        rep.voxels = lv(level).size();
        rep.spacing_mm = lv(level).geometry.spacing.x;
        rep.sigma_px = ex_.sigma(level);
        return rep;
    }

    template <int C, class P>
    synthesis_result run_synthesis(P& progress) const {
        const auto t0 = std::chrono::steady_clock::now();
        const int L = pyr_.coarsest();
        synthesis_result r;
        r.labels.resize(pyr_.levels.size());
        r.levels.resize(pyr_.levels.size());
        double work_done = 0, work_total = 0;
        for (const shell_level& l : pyr_.levels) work_total += static_cast<double>(l.size());
        for (int level = L; level >= 0; --level) {
            const auto tl = std::chrono::steady_clock::now();
            report_progress(progress, work_done / work_total, "synthesis level " + std::to_string(level));
            const shell_level& l = lv(level);
            std::vector<std::uint32_t>& labels = r.labels[static_cast<std::size_t>(level)];
            labels.assign(l.size(), opt_.allowed_labels.empty() ? 0u : opt_.allowed_labels.front());
            if (level < L) {  // UPSAMPLE
                const std::vector<std::uint32_t>& coarse = r.labels[static_cast<std::size_t>(level + 1)];
                for (std::size_t v = 0; v < l.size(); ++v) labels[v] = coarse[l.parent[v]];
            }
            // JITTER
            parallel_for(0, l.size(), [&](std::size_t v) {
                counter_rng rng(opt_.seed, tag_jitter, std::uint64_t{0}, static_cast<std::uint64_t>(level), static_cast<std::uint64_t>(v));
                if (rng.uniform() < opt_.jitter) labels[v] = random_label(level, v, rng);
            }, {.grain = 1024});
            level_report& rep = r.levels[static_cast<std::size_t>(level)];
            rep = start_report(level);
            // OPTIMIZE; the progress callback is asked again between the 27 sub-pass classes of each
            // pass (a few per second on the finest level at 256^3), so a cancel takes effect quickly
            const std::string stage = "synthesis level " + std::to_string(level);
            optimize_level<C>(level, labels, rep, {}, {}, 0, [&] { report_progress(progress, work_done / work_total, stage); });
            rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tl).count();
            work_done += static_cast<double>(l.size());
        }
        r.solid = states(0, r.labels[0]);
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        report_progress(progress, 1.0, "synthesis");
        return r;
    }

    template <int C, class P>
    resynthesis_report run_resynthesis(synthesis_result& r, std::span<const std::uint8_t> forced0, std::span<const std::uint8_t> allowed0,
                                       double r_pattern_voxels, std::uint64_t round, P& progress) const {
        const std::size_t n0 = lv(0).size();
        if (forced0.size() != n0 || allowed0.size() != n0)
            throw invalid_input("resynthesis: forced and allowed need one flag per finest shell voxel (" + std::to_string(n0) + ")");
        if (r.labels.size() != pyr_.levels.size()) throw invalid_input("resynthesis: the result does not come from this pyramid");
        for (std::size_t l = 0; l < r.labels.size(); ++l) check_labels(static_cast<int>(l), r.labels[l]);
        if (!(std::isfinite(r_pattern_voxels) && r_pattern_voxels > 0))
            throw invalid_input("resynthesis: r_pattern must be finite and > 0 voxels, got " + std::to_string(r_pattern_voxels));
        if (round == 0) throw invalid_input("resynthesis: round 0 is the initial synthesis; use 1, 2, ...");
        resynthesis_report rep;
        rep.start_level = std::min(pyr_.coarsest(), static_cast<int>(std::ceil(std::log2(std::max(1.0, r_pattern_voxels)) - 1e-9)));
        const int Lr = rep.start_level;
        // forced and allowed flags on every level up to Lr: a parent is forced (allowed) if a child is
        std::vector<std::vector<std::uint8_t>> forced(static_cast<std::size_t>(Lr + 1)), allowed(static_cast<std::size_t>(Lr + 1));
        forced[0].assign(forced0.begin(), forced0.end());
        allowed[0].resize(n0);
        for (std::size_t v = 0; v < n0; ++v) {
            allowed[0][v] = (allowed0[v] || forced0[v]) ? 1 : 0;
            rep.forced += forced0[v] ? 1 : 0;
        }
        for (int l = 0; l < Lr; ++l) {
            const shell_level& f = lv(l);
            forced[static_cast<std::size_t>(l + 1)].assign(lv(l + 1).size(), 0);
            allowed[static_cast<std::size_t>(l + 1)].assign(lv(l + 1).size(), 0);
            for (std::size_t v = 0; v < f.size(); ++v) {
                forced[static_cast<std::size_t>(l + 1)][f.parent[v]] |= forced[static_cast<std::size_t>(l)][v];
                allowed[static_cast<std::size_t>(l + 1)][f.parent[v]] |= allowed[static_cast<std::size_t>(l)][v];
            }
        }
        // the region: forced parents on level Lr, then their allowed descendants
        std::vector<std::vector<std::uint8_t>> region(static_cast<std::size_t>(Lr + 1));
        region[static_cast<std::size_t>(Lr)] = forced[static_cast<std::size_t>(Lr)];
        for (int l = Lr - 1; l >= 0; --l) {
            const shell_level& f = lv(l);
            region[static_cast<std::size_t>(l)].assign(f.size(), 0);
            for (std::size_t v = 0; v < f.size(); ++v)
                region[static_cast<std::size_t>(l)][v] = region[static_cast<std::size_t>(l + 1)][f.parent[v]] && allowed[static_cast<std::size_t>(l)][v];
        }
        rep.updated.assign(static_cast<std::size_t>(Lr + 1), 0);
        rep.levels.resize(static_cast<std::size_t>(Lr + 1));
        for (int l = Lr; l >= 0; --l) {
            const auto tl = std::chrono::steady_clock::now();
            report_progress(progress, static_cast<double>(Lr - l) / (Lr + 1), "resynthesis level " + std::to_string(l));
            const std::vector<std::uint8_t>& reg = region[static_cast<std::size_t>(l)];
            std::vector<std::uint32_t>& labels = r.labels[static_cast<std::size_t>(l)];
            std::size_t count = 0;
            for (std::size_t v = 0; v < reg.size(); ++v) {
                if (!reg[v]) continue;
                ++count;
                if (l < Lr) labels[v] = r.labels[static_cast<std::size_t>(l + 1)][lv(l).parent[v]];  // UPSAMPLE inside the region
            }
            rep.updated[static_cast<std::size_t>(l)] = count;
            level_report& lr = rep.levels[static_cast<std::size_t>(l)];
            lr = start_report(l);
            lr.voxels = count;
            const std::string stage = "resynthesis level " + std::to_string(l);
            const double at = static_cast<double>(Lr - l) / (Lr + 1);
            if (count) optimize_level<C>(l, labels, lr, reg, forced[static_cast<std::size_t>(l)], round, [&] { report_progress(progress, at, stage); });
            lr.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tl).count();
        }
        r.solid = states(0, r.labels[0]);
        for (std::size_t v = 0; v < n0; ++v)
            if (forced0[v] && !r.solid[v]) ++rep.unsatisfied, r.solid[v] = 1;
        report_progress(progress, 1.0, "resynthesis");
        return rep;
    }

    const shell_pyramid& pyr_;
    exemplar ex_;
    synthesis_options opt_;
    label_space labels_;
    std::vector<shell_neighbourhood> nbs_;
    std::vector<std::vector<std::vector<std::uint32_t>>> classes_;  // per level, 27 sub-pass classes
    double one_minus_cos_ = 0;  // 1 - cos(cone half-angle)
};

}  // namespace fabsynth::surface_pattern
