#include <catch2/catch.hpp>

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/surface_pattern/validation.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace fabsynth;
namespace sp = fabsynth::surface_pattern;

namespace {

/// A box of nx x ny x nz voxels of 1 mm at `at` in a grid of `dims`, plus `extra` voxels.
sp::voxel_set box_set(const ivec3& dims, const ivec3& at, const ivec3& size, const std::vector<ivec3>& extra = {}) {
    std::vector<ivec3> v = extra;
    for (int k = 0; k < size.z; ++k)
        for (int j = 0; j < size.y; ++j)
            for (int i = 0; i < size.x; ++i) v.push_back(at + ivec3(i, j, k));
    return sp::make_voxel_set({dims, vec3(0.0), vec3(1.0)}, std::move(v));
}

constexpr double rho = 1040, g = 9.81;
// rho g [N/m^3] times a length in mm (1e-3 m) is a stress in Pa.
constexpr double rho_g_pa_per_mm = rho * g * 1e-3;

}  // namespace

TEST_CASE("unexpected_direction is a unit vector orthogonal to gravity, (1, 0, 0) for (0, 0, -1)", "[surface_pattern][validation]") {
    CHECK(sp::unexpected_direction({0, 0, -1}) == vec3(1, 0, 0));
    CHECK(sp::unexpected_direction({0, 0, 5}) == vec3(1, 0, 0));
    CHECK(sp::unexpected_direction({1, 0, 0}) == vec3(0, 1, 0));
    for (const vec3 gv : {vec3(0.3, -0.2, -1.0), vec3(1, 1, 1), vec3(-2, 0.5, 0.1)}) {
        const vec3 u = sp::unexpected_direction(gv);
        CHECK(glm::length(u) == Approx(1.0));
        CHECK(std::abs(glm::dot(u, glm::normalize(gv))) < 1e-12);
    }
    const sp::validation_options o = sp::unexpected({});
    CHECK(o.gravity == vec3(0, 0, -1));  // the supports stay on the ground
    CHECK(o.load_direction == vec3(1, 0, 0));
}

TEST_CASE("validation: a vertical bar under its weight carries rho g (L - z) axially", "[surface_pattern][validation]") {
    // 6 x 6 x 60 voxels of 1 mm; the bottom 6 layers (10%) are fixed, the free part spans z = 6..60.
    const sp::voxel_set bar = box_set({8, 8, 62}, {1, 1, 1}, {6, 6, 60});
    sp::validation_options o;
    o.tolerance = 1e-8;
    const sp::stress_field f = sp::validate_stress_field(bar, o);
    const sp::stress_statistics& st = f.stats;
    CHECK(st.fixed_elements == 6u * 36u);
    CHECK(st.elements == 54u * 36u);
    CHECK(st.unsupported_pieces == 0);
    CHECK(st.unsupported_voxels == 0u);
    CHECK(st.iterations > 0);
    // Oracle at element centres z_c (mm above the grid origin; the top is at z = 61).
    std::vector<double> analytic;
    const double scale = rho_g_pa_per_mm * 54;  // the analytic stress at the clamp
    double worst_far = 0;  // largest error, relative to `scale`, two bar widths or more above the clamp
    for (std::size_t i = 0; i < bar.size(); ++i) {
        const double zc = bar.voxels[i].z + 0.5;
        if (zc < 7) {
            CHECK(f.score[i] == 0.0);
            continue;
        }
        const double s = rho_g_pa_per_mm * (61.0 - zc);
        analytic.push_back(s);
        if (zc > 7 + 12) worst_far = std::max(worst_far, std::abs(f.score[i] - s) / scale);
    }
    std::sort(analytic.begin(), analytic.end());
    double mean = 0;
    for (double s : analytic) mean += s;
    mean /= static_cast<double>(analytic.size());
    const double median = 0.5 * (analytic[analytic.size() / 2 - 1] + analytic[analytic.size() / 2]);
    INFO("average " << st.average << " (analytic " << mean << "), median " << st.median << " (" << median << "), p99 " << st.p99
                    << ", max " << st.max << ", worst error far from the clamp " << worst_far << ", iterations " << st.iterations);
    // The rigid clamp stops Poisson's contraction at z = 7: the layers within about one bar width
    // above it carry up to 1.8x the axial stress (the clamp corners are singular). That raises the
    // average by ~3.6% (measured) and puts the 99th percentile and the max into the clamp layer;
    // the median (uniform layers) is not affected.
    CHECK(st.average == Approx(mean).epsilon(0.05));
    CHECK(st.average > mean);
    CHECK(st.median == Approx(median).epsilon(0.01));
    CHECK(st.p99 >= analytic[static_cast<std::size_t>(std::lround(0.99 * (analytic.size() - 1)))]);
    CHECK(st.max >= scale);
    CHECK(st.max <= 2 * scale);
    CHECK(worst_far < 0.01);
}

