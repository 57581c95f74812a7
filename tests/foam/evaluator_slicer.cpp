// The fast slicer paths of evaluator.hpp: run filling for a constant radius, per-pixel tests for
// a varying one, tile sizes, stacks of slices (edges per slab), and the adaptive seed margin of
// gather(), each against contains() (one-point boxes, a different gather), single slices and the
// independent Voronoi construction.
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

TEST_CASE("foam stacks of slices equal slice-by-slice images for 1 and 2 threads", "[foam][stack]") {
    // constant radius (run filling) over two slabs of a 5 mm cell, and a varying radius with
    // supersampling; each also with slabs cut to 3 slices by the image budget
    const voronoi_foam f(linear_field{0, 0.01, 0.5, 0, 50}, constant_field{0.25}, {.cell = 5, .seed = 2016});
    const voronoi_foam g(linear_field{0, 0.05, 2.0, 0, 10}, linear_field{1, 0.08, 0.3, 0, 10}, {.cell = 2, .seed = 31});
    const box2 region({20, 20}, {30, 23});
    const auto check = [&](const auto& foam, double z0, double dz, int count, slice_options so) {
        for (unsigned threads : {1u, 2u}) {
            set_num_threads(threads);
            for (std::size_t slab : {std::size_t(256) << 20, std::size_t(3) * 200 * 60}) {
                so.slab_bytes = slab;
                const std::vector<image8> stack = foam.slices(z0, dz, count, region, 0.05, so);
                REQUIRE(stack.size() == static_cast<std::size_t>(count));
                long differ = 0, solid = 0;
                for (int k = 0; k < count; ++k) {
                    const image8 one = foam.slice(z0 + k * dz, region, 0.05, so);
                    differ += stack[static_cast<std::size_t>(k)] != one;
                    solid += solid_pixels(one);
                }
                INFO(threads << " threads, slab budget " << slab << " bytes, " << solid << " solid pixels");
                CHECK(differ == 0);
                CHECK(solid > count * 200L * 60 / 20);
            }
        }
        set_num_threads(0);
    };
    check(f, 17.513, 0.05, 120, {});                    // 6 mm: slabs of one 5 mm cell and the rest
    check(g, 3.01, 0.07, 30, {.supersample = 2});       // varying radius, 2 x 2 samples per pixel
    // a stack of heights handed out in order, and its bad input
    std::vector<double> zs{1.0, 1.5, 9.0};
    std::vector<std::size_t> order;
    f.for_each_slice(zs, region, 0.05, [&](std::size_t k, image8& img) {
        order.push_back(k);
        CHECK(img == f.slice(zs[k], region, 0.05));
    });
    CHECK(order == std::vector<std::size_t>{0, 1, 2});
    const auto ignore = [](std::size_t, image8&) {};
    CHECK_THROWS_AS(f.for_each_slice(std::vector<double>{}, region, 0.05, ignore), invalid_input);
    CHECK_THROWS_AS(f.for_each_slice(std::vector<double>{1.0, 1.0}, region, 0.05, ignore), invalid_input);
    CHECK_THROWS_AS(f.for_each_slice(std::vector<double>{1.0, NAN}, region, 0.05, ignore), invalid_input);
    CHECK_THROWS_AS(f.slices(0, 0, 3, region, 0.05), invalid_input);
    CHECK_THROWS_AS(f.slices(0, 0.1, 0, region, 0.05), invalid_input);
    CHECK_THROWS_AS(f.slices(NAN, 0.1, 2, region, 0.05), invalid_input);
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
