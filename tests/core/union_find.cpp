// Tests for core/union_find.hpp against a brute-force partition (explicit set labels relabelled on
// every merge) and a brute-force winding check (potentials propagated by graph search).
#include <catch2/catch.hpp>

#include <fabsynth/core/rng.hpp>
#include <fabsynth/core/union_find.hpp>

#include <algorithm>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

using namespace fabsynth;

TEST_CASE("union_find equals a brute-force partition on random unions", "[core][union_find]") {
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        const std::uint32_t n = 1 + static_cast<std::uint32_t>(hash64(seed, 0) % 60);
        union_find uf(n);
        std::vector<std::uint32_t> set_of(n);  // brute force: explicit set label per element
        for (std::uint32_t i = 0; i < n; ++i) set_of[i] = i;
        std::size_t sets = n;
        counter_rng rng(seed, 1);
        for (int step = 0; step < 80; ++step) {
            const auto a = static_cast<std::uint32_t>(rng.uniform_int(n)), b = static_cast<std::uint32_t>(rng.uniform_int(n));
            const bool differ = set_of[a] != set_of[b];
            REQUIRE(uf.unite(a, b) == differ);
            if (differ) {
                const std::uint32_t from = set_of[b], to = set_of[a];
                for (auto& s : set_of)
                    if (s == from) s = to;
                --sets;
            }
            REQUIRE(uf.sets() == sets);
            for (std::uint32_t x = 0; x < n; ++x) {
                // the root is the smallest member of the set
                std::uint32_t smallest = x;
                for (std::uint32_t y = 0; y < n; ++y)
                    if (set_of[y] == set_of[x]) smallest = std::min(smallest, y);
                REQUIRE(uf.find(x) == smallest);
            }
        }
    }
}

TEST_CASE("union_find: long chains are compressed iteratively", "[core][union_find]") {
    const std::uint32_t n = 1u << 20;
    union_find uf(n);
    for (std::uint32_t i = n - 1; i > 0; --i) uf.unite(i, i - 1);
    CHECK(uf.sets() == 1);
    CHECK(uf.find(n - 1) == 0);
    CHECK(uf.same(12345, 999999));
}

TEST_CASE("potential_union_find: winding equals a brute-force search of cycle shifts", "[core][union_find]") {
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        const std::uint32_t n = 2 + static_cast<std::uint32_t>(hash64(seed, 7) % 12);
        potential_union_find uf(n);
        struct link_rec {
            std::uint32_t x, y;
            std::int64_t s;
        };
        std::vector<link_rec> links;
        counter_rng rng(seed, 2);
        for (int step = 0; step < 14; ++step) {
            const auto x = static_cast<std::uint32_t>(rng.uniform_int(n)), y = static_cast<std::uint32_t>(rng.uniform_int(n));
            const std::int64_t s = static_cast<std::int64_t>(rng.uniform_int(3)) - 1;
            links.push_back({x, y, s});
            uf.link(x, y, s);
            // Brute force: propagate positions from each start by graph search; a set winds iff some
            // link disagrees with the propagated positions.
            std::vector<std::optional<std::int64_t>> pos(n);
            std::vector<int> comp(n, -1);
            std::vector<bool> comp_winds;
            for (std::uint32_t start = 0; start < n; ++start) {
                if (pos[start]) continue;
                const int c = static_cast<int>(comp_winds.size());
                comp_winds.push_back(false);
                pos[start] = 0;
                comp[start] = c;
                for (bool changed = true; changed;) {
                    changed = false;
                    for (const auto& l : links) {
                        if (pos[l.x] && !pos[l.y]) pos[l.y] = *pos[l.x] + l.s, comp[l.y] = c, changed = true;
                        if (pos[l.y] && !pos[l.x]) pos[l.x] = *pos[l.y] - l.s, comp[l.x] = c, changed = true;
                    }
                }
                for (const auto& l : links)
                    if (comp[l.x] == c && *pos[l.y] != *pos[l.x] + l.s) comp_winds[static_cast<std::size_t>(c)] = true;
            }
            for (std::uint32_t x = 0; x < n; ++x) {
                REQUIRE(uf.winds(x) == comp_winds[static_cast<std::size_t>(comp[x])]);
                // potentials relative to the root agree with the propagated positions on non-winding sets
                const std::uint32_t r = uf.find(x);
                REQUIRE(comp[r] == comp[x]);
                if (!comp_winds[static_cast<std::size_t>(comp[x])]) REQUIRE(uf.potential(x) == *pos[x] - *pos[r]);
            }
        }
    }
}

TEST_CASE("potential_union_find: a ring glued once around winds, a band does not", "[core][union_find]") {
    potential_union_find ring(3);
    CHECK_FALSE(ring.link(0, 1, 0));
    CHECK_FALSE(ring.link(1, 2, 0));
    CHECK(ring.link(2, 0, 1));  // closes a cycle with shift 1
    CHECK(ring.winds(1));
    CHECK(ring.sets() == 1);

    potential_union_find band(3);
    band.link(0, 1, 1);
    band.link(1, 2, -1);
    CHECK(band.link(0, 2, 0));  // closes a cycle with total shift 0
    CHECK_FALSE(band.winds(2));
    CHECK(band.potential(1) == 1);
    CHECK(band.unite(0, 0) == false);
}

TEST_CASE("union_find refuses 2^32 elements", "[core][union_find]") {
    CHECK_THROWS_AS(union_find(std::size_t{1} << 32), invalid_input);
}
