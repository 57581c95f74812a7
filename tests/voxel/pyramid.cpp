#include <catch2/catch.hpp>

#include <fabsynth/core/rng.hpp>
#include <fabsynth/voxel/pyramid.hpp>

using namespace fabsynth;

TEST_CASE("pyramid levels: dims, spacing, reductions against brute force", "[voxel][pyramid]") {
    voxel_grid<int> g({13, 6, 5}, {1, 2, 3}, 0.5, 0);
    sparse_voxel_grid<int> s({13, 6, 5}, {1, 2, 3}, 0.5, 0);
    for (std::uint64_t i = 0; i < g.size(); ++i)
        if (hash_uniform(3, i) < 0.3) {
            const int v = 1 + static_cast<int>(hash64(4, i) % 9);
            g.set(g.coord(i), v);
            s.set(g.coord(i), v);
        }
    const auto any = build_pyramid(g, reduce_any{});
    REQUIRE(any.size() == 5);  // 13 -> 7 -> 4 -> 2 -> 1
    CHECK(any[1].dims() == ivec3(7, 3, 3));
    CHECK(any[4].dims() == ivec3(1, 1, 1));
    CHECK(any[2].spacing() == vec3(2.0));
    CHECK(any[3].origin() == vec3(1, 2, 3));
    // every fine voxel lies inside its parent's box
    CHECK(any[1].voxel_box({3, 1, 2}).contains(g.center({7, 3, 5 - 1})));

    const auto all = build_pyramid(g, reduce_all{}, 2);
    const auto mean = build_pyramid(g, reduce_mean{}, 2);
    const auto sparse_any = build_pyramid(s, reduce_any{}, 2);
    REQUIRE(all.size() == 2);
    for (std::uint64_t i = 0; i < any[1].size(); ++i) {
        const ivec3 P = any[1].coord(i);
        bool has = false, every = true;
        long sum = 0;
        int n = 0;
        // brute force: scan the whole fine grid for children
        for (std::uint64_t j = 0; j < g.size(); ++j) {
            const ivec3 c = g.coord(j);
            if (c / 2 != P) continue;
            const int v = g.get(c);
            has |= v != 0, every &= v != 0, sum += v, ++n;
        }
        REQUIRE(n >= 1);
        REQUIRE((any[1].get(P) != 0) == has);
        REQUIRE((all[1].get(P) != 0) == every);
        REQUIRE(mean[1].get(P) == static_cast<int>(sum / n));
        REQUIRE(sparse_any[1].get(P) == any[1].get(P));
    }
    CHECK(parent_voxel({5, 4, 1}) == ivec3(2, 2, 0));
    CHECK_THROWS_AS(build_pyramid(g, reduce_any{}, 0), invalid_input);
    // mean of doubles
    voxel_grid<double> d({2, 2, 2}, vec3(0), 1.0, 1.0);
    d.set({1, 1, 1}, 9.0);
    CHECK(build_pyramid(d, reduce_mean{})[1].get({0, 0, 0}) == Approx(2.0));
}