TEST_CASE("validation: the bar loaded sideways is a cantilever under uniform load", "[surface_pattern][validation]") {
    // 8 x 8 x 80 voxels: free length L = 72 mm above the 8 fixed layers, section b = h = 8 mm.
    const sp::voxel_set bar = box_set({8, 8, 80}, {0, 0, 0}, {8, 8, 80});
    sp::validation_options o = sp::unexpected({});
    o.tolerance = 1e-8;
    const sp::stress_field f = sp::validate_stress_field(bar, o);
    const double b = 8, L = 72, A = b * b, I = b * b * b * b / 12, Z = b * b * b / 6;
    const double w = rho * g * 1e-9 * A;               // N/mm (rho g in N/mm^3 times the section)
    const double root = w * L * L / (2 * Z) * 1e6;    // Pa, outer fibre at the clamp
    INFO("max " << f.stats.max << " Pa, beam theory at the root " << root << " Pa, iterations " << f.stats.iterations);
    // The max sits at a corner of the first free layer, where the rigid clamp (no Poisson
    // contraction) makes the stress singular: 1.49x the root stress here, growing slowly with
    // refinement. Checked against beam theory only as a bracket.
    CHECK(f.stats.max >= root);
    CHECK(f.stats.max <= 2 * root);
    // From the second free layer on, the outer column follows M(z) c / I with c = 3.5 mm (element
    // centres half a voxel inside the outer fibre): the largest score there is beam theory's at
    // the second layer within 20% (+15.2% measured: the clamp still disturbs the second layer's
    // corners), and away from both ends (two widths) every outer element is within 5% (1.0%).
    double worst = 0, max_above = 0;
    for (std::size_t i = 0; i < bar.size(); ++i) {
        const ivec3 p = bar.voxels[i];
        const double zc = p.z + 0.5, arm = 80 - zc;  // distance to the free end
        if (zc > 9) max_above = std::max(max_above, f.score[i]);
        if ((p.x != 0 && p.x != 7) || zc < 8 + 16 || arm < 16) continue;
        const double s = w * arm * arm / 2 * 3.5 / I * 1e6;
        worst = std::max(worst, std::abs(f.score[i] - s) / s);
    }
    const double second = w * 70.5 * 70.5 / 2 * 3.5 / I * 1e6;
    INFO("largest score from the second free layer on " << max_above << " (beam " << second << "), worst relative error of the outer column "
                                                        << worst);
    CHECK(max_above == Approx(second).epsilon(0.20));
    CHECK(worst < 0.05);
    // The weight turned sideways is far more demanding than along gravity (Table 3's two rows)
    const sp::stress_statistics down = sp::validate_stress(bar, {});
    CHECK(f.stats.median > 3 * down.median);
}

TEST_CASE("validation: stresses are linear in the density and independent of the thread count", "[surface_pattern][validation]") {
    // An L: a column with an overhanging arm, loaded along gravity and sideways.
    std::vector<ivec3> arm;
    for (int i = 4; i < 20; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 20; k < 24; ++k) arm.push_back({i, j, k});
    const sp::voxel_set l = box_set({20, 4, 24}, {0, 0, 0}, {4, 4, 24}, arm);
    for (const bool sideways : {false, true}) {
        sp::validation_options o;
        if (sideways) o = sp::unexpected(o);
        const sp::stress_statistics a = sp::validate_stress(l, o);
        sp::validation_options o2 = o;
        o2.density_kg_m3 = 2 * o.density_kg_m3;
        const sp::stress_statistics b = sp::validate_stress(l, o2);
        CHECK(b.average == Approx(2 * a.average).epsilon(1e-12));
        CHECK(b.median == Approx(2 * a.median).epsilon(1e-12));
        CHECK(b.p99 == Approx(2 * a.p99).epsilon(1e-12));
        CHECK(b.max == Approx(2 * a.max).epsilon(1e-12));
        CHECK(b.elements == a.elements);

        set_num_threads(1);
        const sp::stress_field one = sp::validate_stress_field(l, o);
        set_num_threads(2);
        const sp::stress_field two = sp::validate_stress_field(l, o);
        set_num_threads(0);
        CHECK(one.score == two.score);
        CHECK(one.stats.average == two.stats.average);
        CHECK(one.stats.p99 == two.stats.p99);
        CHECK(one.stats.iterations == two.stats.iterations);
    }
}

