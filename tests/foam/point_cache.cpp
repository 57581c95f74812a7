// Point queries through the per-thread block cache (foam/detail/point_cache.hpp): the same bits as
// the uncached evaluation (each point from the pieces of its own small cube, distances from the
// seeds, detail/canonical_piece.hpp) in row order, in random order and in an adversarial order (far-apart
// points alternating under a one-block budget, points exactly on a block's border); the batch
// API equals per-point calls for 1 and 2 threads; the cache stays within its documented bound
// over a 10^7-point random walk. The two large cases are [slow] (the sanitizer pass runs the small ones). (The brute-force Voronoi oracle of evaluator.cpp checks the
// answers themselves, through the same contains().)
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/foam/evaluator.hpp"

namespace foam_point_cache_test {

using namespace fabsynth;
using namespace fabsynth::foam;

// The configuration: density graded 0.02 -> 0.4 seeds/mm^3 over 20 mm, tau 0.25 mm, cell 4 mm.
voronoi_foam<linear_field, constant_field> graded(std::size_t budget) {
    return voronoi_foam(linear_field{0, 0.02, 0.4, 0, 20}, constant_field{0.25}, {.cell = 4, .seed = 17, .point_cache_bytes = budget});
}

// Reference answers: the uncached evaluation, each point from the pieces of its own cube q +- r.
struct reference {
    std::vector<std::uint8_t> solid;
    std::vector<double> distance;
};
template <class Foam>
reference uncached(const Foam& f, const std::vector<vec3>& pts) {
    reference r{std::vector<std::uint8_t>(pts.size()), std::vector<double>(pts.size())};
    parallel_for(0, pts.size(), [&](std::size_t i) {
        r.solid[i] = f.contains_uncached(pts[i]);
        r.distance[i] = f.distance_to_edges_uncached(pts[i], f.max_radius());
    });
    return r;
}

template <class Foam>
void check_same_bits(const Foam& f, const std::vector<vec3>& pts) {
    const reference want = uncached(f, pts);
    long solid_differ = 0, distance_differ = 0, solid = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        solid += want.solid[i];
        solid_differ += f.contains(pts[i]) != static_cast<bool>(want.solid[i]);
        const double d = f.distance_to_edges(pts[i], f.max_radius());
        distance_differ += std::memcmp(&d, &want.distance[i], sizeof d) != 0;
    }
    INFO(pts.size() << " points, " << solid << " solid");
    CHECK(solid_differ == 0);
    CHECK(distance_differ == 0);
    CHECK(solid > 0);
    CHECK(solid < static_cast<long>(pts.size()));
}

TEST_CASE("foam point cache: cached answers are the uncached bits, in row, random and adversarial order", "[foam][point_cache][slow]") {
    const auto f = graded(std::size_t(64) << 20);
    std::vector<vec3> rows;  // a 1000 x 1000 grid at 0.02 mm, row by row
    for (int j = 0; j < 1000; ++j)
        for (int i = 0; i < 1000; ++i) rows.push_back(vec3(0.01 + 0.02 * i, 0.01 + 0.02 * j, 7.3));
    check_same_bits(f, rows);

    std::vector<vec3> random;
    counter_rng rng(5, 1);
    for (int i = 0; i < 1000000; ++i) random.push_back(vec3(rng.uniform(-8, 24), rng.uniform(-8, 24), rng.uniform(-8, 24)));
    check_same_bits(f, random);

    // far-apart points alternating, under a budget of one block, and points exactly on block borders
    const auto tight = graded(0);
    std::vector<vec3> adversarial;
    for (int i = 0; i < 1000; ++i) {  // each a block build under the one-block budget
        adversarial.push_back(vec3(rng.uniform(0, 20), rng.uniform(0, 20), rng.uniform(0, 20)));
        adversarial.push_back(vec3(rng.uniform(-40, -20), rng.uniform(0, 20), rng.uniform(30, 50)));
    }
    for (int i = 0; i < 500; ++i) {  // on the faces x = 4 k and y = 4 k (the cell is 4 mm) and at corners
        const double b = 4.0 * std::floor(rng.uniform(-3, 5));
        adversarial.push_back(vec3(b, rng.uniform(0, 20), rng.uniform(0, 20)));
        adversarial.push_back(vec3(rng.uniform(0, 20), b, rng.uniform(0, 20)));
        adversarial.push_back(vec3(b, b, b));
    }
    check_same_bits(tight, adversarial);
    check_same_bits(f, adversarial);
}

TEST_CASE("foam point cache: contains_uncached and distance_to_edges_uncached give the cached bits", "[foam][point_cache]") {
    const auto f = graded(std::size_t(64) << 20);
    counter_rng rng(9, 2);
    int differ = 0;
    for (int i = 0; i < 300; ++i) {
        const vec3 q(rng.uniform(0, 20), rng.uniform(0, 20), rng.uniform(0, 20));
        differ += f.contains(q) != f.contains_uncached(q);
        const double a = f.distance_to_edges(q, 0.25), b = f.distance_to_edges_uncached(q, 0.25);
        differ += std::memcmp(&a, &b, sizeof a) != 0;
    }
    CHECK(differ == 0);
    CHECK_THROWS_AS(f.distance_to_edges_uncached({0, 0, 0}, 5.0), invalid_input);  // beyond the cell
}

TEST_CASE("foam point cache: the batch API equals per-point calls for 1 and 2 threads", "[foam][point_cache]") {
    const auto f = graded(std::size_t(64) << 20);
    std::vector<vec3> pts;
    counter_rng rng(11, 3);
    for (int i = 0; i < 20000; ++i) pts.push_back(vec3(rng.uniform(0, 16), rng.uniform(0, 16), rng.uniform(0, 16)));
    std::vector<std::uint8_t> one(pts.size()), two(pts.size());
    set_num_threads(1);
    f.contains(pts, one);
    set_num_threads(2);
    f.contains(pts, two);
    set_num_threads(0);
    CHECK(one == two);
    long differ = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) differ += one[i] != static_cast<std::uint8_t>(f.contains(pts[i]));
    CHECK(differ == 0);
    std::vector<std::uint8_t> short_out(3);
    CHECK_THROWS_AS(f.contains(pts, short_out), invalid_input);
    const std::vector<vec3> bad{{0, 0, 0}, {NAN, 0, 0}};
    std::vector<std::uint8_t> out(2);
    CHECK_THROWS_AS(f.contains(bad, out), invalid_input);
}

TEST_CASE("foam point cache: memory stays within the budget plus one block over a 10^7-point random walk", "[foam][point_cache][slow]") {
    const std::size_t budget = std::size_t(1) << 20;
    const auto f = graded(budget);
    counter_rng rng(13, 4);
    vec3 q(10, 10, 10);
    std::size_t most = 0, largest_block = 0;
    long solid = 0;
    for (long i = 0; i < 10000000; ++i) {
        q += vec3(rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1));
        solid += f.contains(q);
        if ((i & 1023) == 0) {
            const point_cache_stats st = f.point_cache();
            CHECK(st.bytes <= budget + st.largest_block_bytes);
            most = std::max(most, st.bytes);
            largest_block = std::max(largest_block, st.largest_block_bytes);
        }
    }
    INFO("walked to (" << q.x << ", " << q.y << ", " << q.z << "), " << solid << " solid, most " << most << " bytes, largest block " << largest_block);
    CHECK(most > budget / 2);  // the walk did fill the cache
    CHECK(solid > 0);
}

}  // namespace foam_point_cache_test
