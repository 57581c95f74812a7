#include <catch2/catch.hpp>

#include <fabsynth/core.hpp>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

using namespace fabsynth;

TEST_CASE("parallel_for visits every index once, for any thread count", "[core][parallel]") {
    for (unsigned t : {1u, 2u, 3u, 8u}) {
        std::vector<int> hits(10007, 0);
        parallel_for(0, hits.size(), [&](std::size_t i) { hits[i] += 1; }, {.grain = 13, .threads = t});
        for (int h : hits) REQUIRE(h == 1);
    }
}

TEST_CASE("parallel_reduce is bit-identical across thread counts", "[core][parallel]") {
    auto term = [](std::size_t i) { return std::sin(static_cast<double>(i)) * 1e-3 + hash_uniform(3, i); };
    std::vector<double> sums;
    for (unsigned t : {1u, 2u, 4u, 7u}) sums.push_back(parallel_reduce(0, 123457, 0.0, term, std::plus<>{}, {.grain = 1000, .threads = t}));
    for (double s : sums) CHECK(std::memcmp(&s, &sums[0], sizeof s) == 0);
    // Order-dependent reduction: concatenation proves blocks are combined left to right.
    auto cat = parallel_reduce(0, 50, std::vector<int>{}, [](std::size_t i) { return std::vector<int>{int(i)}; },
                               [](std::vector<int> a, std::vector<int> b) { a.insert(a.end(), b.begin(), b.end()); return a; },
                               {.grain = 4, .threads = 3});
    for (int i = 0; i < 50; ++i) REQUIRE(cat[i] == i);
}

TEST_CASE("parallel_for rethrows the lowest failing chunk's exception", "[core][parallel]") {
    for (unsigned t : {1u, 2u}) {
        try {
            parallel_for(0, 1000, [](std::size_t i) { if (i % 100 == 50) throw invalid_input("bad " + std::to_string(i)); }, {.grain = 10, .threads = t});
            FAIL("no exception");
        } catch (const invalid_input& e) {
            // With one thread, the first failure stops the loop: index 50. With more, chunk 5 is
            // always started before later ones fail-fast, and it is the lowest chunk that can fail.
            CHECK(std::string(e.what()) == "fabsynth: bad 50");
        }
    }
}

TEST_CASE("nested parallel_for runs serially inside workers", "[core][parallel]") {
    std::vector<int> grid(64 * 64, 0);
    parallel_for(0, 64, [&](std::size_t i) { parallel_for(0, 64, [&](std::size_t j) { grid[i * 64 + j] = int(i + j); }); }, {.threads = 2});
    for (std::size_t i = 0; i < 64; ++i)
        for (std::size_t j = 0; j < 64; ++j) REQUIRE(grid[i * 64 + j] == int(i + j));
}
