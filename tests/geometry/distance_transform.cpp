// Exact Euclidean distance transform against brute force over all feature cells.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/distance_transform.hpp"

using namespace fabsynth;

namespace {
std::vector<double> brute_force(const std::array<std::size_t, 3>& n, const std::vector<bool>& feature) {
    std::vector<double> d(feature.size(), std::numeric_limits<double>::infinity());
    auto idx = [&](std::size_t i, std::size_t j, std::size_t k) { return i + n[0] * (j + n[1] * k); };
    for (std::size_t k = 0; k < n[2]; ++k)
        for (std::size_t j = 0; j < n[1]; ++j)
            for (std::size_t i = 0; i < n[0]; ++i)
                for (std::size_t c = 0; c < n[2]; ++c)
                    for (std::size_t b = 0; b < n[1]; ++b)
                        for (std::size_t a = 0; a < n[0]; ++a)
                            if (feature[idx(a, b, c)]) {
                                const double di = double(i) - double(a), dj = double(j) - double(b), dk = double(k) - double(c);
                                d[idx(i, j, k)] = std::min(d[idx(i, j, k)], di * di + dj * dj + dk * dk);
                            }
    return d;
}
}  // namespace

TEST_CASE("squared distance transform equals brute force in 1D, 2D and 3D", "[geometry][distance_transform]") {
    const std::vector<std::array<std::size_t, 3>> shapes = {{31, 1, 1}, {17, 13, 1}, {1, 19, 1}, {9, 7, 5}, {4, 1, 11}};
    int seed = 0;
    for (const auto& n : shapes)
        for (double density : {0.0, 0.01, 0.1, 0.5, 1.0}) {
            std::vector<bool> feature(n[0] * n[1] * n[2]);
            for (std::size_t i = 0; i < feature.size(); ++i) feature[i] = hash_uniform(7, seed, i) < density;
            ++seed;
            INFO("grid " << n[0] << " x " << n[1] << " x " << n[2] << ", density " << density);
            const std::vector<double> d = squared_distance_transform(n, feature);
            REQUIRE(d == brute_force(n, feature));  // exact, +inf where there is no feature at all
        }
}

TEST_CASE("distance transform: a single point gives squared radii, threads do not matter", "[geometry][distance_transform]") {
    const std::array<std::size_t, 3> n = {64, 48, 40};
    std::vector<bool> feature(n[0] * n[1] * n[2], false);
    feature[10 + 64 * (20 + 48 * 30)] = true;
    set_num_threads(1);
    const std::vector<double> one = squared_distance_transform(n, feature);
    set_num_threads(0);
    const std::vector<double> all = squared_distance_transform(n, feature);
    CHECK(one == all);
    CHECK(all[0] == 10.0 * 10 + 20.0 * 20 + 30.0 * 30);
    CHECK(all[63 + 64 * (47 + 48 * 39)] == 53.0 * 53 + 27.0 * 27 + 9.0 * 9);
    CHECK_THROWS_AS(squared_distance_transform({4, 4, 1}, std::vector<bool>(15)), invalid_input);
    CHECK_THROWS_AS(squared_distance_transform({0, 4, 1}, std::vector<bool>()), invalid_input);
}
