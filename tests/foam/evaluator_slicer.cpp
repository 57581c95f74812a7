// The fast slicer paths of evaluator.hpp: run filling for a constant radius, per-pixel tests for
// a varying one, tile sizes, and the adaptive seed margin of gather(), each against contains()
// (one-point boxes, a different gather) and the independent Voronoi construction.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/foam/evaluator.hpp"
#include "foam/reference_voronoi.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;

namespace {

// Pixels of slice(z, region, pix) whose value differs from contains() at the pixel centre.
template <class D, class R>
long slice_vs_contains(const voronoi_foam<D, R>& f, const image8& img, double z, const box2& region, double pix) {
    long bad = 0;
    for (int j = 0; j < img.height; ++j)
        for (int i = 0; i < img.width; ++i) {
            const vec3 q(region.lo.x + (i + 0.5) * pix, region.lo.y + (j + 0.5) * pix, z);
            bad += (img.at(i, j) == 255) != f.contains(q);
        }
    return bad;
}

long solid_pixels(const image8& img) {
    long n = 0;
    for (auto v : img.data) n += v == 255;
    return n;
}

}  // namespace

TEST_CASE("foam slice equals contains() for every tile size (constant radius: run filling)", "[foam]") {
    // the benchmark's graded foam on a strip that spans sparse and dense density
    voronoi_foam f(linear_field{0, 0.01, 0.5, 0, 50}, constant_field{0.25}, {.cell = 5, .seed = 2016});
    const box2 region({0, 20}, {50, 23});
    const double pix = 0.05, z = 20.013;
    set_num_threads(2);
    const image8 ref = f.slice(z, region, pix, {.tile = 128});
    for (int tile : {8, 37, 64, 256, 1024}) {
        INFO("tile " << tile);
        CHECK(f.slice(z, region, pix, {.tile = tile}) == ref);
    }
    set_num_threads(1);
    CHECK(f.slice(z, region, pix) == ref);
    set_num_threads(0);
    CHECK(solid_pixels(ref) > static_cast<long>(ref.data.size()) / 10);  // not a trivial image
    CHECK(slice_vs_contains(f, ref, z, region, pix) == 0);
}

TEST_CASE("foam slice equals contains() with a varying radius (per-pixel path)", "[foam]") {
    voronoi_foam f(linear_field{0, 0.05, 2.0, 0, 10}, linear_field{1, 0.08, 0.3, 0, 10}, {.cell = 2, .seed = 31});
    const box2 region({0, 0}, {10, 10});
    const double pix = 0.04, z = 3.3;
    const image8 a = f.slice(z, region, pix, {.tile = 128});
    const image8 b = f.slice(z, region, pix, {.tile = 24});
    CHECK(a == b);
    CHECK(solid_pixels(a) > static_cast<long>(a.data.size()) / 10);
    CHECK(slice_vs_contains(f, a, z, region, pix) == 0);
}

TEST_CASE("foam evaluator with a thin dense layer (seed margin grows over several passes)", "[foam]") {
    // 20 seeds/mm^3 in 2 <= x <= 2.6, the 1/L^3 minimum elsewhere. A 64-pixel tile of the slices
    // below is centred in the layer, so gather() starts from a margin of ~0.9 mm, while its
    // sub-boxes near x = 0.8 are > 1 mm from any seed: the margin must grow (second pass).
    auto rho = [](const vec3& p) { return p.x >= 2.0 && p.x <= 2.6 ? 20.0 : 0.0; };
    voronoi_foam f(rho, constant_field{0.15}, {.cell = 2, .seed = 41});
    const box3 Q({0.7, 0, 1.2}, {3.9, 4, 3.1});
    const double tm = f.max_radius();
    const box3 E = Q.inflated(tm * 1.01);
    const auto seeds = f.seeds().seeds_in_box(E.inflated(2 * std::sqrt(3.0) * 2 + 0.5));
    reftest::reference_edges ref(seeds, E);
    counter_rng rng(5, 6);
    long tested = 0, banded = 0, solid = 0, disagree = 0;
    // compares one answer of the evaluator at q with the oracle, skipping the 1e-9 band
    auto check = [&](const vec3& q, bool foam_solid) {
        const double d = ref.distance(q, tm);
        ++tested;
        if (std::abs(d - 0.15) < 1e-9) {
            ++banded;
            return;
        }
        solid += d <= 0.15;
        disagree += foam_solid != (d <= 0.15);
    };
    for (int n = 0; n < 4000; ++n) {
        const vec3 q = Q.lo + Q.size() * vec3(rng.uniform(), rng.uniform(), rng.uniform());
        check(q, f.contains(q));
    }
    // slices: 64 x 80 pixels, one tile wide (tile 64) or 4 x 5 tiles (tile 16)
    for (double z : {2.15, 1.9, 2.42}) {
        const box2 region({Q.lo.x, Q.lo.y}, {Q.hi.x, Q.hi.y});
        const image8 img = f.slice(z, region, 0.05, {.tile = z == 1.9 ? 16 : 64});
        for (int j = 0; j < img.height; ++j)
            for (int i = 0; i < img.width; ++i) {
                const vec3 q(region.lo.x + (i + 0.5) * 0.05, region.lo.y + (j + 0.5) * 0.05, z);
                check(q, img.at(i, j) == 255);
            }
    }
    INFO("tested " << tested << " solid " << solid << " banded " << banded);
    CHECK(solid > tested / 20);
    CHECK(disagree == 0);
}

TEST_CASE("foam edges_in_box on a flat box", "[foam]") {
    voronoi_foam f(constant_field{0.5}, constant_field{0.2}, {.cell = 2, .seed = 3});
    const box3 flat({0, 0, 1}, {4, 4, 1});  // zero thickness: one sub-box along z
    std::vector<edge_segment> e;
    f.edges_in_box(flat, e);
    CHECK(!e.empty());  // Voronoi edges cross any plane
    for (const auto& s : e) {
        CHECK(s.a.z == Approx(1.0).margin(1e-9));
        CHECK(s.b.z == Approx(1.0).margin(1e-9));
    }
}
