// Evaluator vs an independent explicit Voronoi construction (reference_voronoi.hpp).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/foam/evaluator.hpp"
#include "foam/reference_voronoi.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;

namespace {

struct agreement {
    long tested = 0, banded = 0, solid = 0, disagree = 0, dist_mismatch = 0;
};

// Compares contains() and distance_to_edges() (through the point cache) with the reference on n
// random points of Q, one slice through Q with slice() and four with slices().
template <class D, class R>
agreement compare(const voronoi_foam<D, R>& f, const box3& Q, long n, std::uint64_t key) {
    const double tm = f.max_radius();
    const box3 E = Q.inflated(tm * 1.01);
    const double L = f.options().cell;
    const auto seeds = f.seeds().seeds_in_box(E.inflated(2 * std::sqrt(3.0) * L + 0.5));
    reftest::reference_edges ref(seeds, E);
    agreement a;
    counter_rng rng(key, 99);
    for (long i = 0; i < n; ++i) {
        const vec3 q = Q.lo + Q.size() * vec3(rng.uniform(), rng.uniform(), rng.uniform());
        const double tau = f.radius(q);
        const double d = ref.distance(q, tm);
        ++a.tested;
        if (std::abs(d - tau) < 1e-9) {
            ++a.banded;
            continue;
        }
        const bool want = d <= tau;
        a.solid += want;
        if (f.contains(q) != want) ++a.disagree;
        const double de = f.distance_to_edges(q, tm);
        if (std::isinf(d) != std::isinf(de) || (!std::isinf(d) && std::abs(d - de) > 1e-9)) ++a.dist_mismatch;
    }
    // slice path: the pixel centres of one slice through Q (slice()) and of four (slices(), the
    // edges of each tile column built once per slab)
    const double pix = 0.05;
    const box2 region({Q.lo.x, Q.lo.y}, {Q.hi.x, Q.hi.y});
    const auto check_image = [&](const image8& img, double z) {
        for (int j = 0; j < img.height; ++j)
            for (int i = 0; i < img.width; ++i) {
                const vec3 q(region.lo.x + (i + 0.5) * pix, region.lo.y + (j + 0.5) * pix, z);
                if (!Q.contains(q)) continue;
                const double d = ref.distance(q, tm), tau = f.radius(q);
                ++a.tested;
                if (std::abs(d - tau) < 1e-9) {
                    ++a.banded;
                    continue;
                }
                a.solid += d <= tau;
                if ((img.at(i, j) == 255) != (d <= tau)) ++a.disagree;
            }
    };
    const double z = Q.center().z + 0.0123;
    check_image(f.slice(z, region, pix, {.supersample = 1, .tile = 32}), z);
    const double z0 = Q.lo.z + 0.0077, dz = Q.size().z / 4.3;
    const std::vector<image8> stack = f.slices(z0, dz, 4, region, pix, {.tile = 32});
    for (int k = 0; k < 4; ++k) check_image(stack[static_cast<std::size_t>(k)], z0 + k * dz);
    return a;
}

long points(long fast, long slow, bool is_slow) { return is_slow ? slow : fast; }

void run_configs(bool slow) {
    const long n = points(4000, 100000, slow);
    SECTION("uniform density") {
        voronoi_foam f(constant_field{0.5}, constant_field{0.25}, {.cell = 2, .seed = 11});
        const auto a = compare(f, box3({0, 0, 0}, {6, 6, 6}), n, 1);
        INFO("tested " << a.tested << " solid " << a.solid << " banded " << a.banded);
        CHECK(a.solid > a.tested / 20);
        CHECK(a.disagree == 0);
        CHECK(a.dist_mismatch == 0);
    }
    SECTION("strong gradient, graded radius") {
        voronoi_foam f(linear_field{0, 0.02, 4.0, 0, 6}, linear_field{1, 0.08, 0.3, 0, 6},
                       {.cell = 2, .seed = 12});
        const auto a = compare(f, box3({0, 0, 0}, {6, 6, 4}), n, 2);
        INFO("tested " << a.tested << " solid " << a.solid << " banded " << a.banded);
        CHECK(a.solid > a.tested / 20);
        CHECK(a.disagree == 0);
        CHECK(a.dist_mismatch == 0);
    }
    SECTION("very low density") {
        voronoi_foam f(constant_field{0.002}, constant_field{0.5}, {.cell = 5, .seed = 13});  // clamped to 1/125
        const auto a = compare(f, box3({-5, -5, -5}, {10, 10, 10}), n, 3);
        INFO("tested " << a.tested << " solid " << a.solid << " banded " << a.banded);
        CHECK(a.solid > a.tested / 50);
        CHECK(a.disagree == 0);
        CHECK(a.dist_mismatch == 0);
    }
    SECTION("very high density") {
        voronoi_foam f(constant_field{60.0}, constant_field{0.1}, {.cell = 1, .seed = 14});
        const auto a = compare(f, box3({0, 0, 0}, {1.5, 1.5, 1.5}), n, 4);
        INFO("tested " << a.tested << " solid " << a.solid << " banded " << a.banded);
        CHECK(a.solid > a.tested / 5);
        CHECK(a.disagree == 0);
        CHECK(a.dist_mismatch == 0);
    }
}

}  // namespace

TEST_CASE("foam evaluator equals an explicit Voronoi construction", "[foam]") { run_configs(false); }

TEST_CASE("foam evaluator equals an explicit Voronoi construction on 1e5 points", "[foam][slow]") {
    run_configs(true);
}

