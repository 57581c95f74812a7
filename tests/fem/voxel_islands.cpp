// fem/detail/voxel_islands.hpp now labels through voxel/components.hpp (plus a periodic glue);
// the oracle is the flood fill it replaced (periodic image tracked per voxel), kept here verbatim.
#include <catch2/catch.hpp>

#include <fabsynth/core/rng.hpp>
#include <fabsynth/fem/detail/voxel_islands.hpp>

#include <array>
#include <vector>

using namespace fabsynth;
using fabsynth::fem::detail::voxel_components;

namespace {
voxel_components reference_islands(const ivec3& cells, bool periodic, const std::vector<double>& scale) {
    const std::size_t total = scale.size();
    voxel_components r;
    r.label.assign(total, -1);
    // Periodic image each voxel was reached in (unwrapped = coords + shift * cells).
    std::vector<std::array<std::int32_t, 3>> shift(periodic ? total : 0);
    std::vector<std::size_t> stack;
    auto index = [&](const ivec3& q) { return static_cast<std::size_t>(q.x) + static_cast<std::size_t>(cells.x) * (static_cast<std::size_t>(q.y) + static_cast<std::size_t>(cells.y) * static_cast<std::size_t>(q.z)); };
    auto coords = [&](std::size_t i) { return ivec3(static_cast<int>(i % static_cast<std::size_t>(cells.x)), static_cast<int>((i / static_cast<std::size_t>(cells.x)) % static_cast<std::size_t>(cells.y)), static_cast<int>(i / (static_cast<std::size_t>(cells.x) * static_cast<std::size_t>(cells.y)))); };
    for (std::size_t s = 0; s < total; ++s) {
        if (scale[s] == 0.0 || r.label[s] >= 0) continue;
        const auto id = static_cast<std::int32_t>(r.size.size());
        r.size.push_back(0);
        r.first.push_back(s);
        r.wraps.push_back(0);
        r.label[s] = id;
        if (periodic) shift[s] = {0, 0, 0};
        stack.push_back(s);
        while (!stack.empty()) {
            const std::size_t v = stack.back();
            stack.pop_back();
            ++r.size.back();
            const ivec3 p = coords(v);
            for (int f = 0; f < 6; ++f) {
                ivec3 q = p;
                q[f / 2] += (f % 2) ? 1 : -1;
                std::array<std::int32_t, 3> sh{};
                if (periodic) {
                    sh = shift[v];
                    for (int a = 0; a < 3; ++a) {
                        if (q[a] < 0) q[a] += cells[a], --sh[static_cast<std::size_t>(a)];
                        else if (q[a] >= cells[a]) q[a] -= cells[a], ++sh[static_cast<std::size_t>(a)];
                    }
                } else if (q[f / 2] < 0 || q[f / 2] >= cells[f / 2]) {
                    continue;
                }
                const std::size_t w = index(q);
                if (scale[w] == 0.0) continue;
                if (r.label[w] >= 0) {
                    if (periodic && shift[w] != sh) r.wraps.back() = 1;
                    continue;
                }
                r.label[w] = id;
                if (periodic) shift[w] = sh;
                stack.push_back(w);
            }
        }
    }
    return r;
}
}  // namespace

TEST_CASE("voxel islands equal the previous flood fill, periodic and not", "[fem][voxel_islands]") {
    int wrapping = 0, several = 0;
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
        const ivec3 cells(1 + static_cast<int>(hash64(seed, 1) % 7), 1 + static_cast<int>(hash64(seed, 2) % 6),
                          1 + static_cast<int>(hash64(seed, 3) % 5));
        const double density = 0.2 + 0.6 * hash_uniform(seed, 4);
        std::vector<double> scale(static_cast<std::size_t>(cells.x * cells.y * cells.z));
        for (std::size_t i = 0; i < scale.size(); ++i) scale[i] = hash_uniform(seed, 5, i) < density ? 1.0 : 0.0;
        for (const bool periodic : {false, true}) {
            const voxel_components want = reference_islands(cells, periodic, scale);
            const voxel_components got = fem::detail::label_voxel_components(cells, periodic, scale);
            REQUIRE(got.label == want.label);
            REQUIRE(got.size == want.size);
            REQUIRE(got.first == want.first);
            REQUIRE(got.wraps == want.wraps);
            for (auto w : want.wraps) wrapping += w;
            several += want.size.size() > 1 ? 1 : 0;
        }
    }
    CHECK(wrapping > 10);  // the cases exercise both outcomes
    CHECK(several > 10);
}
