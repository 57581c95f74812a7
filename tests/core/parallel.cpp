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

TEST_CASE("parallel_for reports the lowest failing chunk even when every chunk fails", "[core][parallel]") {
    for (int round = 0; round < 200; ++round)
        for (unsigned t : {2u, 3u}) {
            try {
                parallel_for(0, 64, [](std::size_t i) { throw invalid_input("chunk " + std::to_string(i)); }, {.grain = 1, .threads = t});
                FAIL("no exception");
            } catch (const invalid_input& e) {
                REQUIRE(std::string(e.what()) == "fabsynth: chunk 0");
            }
        }
}

TEST_CASE("parallel_for on the persistent pool: many short loops, changing thread counts", "[core][parallel]") {
    std::vector<long> v(256);
    for (int round = 0; round < 2000; ++round) {
        const unsigned t = 1 + static_cast<unsigned>(round % 4);
        parallel_for(0, v.size(), [&](std::size_t i) { v[i] += static_cast<long>(i); }, {.threads = t});
    }
    for (std::size_t i = 0; i < v.size(); ++i) REQUIRE(v[i] == 2000 * static_cast<long>(i));
}

TEST_CASE("parallel_for called from several host threads at once", "[core][parallel]") {
    constexpr int hosts = 4, rounds = 300;
    std::vector<std::vector<double>> out(hosts, std::vector<double>(1000, 0.0));
    std::vector<double> sums(hosts * rounds, 0.0);
    {
        std::vector<std::jthread> host;
        for (int h = 0; h < hosts; ++h)
            host.emplace_back([&, h] {
                for (int r = 0; r < rounds; ++r) {
                    parallel_for(0, out[h].size(), [&](std::size_t i) { out[h][i] += 1.0; }, {.grain = 7, .threads = 2});
                    sums[h * rounds + r] = parallel_reduce(0, 5000, 0.0, [&](std::size_t i) { return std::sin(double(i + h)); },
                                                           std::plus<>{}, {.grain = 64, .threads = 2});
                }
            });
    }
    for (int h = 0; h < hosts; ++h) {
        for (double x : out[h]) REQUIRE(x == rounds);
        const double serial = parallel_reduce(0, 5000, 0.0, [&](std::size_t i) { return std::sin(double(i + h)); }, std::plus<>{},
                                              {.grain = 64, .threads = 1});
        for (int r = 0; r < rounds; ++r) REQUIRE(std::memcmp(&sums[h * rounds + r], &serial, sizeof serial) == 0);
    }
}

TEST_CASE("a loop body may call parallel_for from the caller's share and from workers", "[core][parallel]") {
    std::vector<int> grid(32 * 32, 0);
    std::atomic<int> nested_threads_above_one{0};
    parallel_for(0, 32, [&](std::size_t i) {
        parallel_for(0, 32, [&](std::size_t j) { grid[i * 32 + j] += 1; }, {.threads = 8});
        if (!fabsynth::detail::inside_worker()) ++nested_threads_above_one;
    }, {.threads = 2});
    CHECK(nested_threads_above_one == 0);
    for (int g : grid) REQUIRE(g == 1);
}
