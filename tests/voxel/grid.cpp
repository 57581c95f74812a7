#include <catch2/catch.hpp>

#include <fabsynth/core/rng.hpp>
#include <fabsynth/voxel/grid.hpp>
#include <fabsynth/voxel/neighbourhood.hpp>

#include <map>
#include <set>

using namespace fabsynth;

TEST_CASE("grid index <-> coordinate and world mapping", "[voxel][grid]") {
    voxel_grid<float> g({5, 7, 3}, {1.0, -2.0, 0.5}, vec3(0.5, 0.25, 2.0), -1.0f);
    CHECK(g.size() == 105u);
    std::uint64_t expect = 0;
    for (int z = 0; z < 3; ++z)
        for (int y = 0; y < 7; ++y)
            for (int x = 0; x < 5; ++x) {
                const ivec3 p(x, y, z);
                REQUIRE(g.index(p) == expect++);  // x-fastest
                REQUIRE(g.coord(g.index(p)) == p);
                REQUIRE(g.voxel_of(g.center(p)) == p);
                const box3 b = g.voxel_box(p);
                REQUIRE(b.contains(g.center(p)));
                REQUIRE(b.size().x == Approx(0.5));
            }
    CHECK(g.center({0, 0, 0}) == vec3(1.25, -1.875, 1.5));
    CHECK(g.get({4, 6, 2}) == -1.0f);
    g.set({4, 6, 2}, 3.0f);
    CHECK(g.at({4, 6, 2}) == 3.0f);
    g[{0, 1, 2}] = 7.0f;
    CHECK(g.get({0, 1, 2}) == 7.0f);
    CHECK_THROWS_AS(g.at({5, 0, 0}), invalid_input);
    CHECK_THROWS_AS(g.at({0, -1, 0}), invalid_input);
    CHECK(g.get_or_background({-1, 0, 0}) == -1.0f);
    CHECK(g.voxel_of({-100, 0, 0}).x < 0);
    CHECK(g.voxel_of({1e300, 0, 0}).x > 0);  // clamped, no overflow
}

TEST_CASE("dense and sparse storage agree on random writes", "[voxel][grid]") {
    voxel_grid<int> dense({9, 8, 7}, vec3(0), 1.0, 0);
    sparse_voxel_grid<int> sparse({9, 8, 7}, vec3(0), 1.0, 0);
    counter_rng r(7);
    std::map<std::uint64_t, int> ref;
    for (int i = 0; i < 300; ++i) {
        const ivec3 p(static_cast<int>(r.uniform_int(9)), static_cast<int>(r.uniform_int(8)), static_cast<int>(r.uniform_int(7)));
        const int v = static_cast<int>(r.uniform_int(5)) + 1;
        dense.set(p, v);
        sparse.set(p, v);
        ref[dense.index(p)] = v;
    }
    CHECK(sparse.storage().stored() == ref.size());
    for (std::uint64_t i = 0; i < dense.size(); ++i) {
        const ivec3 p = dense.coord(i);
        const int want = ref.count(i) ? ref[i] : 0;
        REQUIRE(dense.get(p) == want);
        REQUIRE(sparse.get(p) == want);
    }
    // sparse for_each visits exactly the stored voxels in increasing index order
    std::vector<std::uint64_t> seen;
    sparse.for_each([&](ivec3 p, int v) {
        seen.push_back(sparse.index(p));
        CHECK(v == ref[sparse.index(p)]);
    });
    std::vector<std::uint64_t> keys;
    for (auto& kv : ref) keys.push_back(kv.first);
    CHECK(seen == keys);
    CHECK(dense.count_if([](int v) { return v != 0; }) == ref.size());
    // bool values are stored as bytes
    voxel_grid<bool> b({2, 2, 2}, vec3(0), 1.0);
    b.set({1, 1, 1}, true);
    CHECK(b.get({1, 1, 1}));
    CHECK_FALSE(b.get({0, 1, 1}));
}

TEST_CASE("oversized or invalid grids are refused before allocating", "[voxel][grid][errors]") {
    // 10^12 voxels
    CHECK_THROWS_AS(voxel_grid<float>({10000, 10000, 10000}, vec3(0), 1.0), invalid_input);
    CHECK_THROWS_AS(sparse_voxel_grid<float>({10000, 10000, 10000}, vec3(0), 1.0), invalid_input);
    CHECK_THROWS_AS(voxel_grid<std::uint8_t>({1 << 21, 1 << 21, 1 << 21}, vec3(0), 1.0), invalid_input);
    CHECK_THROWS_AS(voxel_grid<float>({0, 4, 4}, vec3(0), 1.0), invalid_input);
    CHECK_THROWS_AS(voxel_grid<float>({-3, 4, 4}, vec3(0), 1.0), invalid_input);
    CHECK_THROWS_AS(voxel_grid<float>({(1 << 21) + 1, 1, 1}, vec3(0), 1.0), invalid_input);
    CHECK_THROWS_AS(voxel_grid<float>({4, 4, 4}, vec3(0), 0.0), invalid_input);
    CHECK_THROWS_AS(voxel_grid<float>({4, 4, 4}, vec3(0), std::nan("")), invalid_input);
    CHECK_THROWS_AS(voxel_grid<float>({4, 4, 4}, vec3(0, std::nan(""), 0), 1.0), invalid_input);
    CHECK_THROWS_WITH(voxel_grid<double>({100000, 100000, 1000}, vec3(0), 1.0), Catch::Contains("GiB"));
    // a large but legal sparse grid costs nothing
    sparse_voxel_grid<float> big({4096, 4096, 4096}, vec3(0), 1.0);
    big.set({4095, 4095, 4095}, 1.0f);
    CHECK(big.storage().stored() == 1u);
    CHECK(big.get({4095, 4095, 4095}) == 1.0f);
}

TEST_CASE("fit_grid covers the box with padding and cubic voxels", "[voxel][grid]") {
    const box3 b({-1, 0, 2}, {3, 1, 2.5});
    const grid_geometry g = fit_grid(b, 40, 2);
    CHECK(g.spacing == vec3(0.1));
    CHECK(g.dims == ivec3(44, 14, 9));
    const box3 gb = g.bounds();
    CHECK(gb.lo.x <= b.lo.x - 0.2 + 1e-9);
    CHECK(gb.hi.z >= b.hi.z + 0.2 - 1e-9);
    CHECK_THROWS_AS(fit_grid(box3{}, 10), invalid_input);
    CHECK_THROWS_AS(fit_grid(b, 0), invalid_input);
    CHECK_THROWS_AS(fit_grid(b, -5), invalid_input);
}

template <class C>
void check_neighbourhood(std::size_t n, int max_l1) {
    std::set<std::array<int, 3>> s(C::offsets.begin(), C::offsets.end());
    CHECK(s.size() == n);
    for (const auto& o : C::offsets) {
        const int l1 = std::abs(o[0]) + std::abs(o[1]) + std::abs(o[2]);
        CHECK(l1 >= 1);
        CHECK(l1 <= max_l1);
        CHECK(s.count({-o[0], -o[1], -o[2]}) == 1);  // symmetric
    }
}

TEST_CASE("6/18/26 neighbourhoods", "[voxel][neighbourhood]") {
    check_neighbourhood<connectivity::c6>(6, 1);
    check_neighbourhood<connectivity::c18>(18, 2);
    check_neighbourhood<connectivity::c26>(26, 3);
    static_assert(connectivity::c26::offsets.size() == 26);
}
