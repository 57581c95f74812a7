// Tests of sampling/poisson_disk.hpp. The oracles (pairwise distances, maximality, the sequential
// greedy) are brute force written here; they share no code with the header.
#include <catch2/catch.hpp>

#include "support/test_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/sampling/poisson_disk.hpp"

namespace {

using fabsynth::vec2;
using fabsynth::vec3;

template <class P>
std::vector<P> random_points(std::size_t n, unsigned seed, double side = 1.0) {
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> u(0.0, side);
    std::vector<P> pts(n);
    for (auto& p : pts)
        for (int d = 0; d < P::length(); ++d) p[d] = static_cast<typename P::value_type>(u(g));
    return pts;
}

template <class P>
double dist2(const P& a, const P& b) {
    double s = 0;
    for (int d = 0; d < P::length(); ++d) s += (double(a[d]) - double(b[d])) * (double(a[d]) - double(b[d]));
    return s;
}

// Sequential greedy, written from the documented definition: increasing hash64(seed, i), ties by
// index; accept iff no accepted point at distance < r. O(n * samples).
template <class P>
std::vector<std::size_t> reference_greedy(const std::vector<P>& pts, std::vector<std::size_t> cand, double r,
                                          std::uint64_t seed) {
    std::sort(cand.begin(), cand.end(), [&](std::size_t a, std::size_t b) {
        const auto ka = fabsynth::hash64(seed, a), kb = fabsynth::hash64(seed, b);
        return ka != kb ? ka < kb : a < b;
    });
    std::vector<std::size_t> acc;
    for (std::size_t i : cand) {
        bool ok = true;
        for (std::size_t j : acc)
            if (dist2(pts[i], pts[j]) < r * r) {
                ok = false;
                break;
            }
        if (ok) acc.push_back(i);
    }
    return acc;
}

template <class P>
void check_disk_and_maximal(const std::vector<P>& pts, const std::vector<std::size_t>& cand,
                            const std::vector<std::size_t>& s, double r) {
    for (std::size_t a = 0; a < s.size(); ++a)
        for (std::size_t b = a + 1; b < s.size(); ++b) REQUIRE(dist2(pts[s[a]], pts[s[b]]) >= r * r);
    for (std::size_t i : cand) {
        bool covered = false;
        for (std::size_t j : s) covered = covered || dist2(pts[i], pts[j]) < r * r || i == j;
        REQUIRE(covered);
    }
}

std::vector<std::size_t> all_indices(std::size_t n) {
    std::vector<std::size_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = i;
    return v;
}


}  // namespace

TEST_CASE("poisson_disk keeps the radius, is maximal and equals the sequential greedy (3D)", "[sampling][poisson]") {
    const auto pts = random_points<vec3>(3000, 1);
    for (double r : {0.03, 0.08, 0.2, 0.5}) {
        const auto s = fabsynth::sampling::poisson_disk(pts, r, {.seed = 11});
        INFO("r = " << r << ", samples = " << s.size());
        check_disk_and_maximal(pts, all_indices(pts.size()), s, r);
        CHECK(s == reference_greedy(pts, all_indices(pts.size()), r, 11));
    }
}

TEST_CASE("poisson_disk in 2D with float points, subset and mask", "[sampling][poisson]") {
    const auto pts = random_points<glm::vec2>(4000, 2, 10.0f);
    std::vector<std::size_t> subset;
    for (std::size_t i = 0; i < pts.size(); i += 3) subset.push_back(i);
    std::vector<std::uint8_t> mask(pts.size(), 0);
    for (std::size_t i = 0; i < pts.size(); ++i) mask[i] = (i % 2 == 0);
    std::vector<std::size_t> both;
    for (std::size_t i : subset)
        if (mask[i]) both.push_back(i);

    const double r = 0.4;
    const auto s_sub = fabsynth::sampling::poisson_disk(pts, r, {.seed = 5, .subset = subset});
    check_disk_and_maximal(pts, subset, s_sub, r);
    CHECK(s_sub == reference_greedy(pts, subset, r, 5));
    for (std::size_t i : s_sub) CHECK(i % 3 == 0);

    const auto s_both = fabsynth::sampling::poisson_disk(pts, r, {.seed = 5, .subset = subset, .mask = mask});
    check_disk_and_maximal(pts, both, s_both, r);
    CHECK(s_both == reference_greedy(pts, both, r, 5));

    // A point keeps its priority in any subset: another seed gives another set.
    const auto s_other = fabsynth::sampling::poisson_disk(pts, r, {.seed = 6, .subset = subset});
    CHECK(s_other != s_sub);
}

TEST_CASE("poisson_disk gives identical index sets for 1, 2 and 3 threads", "[sampling][poisson][parallel]") {
    fabsynth::test::thread_count_guard guard;
    const auto pts = random_points<vec3>(60000, 3);
    std::vector<std::vector<std::size_t>> runs;
    for (unsigned t : {1u, 2u, 3u}) {
        fabsynth::set_num_threads(t);
        runs.push_back(fabsynth::sampling::poisson_disk(pts, 0.05, {.seed = 9}));
    }
    CHECK(runs[0] == runs[1]);
    CHECK(runs[0] == runs[2]);
    // The brute-force greedy on the same input agrees too (the parallel path is exercised: the
    // batches exceed the parallel_for grain).
    CHECK(runs[0] == reference_greedy(pts, all_indices(pts.size()), 0.05, 9));
}

