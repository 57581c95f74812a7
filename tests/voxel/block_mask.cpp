#include <catch2/catch.hpp>

#include <fabsynth/core/rng.hpp>
#include <fabsynth/voxel/block_mask.hpp>

#include <set>

using namespace fabsynth;

namespace {
grid_geometry grid(ivec3 dims) { return {dims, vec3(-1.0, 2.0, 0.5), vec3(0.5)}; }
}  // namespace

TEST_CASE("block_mask: membership, ranks and order agree with std::set on random sets", "[voxel][block_mask]") {
    // dims that are not multiples of 8, so partial border blocks are exercised
    for (const ivec3 dims : {ivec3(13, 7, 21), ivec3(1, 1, 1), ivec3(8, 16, 9), ivec3(40, 3, 17)}) {
        const grid_geometry g = grid(dims);
        for (const double density : {0.0, 0.02, 0.3, 1.0}) {
            INFO("dims " << dims.x << "x" << dims.y << "x" << dims.z << " density " << density);
            counter_rng rng(7, static_cast<std::uint64_t>(dims.x), static_cast<std::uint64_t>(density * 100));
            std::vector<ivec3> voxels;
            std::set<std::uint64_t> ref;
            for (std::uint64_t i = 0; i < g.count(); ++i)
                if (rng.uniform() < density) {
                    voxels.push_back(g.coord(i));
                    ref.insert(i);
                }
            // shuffled, with duplicates
            for (std::size_t i = voxels.size(); i > 1; --i) std::swap(voxels[i - 1], voxels[rng.uniform_int(i)]);
            if (!voxels.empty()) voxels.push_back(voxels.front());
            const block_mask m(g, voxels);
            REQUIRE(m.size() == ref.size());
            CHECK(m.empty() == ref.empty());
            std::vector<std::int64_t> seen(ref.size(), 0);
            for (std::uint64_t i = 0; i < g.count(); ++i) {
                const ivec3 p = g.coord(i);
                const bool in = ref.count(i) != 0;
                REQUIRE(m.contains(p) == in);
                const std::int64_t r = m.rank(p);
                if (in) {
                    REQUIRE(r >= 0);
                    REQUIRE(r < static_cast<std::int64_t>(ref.size()));
                    ++seen[static_cast<std::size_t>(r)];
                } else {
                    REQUIRE(r == -1);
                }
            }
            for (auto c : seen) REQUIRE(c == 1);  // ranks are a bijection onto [0, size)
            // for_each / voxels(): grid-index order
            std::vector<std::uint64_t> order;
            for (const ivec3& p : m.voxels()) order.push_back(g.index(p));
            CHECK(order == std::vector<std::uint64_t>(ref.begin(), ref.end()));
            // outside the grid: never a member
            CHECK_FALSE(m.contains({-1, 0, 0}));
            CHECK_FALSE(m.contains(dims));
            CHECK_FALSE(m.contains({0, dims.y, 0}));
            CHECK(m.rank({0, 0, -1}) == -1);
        }
    }
}

TEST_CASE("block_mask: insert, erase and stale ranks", "[voxel][block_mask]") {
    block_mask m(grid({20, 20, 20}));
    CHECK(m.insert({3, 4, 5}));
    CHECK_FALSE(m.insert({3, 4, 5}));
    CHECK(m.insert({19, 19, 19}));
    CHECK(m.size() == 2);
    CHECK(m.block_count() == 2);
    CHECK_FALSE(m.ranks_valid());
    CHECK_THROWS_AS(m.rank({3, 4, 5}), error);
    m.update_ranks();
    CHECK(m.rank({3, 4, 5}) == 0);
    CHECK(m.rank({19, 19, 19}) == 1);
    CHECK(m.erase({3, 4, 5}));
    CHECK_FALSE(m.erase({3, 4, 5}));
    CHECK_FALSE(m.erase({-3, 4, 5}));
    CHECK_FALSE(m.contains({3, 4, 5}));
    CHECK(m.size() == 1);
    m.update_ranks();
    CHECK(m.rank({19, 19, 19}) == 0);
    CHECK_THROWS_AS(m.insert({20, 0, 0}), invalid_input);
    CHECK_THROWS_AS(m.insert({0, -1, 0}), invalid_input);
    const std::vector<ivec3> outside{{0, 0, 0}, {0, 0, 20}};
    CHECK_THROWS_AS(block_mask(grid({20, 20, 20}), outside), invalid_input);
    // invalid grids and a directory beyond 2^27 blocks
    CHECK_THROWS_AS(block_mask(grid({0, 4, 4})), invalid_input);
    CHECK_THROWS_AS(block_mask(grid({1 << 14, 1 << 14, 1 << 12})), invalid_input);
    const block_mask d;
    CHECK(d.empty());
    CHECK(d.geometry().dims == ivec3(1));
}

TEST_CASE("block_mask: memory is O(grid / 512 + members)", "[voxel][block_mask]") {
    // a plane of 512 x 512 voxels in a 512^3 grid: 4096 blocks of 88 bytes + a 1 MiB directory
    const grid_geometry g = grid({512, 512, 512});
    block_mask m(g);
    for (int y = 0; y < 512; ++y)
        for (int x = 0; x < 512; ++x) m.insert({x, y, 100});
    m.update_ranks();
    CHECK(m.size() == 512u * 512u);
    CHECK(m.block_count() == 64u * 64u);
    CHECK(m.memory_bytes() < (std::size_t{1} << 20) + 2 * 4096 * 88);
    CHECK(m.rank({511, 511, 100}) == 512 * 512 - 1);
    CHECK(m.contains({17, 300, 100}));
    CHECK_FALSE(m.contains({17, 300, 101}));
}