TEST_CASE("foam supersampled coverage", "[foam]") {
    voronoi_foam f(constant_field{0.5}, constant_field{0.25}, {.cell = 2, .seed = 5});
    counter_rng rng(3, 4);
    for (int i = 0; i < 200; ++i) {
        const vec3 q(rng.uniform(0, 5), rng.uniform(0, 5), rng.uniform(0, 5));
        const double c = f.coverage(q, 0.1, 3);
        REQUIRE(c >= 0.0);
        REQUIRE(c <= 1.0);
        // independent: the same samples through contains()
        int cnt = 0;
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                for (int l = 0; l < 3; ++l) cnt += f.contains(q - vec3(0.05) + 0.1 * (vec3(l, j, k) + 0.5) / 3.0);
        REQUIRE(c == cnt / 27.0);  // the same bits: one gather for all samples (canonical pieces)
    }
    // grayscale slice: a pixel's value is the fraction of its s x s sub-samples that are solid
    const box2 region({1, 1}, {2, 2});
    const image8 g = f.slice(2.5, region, 0.1, {.supersample = 4});
    const image8 fine = f.slice(2.5, region, 0.025);
    for (int j = 0; j < g.height; ++j)
        for (int i = 0; i < g.width; ++i) {
            int cnt = 0;
            for (int v = 0; v < 4; ++v)
                for (int u = 0; u < 4; ++u) cnt += fine.at(4 * i + u, 4 * j + v) == 255;
            REQUIRE(g.at(i, j) == (255 * cnt + 8) / 16);
        }
}

TEST_CASE("foam slices are deterministic across threads, tiles and stacks", "[foam]") {
    voronoi_foam f(linear_field{0, 0.05, 1.0, 0, 20}, constant_field{0.2}, {.cell = 3, .seed = 21});
    const box2 region({0, 0}, {20, 8});
    set_num_threads(1);
    const image8 a = f.slice(3.3, region, 0.05, {.tile = 64});
    set_num_threads(2);
    const image8 b = f.slice(3.3, region, 0.05, {.tile = 64});
    const image8 c = f.slice(3.3, region, 0.05, {.tile = 40});
    std::vector<image8> stack;
    for (double z : {3.2, 3.25, 3.3, 3.35}) stack.push_back(f.slice(z, region, 0.05));
    set_num_threads(0);
    CHECK(a == b);
    CHECK(a == c);
    CHECK(stack[2] == a);
    CHECK(stack[1] != a);
}

TEST_CASE("foam bad input", "[foam]") {
    CHECK_THROWS_AS((voronoi_foam(constant_field{1}, constant_field{0}, {})), invalid_input);
    CHECK_THROWS_AS((voronoi_foam(constant_field{1}, constant_field{-1}, {})), invalid_input);
    CHECK_THROWS_AS((voronoi_foam(constant_field{1}, constant_field{std::nan("")}, {})), invalid_input);
    CHECK_THROWS_AS((voronoi_foam(constant_field{1}, constant_field{INFINITY}, {})), invalid_input);
    CHECK_THROWS_AS((voronoi_foam(constant_field{1}, constant_field{3}, {.cell = 2})), invalid_input);
    CHECK_THROWS_AS((voronoi_foam(constant_field{1}, constant_field{0.2}, {.cell = 0})), invalid_input);
    voronoi_foam neg(constant_field{-1}, constant_field{0.2}, {});
    CHECK_THROWS_AS(neg.contains({0, 0, 0}), invalid_input);
    voronoi_foam nan(constant_field{std::nan("")}, constant_field{0.2}, {});
    CHECK_THROWS_AS(nan.contains({0, 0, 0}), invalid_input);
    voronoi_foam inf(constant_field{INFINITY}, constant_field{0.2}, {});
    CHECK_THROWS_AS(inf.contains({0, 0, 0}), invalid_input);
    // density above the full-block bound is clamped to 1/(2 tau)^3: same seeds as at the bound
    voronoi_foam hi(constant_field{1e6}, constant_field{0.25}, {.cell = 2});
    voronoi_foam at(constant_field{8.0}, constant_field{0.25}, {.cell = 2});
    CHECK(hi.seeds().seeds_in_box({{0, 0, 0}, {4, 4, 4}}) == at.seeds().seeds_in_box({{0, 0, 0}, {4, 4, 4}}));
    voronoi_foam ok(constant_field{0.5}, constant_field{0.2}, {});
    CHECK_THROWS_AS(ok.contains({NAN, 0, 0}), invalid_input);
    CHECK_THROWS_AS(ok.contains({1e300, 0, 0}), invalid_input);
    CHECK_THROWS_AS(ok.slice(0, {{0, 0}, {1e6, 1e6}}, 0.01), invalid_input);  // region too large
    CHECK_THROWS_AS(ok.slice(0, {{0, 0}, {1, 1}}, 0), invalid_input);
    CHECK_THROWS_AS(ok.slice(NAN, {{0, 0}, {1, 1}}, 0.1), invalid_input);
    CHECK_THROWS_AS(ok.seeds().seeds_in_box({{0, 0, 0}, {1e5, 1e5, 1e5}}), invalid_input);
    // radius field with no known maximum needs foam_options::max_radius
    auto tau = [](const vec3&) { return 0.2; };
    CHECK_THROWS_AS((voronoi_foam(constant_field{0.5}, tau, {})), invalid_input);
    voronoi_foam lam(constant_field{0.5}, tau, {.max_radius = 0.2});
    CHECK_NOTHROW(lam.contains({1, 1, 1}));
}