TEST_CASE("validation: unsupported pieces are left out and reported, or refused on request", "[surface_pattern][validation]") {
    const ivec3 dims(10, 10, 40);
    const sp::voxel_set bar = box_set(dims, {1, 1, 0}, {4, 4, 30});
    std::vector<ivec3> extra;
    for (int k = 33; k < 36; ++k)  // a 3x3x3 block floating above the bar
        for (int j = 1; j < 4; ++j)
            for (int i = 1; i < 4; ++i) extra.push_back({i, j, k});
    extra.push_back({5, 5, 20});  // a voxel touching the bar only along an edge: a hinge, its own piece
    const sp::voxel_set both = box_set(dims, {1, 1, 0}, {4, 4, 30}, extra);
    // the extent along gravity now reaches z = 36: 10% is 3.6 mm, the bottom 3 layers
    sp::validation_options o;
    o.support_fraction = 0.1 * 30 / 36;  // same supports as the bar alone (3 layers)
    const sp::stress_field alone = sp::validate_stress_field(bar, {.support_fraction = 0.1});
    const sp::stress_field f = sp::validate_stress_field(both, o);
    CHECK(f.stats.unsupported_pieces == 2);
    CHECK(f.stats.unsupported_voxels == 28u);
    CHECK(f.stats.elements == alone.stats.elements);
    CHECK(f.stats.fixed_elements == alone.stats.fixed_elements);
    CHECK(f.stats.average == Approx(alone.stats.average).epsilon(1e-12));
    CHECK(f.stats.p99 == Approx(alone.stats.p99).epsilon(1e-12));
    std::size_t nan = 0;
    for (double s : f.score) nan += std::isnan(s) ? 1 : 0;
    CHECK(nan == 28u);

    o.require_supported = true;
    CHECK_THROWS_AS(sp::validate_stress(both, o), no_solution);
    CHECK_THROWS_WITH(sp::validate_stress(both, o), Catch::Contains("2 of 3 pieces (28 of"));
    // a set whose lowest piece is the only supported one still solves; one with no support cannot
    const sp::voxel_set floating = box_set(dims, {1, 1, 0}, {1, 1, 1}, {{5, 5, 30}, {5, 5, 31}, {5, 5, 32}, {5, 5, 33}, {5, 5, 34}});
    const sp::stress_statistics fl = sp::validate_stress(floating, {});
    CHECK(fl.unsupported_pieces == 1);
    CHECK(fl.elements == 0u);  // the one supported voxel is all support
    CHECK(fl.fixed_elements == 1u);
}

TEST_CASE("validation: bad input is refused", "[surface_pattern][validation]") {
    const sp::voxel_set bar = box_set({4, 4, 12}, {0, 0, 0}, {2, 2, 10});
    const sp::voxel_set empty{{ivec3(4, 4, 12), vec3(0.0), vec3(1.0)}, {}};
    CHECK_THROWS_AS(sp::validate_stress(empty, {}), invalid_input);
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    CHECK_THROWS_AS(sp::validate_stress(bar, {.gravity = {0, 0, 0}}), invalid_input);
    CHECK_THROWS_AS(sp::validate_stress(bar, {.gravity = {0, nan, -1}}), invalid_input);
    CHECK_THROWS_AS(sp::validate_stress(bar, {.gravity = {0, 0, -inf}}), invalid_input);
    CHECK_THROWS_AS(sp::validate_stress(bar, {.load_direction = {nan, 0, 0}}), invalid_input);
    CHECK_THROWS_AS(sp::validate_stress(bar, {.density_kg_m3 = 0}), invalid_input);
    CHECK_THROWS_AS(sp::validate_stress(bar, {.g = -9.81}), invalid_input);
    CHECK_THROWS_AS(sp::validate_stress(bar, {.support_fraction = 0}), invalid_input);
    CHECK_THROWS_AS(sp::validate_stress(bar, {.support_fraction = 1.5}), invalid_input);
    CHECK_THROWS_AS(sp::validate_stress(bar, {.tolerance = 0}), invalid_input);
    CHECK_THROWS_AS(sp::validate_stress(bar, {.max_iterations = 0}), invalid_input);
    CHECK_THROWS_AS(sp::unexpected_direction({0, 0, 0}), invalid_input);
    CHECK_THROWS_AS(sp::unexpected_direction({nan, 0, 1}), invalid_input);
    sp::voxel_set unsorted = bar;
    std::swap(unsorted.voxels[0], unsorted.voxels[1]);
    CHECK_THROWS_AS(sp::validate_stress(unsorted, {}), invalid_input);
    sp::validation_options soft;
    soft.material.nu = 0.5;
    CHECK_THROWS_AS(sp::validate_stress(bar, soft), invalid_input);
}

TEST_CASE("validation: a bar hung from the ceiling mirrors the bar on the floor", "[surface_pattern][validation]") {
    const sp::voxel_set bar = box_set({4, 4, 30}, {0, 0, 0}, {4, 4, 30});
    const sp::stress_statistics floor = sp::validate_stress(bar, {.tolerance = 1e-10});
    const sp::stress_statistics ceiling = sp::validate_stress(bar, {.gravity = {0, 0, 1}, .tolerance = 1e-10});
    CHECK(ceiling.fixed_elements == floor.fixed_elements);
    CHECK(ceiling.average == Approx(floor.average).epsilon(1e-6));
    CHECK(ceiling.median == Approx(floor.median).epsilon(1e-6));
    CHECK(ceiling.max == Approx(floor.max).epsilon(1e-6));
}