TEST_CASE("poisson_disk handles duplicates and a single point", "[sampling][poisson]") {
    std::vector<vec2> pts{{0, 0}, {0, 0}, {1, 0}, {1, 0}, {0.5, 0}};
    const auto s = fabsynth::sampling::poisson_disk(pts, 0.6, {});
    check_disk_and_maximal(pts, all_indices(pts.size()), s, 0.6);
    CHECK(s == reference_greedy(pts, all_indices(pts.size()), 0.6, 0));
    // Exactly r apart is allowed.
    std::vector<vec2> two{{0, 0}, {1, 0}};
    CHECK(fabsynth::sampling::poisson_disk(two, 1.0, {}).size() == 2);
    std::vector<vec2> one{{3, 4}};
    CHECK(fabsynth::sampling::poisson_disk(one, 1.0, {}) == std::vector<std::size_t>{0});
}

TEST_CASE("poisson_disk_count reaches 1000 of 10^5 random points in a cube within 2%", "[sampling][poisson][count]") {
    const auto pts = random_points<vec3>(100000, 4, 50.0);
    const auto res = fabsynth::sampling::poisson_disk_count(pts, 1000, {.seed = 1});
    INFO("count " << res.indices.size() << " radius " << res.radius << " evaluations " << res.evaluations);
    CHECK(res.within_tolerance);
    CHECK(std::abs(double(res.indices.size()) - 1000.0) <= 20.0);
    CHECK(res.indices == fabsynth::sampling::poisson_disk(pts, res.radius, {.seed = 1}));
    // Spot-check the radius on the result (all pairs of the samples).
    for (std::size_t a = 0; a < res.indices.size(); ++a)
        for (std::size_t b = a + 1; b < res.indices.size(); ++b)
            REQUIRE(dist2(pts[res.indices[a]], pts[res.indices[b]]) >= res.radius * res.radius);
}

TEST_CASE("poisson_disk_count on the voxel centres of a voxelized sphere shell", "[sampling][poisson][count]") {
    // Voxel centres (unit voxels) whose distance from the centre is in [R - 1.5, R]. On a lattice
    // the count only changes where r^2 crosses an integer (a jump of ~2/r^2 relative), so the
    // sphere is large enough (r ~ 10 voxels at 1000 samples) for those jumps to be below 2%.
    const double R = 100.0;
    const int n = 101;
    std::vector<vec3> pts;
    for (int z = -n; z <= n; ++z)
        for (int y = -n; y <= n; ++y)
            for (int x = -n; x <= n; ++x) {
                const vec3 c(x + 0.5, y + 0.5, z + 0.5);
                const double d = glm::length(c);
                if (d <= R && d >= R - 1.5) pts.push_back(c);
            }
    REQUIRE(pts.size() > 100000);
    const auto res = fabsynth::sampling::poisson_disk_count(pts, 1000, {.seed = 2});
    INFO("voxels " << pts.size() << " count " << res.indices.size() << " radius " << res.radius);
    CHECK(res.within_tolerance);
    CHECK(std::abs(double(res.indices.size()) - 1000.0) <= 20.0);
    check_disk_and_maximal(pts, all_indices(pts.size()), res.indices, res.radius);
}

TEST_CASE("poisson_disk_count: small targets, all points and unreachable targets", "[sampling][poisson][count]") {
    const auto pts = random_points<vec2>(500, 7);
    auto one = fabsynth::sampling::poisson_disk_count(pts, 1, {});
    CHECK(one.indices.size() == 1);
    auto all = fabsynth::sampling::poisson_disk_count(pts, 500, {.relative_tolerance = 0.0});
    CHECK(all.indices.size() == 500);
    // Only 3 distinct positions: a target of 5 cannot be reached; the closest count (3) comes back.
    std::vector<vec2> dup{{0, 0}, {0, 0}, {1, 0}, {1, 0}, {2, 0}, {2, 0}};
    auto closest = fabsynth::sampling::poisson_disk_count(dup, 5, {});
    CHECK(closest.indices.size() == 3);
    CHECK_FALSE(closest.within_tolerance);
}

TEST_CASE("poisson_disk rejects bad input with messages naming it", "[sampling][poisson][errors]") {
    using fabsynth::invalid_input;
    using Catch::Matchers::StartsWith;
    using Catch::Matchers::Contains;
    const std::vector<vec3> empty;
    std::vector<vec3> pts = random_points<vec3>(10, 1);
    CHECK_THROWS_AS(fabsynth::sampling::poisson_disk(empty, 1.0), invalid_input);
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk(empty, 1.0), StartsWith("fabsynth:") && Contains("empty"));
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk(pts, 0.0), StartsWith("fabsynth:") && Contains("radius"));
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk(pts, -1.0), Contains("radius"));
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk(pts, std::nan("")), Contains("radius"));
    auto bad = pts;
    bad[4].y = std::nan("");
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk(bad, 0.1), StartsWith("fabsynth:") && Contains("point 4"));
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk_count(pts, 0), Contains("target 0"));
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk_count(pts, 11), Contains("target 11"));
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk_count(empty, 1), Contains("empty"));
    const std::size_t out_of_range[] = {3, 10};
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk(pts, 0.1, {.subset = out_of_range}), Contains("subset index 10"));
    const std::uint8_t short_mask[] = {1, 1};
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk(pts, 0.1, {.mask = short_mask}), Contains("mask"));
    const std::vector<std::uint8_t> none(10, 0);
    CHECK_THROWS_WITH(fabsynth::sampling::poisson_disk(pts, 0.1, {.mask = none}), Contains("no candidate"));
}
