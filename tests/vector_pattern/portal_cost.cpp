// Tests for vector_pattern/portal_cost.hpp: the §3.6.1 transition cost between pieces, and that
// synthesize_along's DP table (detail::junction_costs) is that cost and nothing else.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "fabsynth/io/svg.hpp"
#include "fabsynth/vector_pattern.hpp"

namespace vp = fabsynth::vector_pattern;
namespace dp = fabsynth::dp;

TEST_CASE("portal transition costs follow §3.6.1", "[pattern][portal_cost]") {
    const vp::portal_side right_a{{1.0, 0.0, -2.0, -3.0}, {{1, 0}, {1, 0}, {1, 0}, {1, 0}}};
    const vp::portal_side left_b{{3.5, 2.5, 0.5, -0.5}, {{1, 0}, {0, 2}, {1, 0}, {-1, 0}}};  // shifted by +2.5
    const vp::portal_match m = vp::match_portals(right_a, left_b);
    CHECK(m.d_match == Approx(0.0).margin(1e-12));
    CHECK(m.offset == Approx(-2.5));  // moving b down by 2.5 mm aligns it
    CHECK(m.d_tangent == Approx(0.0 + 1.0 + 0.0 + 2.0));
    // Heights 0,0 vs 1,-1: best shift 0, mean squared residual 1.
    const vp::portal_match v = vp::match_portals({{0.0, 0.0}, {{1, 0}, {1, 0}}}, {{1.0, -1.0}, {{1, 0}, {1, 0}}});
    CHECK(v.d_match == Approx(1.0));
    CHECK(v.offset == Approx(0.0));

    std::vector<vp::piece_portals> pieces(3);
    pieces[0].right = right_a;
    pieces[1].left = left_b;
    pieces[1].right = {{0.0, -1.0}, {{1, 0}, {1, 0}}};
    pieces[2].left = {{0.0, -1.0}, {{1, 0}, {1, 0}}};
    const dp::transition_table t = vp::portal_transition_table(pieces);
    CHECK(t.compatible(0, 1));
    CHECK_FALSE(t.compatible(0, 2));  // 4 endpoints vs 2
    CHECK_FALSE(t.compatible(1, 1));
    CHECK(t.compatible(1, 2));
    CHECK(t.compatible(2, 0));  // 0 endpoints on both: nothing to match
    CHECK(t.cost(0, 1) == Approx(0.8 * 0.0 + 0.2 * 3.0));
    CHECK(t.offset(0, 1) == Approx(-2.5));
    CHECK(t.cost(1, 2) == Approx(0.0).margin(1e-15));
    CHECK(t.cost(2, 0) == 0.0);

    std::vector<vp::piece_portals> bad(1);
    bad[0].left = {{1.0}, {{1, 0}}};  // odd endpoint count
    CHECK_THROWS_AS(vp::portal_transition_table(bad), fabsynth::invalid_input);
    bad[0].left = {{1.0, 2.0}, {{1, 0}}};  // tangent missing
    CHECK_THROWS_AS(vp::portal_transition_table(bad), fabsynth::invalid_input);
    bad[0].left = {{1.0, std::nan("")}, {{1, 0}, {1, 0}}};
    CHECK_THROWS_AS(vp::portal_transition_table(bad), fabsynth::invalid_input);
    bad[0].left = {{1.0, 2.0}, {{1, 0}, {0, 0}}};
    CHECK_THROWS_AS(vp::portal_transition_table(bad), fabsynth::invalid_input);
    CHECK_THROWS_AS(vp::portal_transition_table(pieces, 1.5), fabsynth::invalid_input);
}

TEST_CASE("synthesis builds its DP table from portal_cost alone", "[pattern][portal_cost]") {
    const vp::exemplar ex = vp::exemplar_from_svg(fabsynth::io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/greek_key.svg"));
    // Closed curve: the DP pieces are the sliced pieces themselves, so with seed 0 and no ban the
    // table must equal portal_transition_table over the pieces' portals, entry for entry.
    vp::synthesis_options o{.length = 300.0, .closed = true};
    const vp::detail::prepared_pieces pp = vp::detail::prepare_pieces(ex, o);
    REQUIRE(pp.dp.size() == pp.pieces.size());
    std::vector<vp::piece_portals> portals;
    for (const vp::piece& p : pp.pieces) portals.push_back(vp::portals_of(p));
    const dp::transition_table expected = vp::portal_transition_table(portals, o.alpha);
    const dp::transition_table table = vp::detail::junction_costs(pp, o, {}, {});
    const std::size_t n = pp.pieces.size();
    std::size_t compatible = 0;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            REQUIRE(table.compatible(i, j) == expected.compatible(i, j));
            if (!table.compatible(i, j)) continue;
            ++compatible;
            CHECK(table.cost(i, j) == expected.cost(i, j));
            CHECK(table.offset(i, j) == expected.offset(i, j));
        }
    CHECK(compatible > 0);
    // A ban removes exactly that transition; a seed scales costs by a factor in [1, 1 + variation).
    std::size_t bi = 0, bj = 0;
    while (!expected.compatible(bi, bj)) (bj + 1 < n) ? ++bj : (bj = 0, ++bi);
    const dp::transition_table banned = vp::detail::junction_costs(pp, o, {{bi, bj}}, {});
    CHECK_FALSE(banned.compatible(bi, bj));
    const dp::transition_table seeded = vp::detail::junction_costs(pp, o, {}, {.seed = 5, .variation = 0.25});
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (expected.compatible(i, j)) {
                CHECK(seeded.cost(i, j) >= expected.cost(i, j));
                CHECK(seeded.cost(i, j) <= 1.25 * expected.cost(i, j) + 1e-15);
                CHECK(seeded.offset(i, j) == expected.offset(i, j));
            }
}
