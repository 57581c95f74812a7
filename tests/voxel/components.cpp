#include <catch2/catch.hpp>

#include <fabsynth/core/rng.hpp>
#include <fabsynth/voxel/components.hpp>

#include <map>
#include <numeric>

using namespace fabsynth;

namespace {

// Brute-force oracle: union-find over every pair of selected voxels whose offset is within the
// neighbourhood, defined by the Chebyshev / L1 distance rather than by the offset tables.
std::vector<int> brute_force_labels(const voxel_grid<std::uint8_t>& g, int max_l1, int& count) {
    const auto n = static_cast<std::size_t>(g.size());
    std::vector<std::size_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](std::size_t x) {
        while (parent[x] != x) x = parent[x];
        return x;
    };
    std::vector<std::size_t> sel;
    for (std::size_t i = 0; i < n; ++i)
        if (g.get(g.coord(i))) sel.push_back(i);
    for (std::size_t a = 0; a < sel.size(); ++a)
        for (std::size_t b = a + 1; b < sel.size(); ++b) {
            const ivec3 d = glm::abs(g.coord(sel[a]) - g.coord(sel[b]));
            if (std::max({d.x, d.y, d.z}) <= 1 && d.x + d.y + d.z <= max_l1) {
                const std::size_t ra = find(sel[a]), rb = find(sel[b]);
                if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
            }
        }
    std::vector<int> label(n, -1);
    std::map<std::size_t, int> root_label;
    count = 0;
    for (std::size_t i : sel) {
        const std::size_t r = find(i);
        if (!root_label.count(r)) root_label[r] = count++;
        label[i] = root_label[r];
    }
    return label;
}

template <class C>
void compare_with_brute_force(int max_l1, std::uint64_t seed, double density) {
    voxel_grid<std::uint8_t> g({9, 7, 6}, vec3(0), 1.0);
    sparse_voxel_grid<std::uint8_t> s({9, 7, 6}, vec3(0), 1.0);
    for (std::uint64_t i = 0; i < g.size(); ++i)
        if (hash_uniform(seed, i) < density) g.set(g.coord(i), 1), s.set(g.coord(i), 1);
    int count = 0;
    const auto want = brute_force_labels(g, max_l1, count);
    auto is_set = [](std::uint8_t v) { return v != 0; };
    const auto got = label_components<C>(g, is_set);
    const auto got_sparse = label_components<C>(s, is_set);
    REQUIRE(got.count == count);
    REQUIRE(got_sparse.count == count);
    std::vector<std::int64_t> sizes(static_cast<std::size_t>(count), 0);
    for (std::uint64_t i = 0; i < g.size(); ++i) {
        const ivec3 p = g.coord(i);
        REQUIRE(got.labels.get(p) == want[i]);  // same numbering: by first voxel in index order
        REQUIRE(got_sparse.labels.get(p) == want[i]);
        if (want[i] >= 0) ++sizes[static_cast<std::size_t>(want[i])];
    }
    CHECK(got.sizes == sizes);
    CHECK(got_sparse.sizes == sizes);
}

}  // namespace

TEST_CASE("component labels match brute-force union-find on random grids", "[voxel][components]") {
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
        const double density = 0.15 + 0.1 * static_cast<double>(seed % 4);
        compare_with_brute_force<connectivity::c6>(1, seed, density);
        compare_with_brute_force<connectivity::c18>(2, seed, density);
        compare_with_brute_force<connectivity::c26>(3, seed, density);
    }
}

TEST_CASE("components: hand-made cases and errors", "[voxel][components]") {
    voxel_grid<std::uint8_t> g({4, 4, 4}, vec3(0), 1.0);
    g.set({0, 0, 0}, 1);
    g.set({1, 1, 1}, 1);  // corner neighbour only
    g.set({3, 3, 3}, 1);
    auto sel = [](std::uint8_t v) { return v != 0; };
    CHECK(label_components<connectivity::c6>(g, sel).count == 3);
    CHECK(label_components<connectivity::c18>(g, sel).count == 3);
    CHECK(label_components<connectivity::c26>(g, sel).count == 2);
    g.set({1, 1, 0}, 1);  // now (0,0,0)-(1,1,0) edge neighbours, (1,1,0)-(1,1,1) face neighbours
    CHECK(label_components<connectivity::c18>(g, sel).count == 2);
    CHECK(label_components<connectivity::c6>(g, sel).count == 3);
    // the complement: one 6-connected component
    CHECK(label_components<connectivity::c6>(g, [](std::uint8_t v) { return v == 0; }).count == 1);
    // one huge component does not recurse
    voxel_grid<std::uint8_t> full({64, 64, 64}, vec3(0), 1.0, 1);
    const auto cc = label_components<connectivity::c6>(full, sel);
    CHECK(cc.count == 1);
    CHECK(cc.sizes[0] == 64 * 64 * 64);
    sparse_voxel_grid<std::uint8_t> s({4, 4, 4}, vec3(0), 1.0);
    CHECK_THROWS_AS(label_components<connectivity::c6>(s, [](std::uint8_t v) { return v == 0; }), invalid_input);
}
