// Slice-stack planning (foam/slice_stack.hpp) against the layer arithmetic written out here.
#include <catch2/catch.hpp>

#include <cmath>

#include "fabsynth/foam/slice_stack.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;

TEST_CASE("slice stack: layers, selected layers, heights and region", "[foam][slice_stack]") {
    const box3 bb({1, 2, 3}, {11, 7, 8.05});  // 5.05 mm tall
    const slice_stack all = plan_slice_stack(bb, 0.1, 0.5, 0);
    CHECK(all.layers == 10);  // floor(5.05 / 0.5)
    REQUIRE(all.selected.size() == 10);
    for (int k = 0; k < 10; ++k) {
        CHECK(all.selected[static_cast<std::size_t>(k)] == k);
        CHECK(all.z(k) == Approx(3 + 0.5 * k + 0.25));
    }
    CHECK(all.region.lo == vec2(0.9, 1.9));
    CHECK(all.region.hi == vec2(11.1, 7.1));
    const slice_stack four = plan_slice_stack(bb, 0.1, 0.5, 4);
    CHECK(four.selected == std::vector<int>{1, 3, 6, 8});  // floor((s + 1/2) 10 / 4)
    const slice_stack dflt = plan_slice_stack(bb, 0.25, 0, 0);  // layer height = pixel
    CHECK(dflt.layer == 0.25);
    CHECK(dflt.layers == 20);
    const slice_stack flat = plan_slice_stack(box3({0, 0, 0}, {1, 1, 0.01}), 0.1, 0.1, 0);
    CHECK(flat.layers == 1);
    CHECK_THROWS_AS(plan_slice_stack(bb, 0, 0.5, 0), invalid_input);
    CHECK_THROWS_AS(plan_slice_stack(box3(), 0.1, 0.5, 0), invalid_input);
    CHECK(plan_slice_stack(bb, 0.1, 0.5, 10).selected == all.selected);  // as many slices as layers: every layer
    CHECK_THROWS_WITH(plan_slice_stack(bb, 0.1, 0.5, 11), Catch::Contains("only 10 layers"));
    CHECK_THROWS_WITH(plan_slice_stack(box3({0, 0, 0}, {1, 1, 1e300}), 0.1, 0.1, 0), Catch::Contains("too many"));
}

TEST_CASE("slice stack cost: the planned stack's slices and pixels, before planning", "[foam][slice_stack]") {
    const box3 bb({1, 2, 3}, {11, 7, 8.05});
    for (int count : {0, 4, 10}) {
        const slice_stack st = plan_slice_stack(bb, 0.1, 0.5, count);
        const slice_stack_cost c = estimate_slice_stack(bb, 0.1, 0.5, count, 3, 1e12);
        INFO("count " << count);
        CHECK(c.slices == static_cast<double>(st.selected.size()));
        // the region's pixels as the slicer counts them (ceil of its side over the pixel)
        const double nx = std::ceil((st.region.hi.x - st.region.lo.x) / st.pixel - 1e-9), ny = std::ceil((st.region.hi.y - st.region.lo.y) / st.pixel - 1e-9);
        CHECK(std::abs(c.pixels_per_slice - nx * ny) <= nx + ny + 1);  // at most one row and column of rounding
        CHECK(c.evaluations == Approx(c.slices * c.pixels_per_slice * 9));
        CHECK(c.slab_bytes == Approx(c.slices * c.pixels_per_slice));  // the whole stack fits the slab
    }
    // a small slab holds one slice at least; the layer height defaults to the pixel
    const slice_stack_cost tight = estimate_slice_stack(bb, 0.25, 0, 0, 1, 10);
    CHECK(tight.slices == 20);
    CHECK(tight.slab_bytes == tight.pixels_per_slice);
    // the 2e12-evaluation stack is priced without allocating anything
    const slice_stack_cost huge = estimate_slice_stack(box3({0, 0, 0}, {40, 40, 40}), 0.003, 0, 0, 1, 256e6);
    CHECK(huge.evaluations > 2e12);
}
