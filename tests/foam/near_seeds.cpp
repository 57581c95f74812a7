// The near-seed test of contains() (foam/detail/near_seeds.hpp): answers equal to the exact
// uncached query on random points and on points right at beam surfaces, of a uniform and of a
// steeply graded foam (graded radius too); the bound of its Lemma 1 (second-smallest distance to
// the bisector planes of the nearest seed) never exceeds the true distance to the edges; its own
// decisions, taken directly, are never wrong.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/foam/evaluator.hpp"

namespace foam_near_seeds_test {

using namespace fabsynth;
using namespace fabsynth::foam;

using graded_foam = voronoi_foam<linear_field, linear_field>;

graded_foam uniform_foam() {
    return graded_foam(linear_field{0, 0.3, 0.3, 0, 1}, linear_field{0, 0.25, 0.25, 0, 1}, {.cell = 4, .seed = 11});
}
// density 0.02 -> 0.6 seeds/mm^3 and radius 0.35 -> 0.15 mm over 8 mm in x
graded_foam steep_foam() {
    return graded_foam(linear_field{0, 0.02, 0.6, 0, 8}, linear_field{0, 0.35, 0.15, 0, 8}, {.cell = 4, .seed = 12});
}

// Random points of [-4, 12]^3 and points at beam surfaces: on edge pieces of the box, moved off
// the edge by the local radius times 1 +- 1e-6, 1 +- 1e-9 and 1 (the exact surface, up to rounding).
std::vector<vec3> test_points(const graded_foam& f, std::uint64_t key, int random_count) {
    std::vector<vec3> pts;
    counter_rng rng(key, 3);
    for (int i = 0; i < random_count; ++i) pts.push_back(vec3(rng.uniform(-4, 12), rng.uniform(-4, 12), rng.uniform(-4, 12)));
    std::vector<edge_segment> edges;
    f.edges_in_box({{0, 0, 0}, {8, 8, 8}}, edges);
    for (std::size_t e = 0; e < edges.size(); e += 3) {
        const vec3 a = edges[e].a, b = edges[e].b, d = b - a;
        if (!(glm::dot(d, d) > 1e-12)) continue;
        const vec3 u = glm::normalize(d);
        vec3 w = glm::cross(u, vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
        if (!(glm::dot(w, w) > 1e-12)) continue;
        w = glm::normalize(w);
        const vec3 p = a + rng.uniform(0.1, 0.9) * d;
        const double t = f.radius(p);
        for (double s : {1 - 1e-6, 1 - 1e-9, 1.0, 1 + 1e-9, 1 + 1e-6}) pts.push_back(p + s * t * w);
    }
    return pts;
}

void check_against_uncached(const graded_foam& f, const std::vector<vec3>& pts) {
    long differ = 0, solid = 0;
    for (const vec3& q : pts) {
        const bool want = f.contains_uncached(q);
        solid += want;
        differ += f.contains(q) != want;
    }
    INFO(pts.size() << " points, " << solid << " solid");
    CHECK(differ == 0);
    CHECK(solid > 0);
    CHECK(solid < static_cast<long>(pts.size()));
}

TEST_CASE("foam near seeds: contains() equals contains_uncached() on random and beam-surface points", "[foam][near_seeds]") {
    for (const graded_foam& f : {uniform_foam(), steep_foam()}) {
        const auto pts = test_points(f, f.options().seed, 10000);
        check_against_uncached(f, pts);
        check_against_uncached(f, pts);  // the second pass from warm seed caches
    }
}

TEST_CASE("foam near seeds: the certified bound never exceeds the distance to the edges, decisions are exact", "[foam][near_seeds]") {
    for (const graded_foam& f : {uniform_foam(), steep_foam()}) {
        const auto seeds = f.seeds().seeds_in_box({{-10, -10, -10}, {18, 18, 18}});
        counter_rng rng(f.options().seed, 5);
        foam::detail::near_seeds ns;
        long bound_over = 0, wrong = 0, decided = 0, near_edge = 0;
        const double L = f.options().cell;
        for (int i = 0; i < 2000; ++i) {
            const vec3 q(rng.uniform(-2, 10), rng.uniform(-2, 10), rng.uniform(-2, 10));
            // Lemma 1: second smallest distance from q to the bisector planes of its nearest seed
            std::size_t i1 = 0;
            for (std::size_t j = 1; j < seeds.size(); ++j)
                if (glm::length(seeds[j] - q) < glm::length(seeds[i1] - q)) i1 = j;
            double b1 = 1e300, b2 = 1e300;
            for (std::size_t j = 0; j < seeds.size(); ++j) {
                if (j == i1) continue;
                const vec3 n = seeds[j] - seeds[i1];
                const double delta = glm::dot(n, 0.5 * (seeds[j] + seeds[i1]) - q) / glm::length(n);
                if (delta < b1) b2 = b1, b1 = delta;
                else if (delta < b2) b2 = delta;
            }
            const double truth = f.distance_to_edges_uncached(q, L);  // +infinity beyond L
            near_edge += truth <= L;
            if (b2 > truth + 1e-9) ++bound_over;
            // the test's own decisions, without the exact fallback
            const double t = f.radius(q);
            const auto a = foam::detail::near_seed_test(q, foam::coarse_cell_of(q, f.options().cell), t, f.seeds(), 4242, f.max_radius(), std::size_t(1) << 26, std::size_t(1) << 24, ns);
            if (a == foam::detail::near_answer::undecided) continue;
            ++decided;
            if ((a == foam::detail::near_answer::solid) != f.contains_uncached(q)) ++wrong;
        }
        INFO(near_edge << " points within a cell of an edge, " << decided << " decided");
        CHECK(bound_over == 0);
        CHECK(wrong == 0);
        CHECK(near_edge > 500);
        CHECK(decided > 1950);
    }
}

TEST_CASE("foam near seeds: a tiny seed budget keeps the answers", "[foam][near_seeds]") {
    const auto f = graded_foam(linear_field{0, 0.02, 0.6, 0, 8}, linear_field{0, 0.35, 0.15, 0, 8},
                               {.cell = 4, .seed = 12, .point_cache_bytes = 0});
    check_against_uncached(f, test_points(f, 9, 3000));
}

TEST_CASE("foam near seeds: misses on cells never held do not count as thrashing", "[foam][near_seeds]") {
    // A cache full of one foam's extended cells (owner 1: one query in each of 512 extended cells,
    // each cell visited once, so every query misses, none on an evicted cell), then another foam
    // (owner 2) queried once per new extended cell: its cells are built at their first miss, as a
    // cold pass needs (a cache that counted every miss as thrashing answered 31 of 32 of them from
    // raw cells and built none; the cold pass ran at 0.87 instead of 1.23 M points/s).
    const auto f = uniform_foam();
    const double L = f.options().cell;
    const std::size_t ext_budget = std::size_t(1) << 20, raw_budget = std::size_t(8) << 20;  // ~60 extended cells
    foam::detail::near_seeds ns;
    const auto centre_of = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
        return vec3(static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5, static_cast<double>(z) + 0.5) * (2 * L);
    };
    const auto query = [&](std::uint64_t owner, const vec3& q) {
        const i64vec3 k = coarse_cell_of(q, L);
        (void)foam::detail::near_seed_test(q, k, f.radius(q), f.seeds(), owner, f.max_radius(), ext_budget, raw_budget, ns);
        return ns.ext.find(owner, foam::detail::extended_key(k)) != nullptr;
    };
    for (std::int64_t z = 0; z < 8; ++z)
        for (std::int64_t y = 0; y < 8; ++y)
            for (std::int64_t x = 0; x < 8; ++x) (void)query(1, centre_of(x, y, z));
    REQUIRE(ns.ext.bytes() > ext_budget / 2);  // full: a new cell evicts one
    int built = 0;
    for (std::int64_t x = 0; x < 64; ++x) built += query(2, centre_of(x, 20, 20));
    CHECK(built == 64);
    // a working set 4x the cache, queried again and again, does thrash: most misses then are
    // answered from raw cells without a build (the answers stay exact: the tests above), so after
    // a query its cell is held only when it already was (about the quarter the cache holds), not
    // always as when every miss builds
    int held = 0;
    for (int round = 0; round < 4; ++round)
        for (std::int64_t z = 0; z < 8; ++z)
            for (std::int64_t y = 0; y < 8; ++y)
                for (std::int64_t x = 0; x < 4; ++x) {
                    const bool h = query(3, centre_of(x, y, z));
                    if (round == 3) held += h;
                }
    CHECK(held < 128);  // of 256
}

}  // namespace foam_near_seeds_test
