// How a filigree reads (filigree/appearance.hpp) on drawings whose answer is known by hand: an X
// is one transversal crossing, a T-junction, a shallow crossing and a matched overlap are none;
// the overlap area of two crossing strips is their square; free ends are the ends that touch no
// other strip. Then the crossing term of the matching energy (pattern_state::pair_energy) on the
// pipeline: it lowers the crossings per instance of a fixed run, and an over-dense initialization
// ends with fewer instances once complete overlaps are merged (§3.5 "Discussion").
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "fabsynth/filigree/appearance.hpp"
#include "fabsynth/filigree/pipeline.hpp"
#include "support/filigree_elements.hpp"

namespace appearance_test {

using namespace fabsynth;
using namespace fabsynth::filigree;
using skeleton = graph::skeleton_graph<vec2>;

// A straight strip from a to b, `width` mm wide, split into `pieces` edges.
inline skeleton strip(vec2 a, vec2 b, double width = 1.0, int pieces = 4) {
    skeleton g;
    for (int k = 0; k <= pieces; ++k) g.add_vertex(a + (b - a) * (static_cast<double>(k) / pieces), width);
    for (int k = 0; k < pieces; ++k) g.add_edge(static_cast<graph::vertex_id>(k), static_cast<graph::vertex_id>(k + 1));
    return g;
}

inline appearance_report measure(const std::vector<skeleton>& s) {
    return measure_appearance(std::span<const skeleton>(s), [](vec2) { return true; });
}

// A strip through the origin at `deg` degrees, 20 mm long.
inline skeleton at_angle(double deg) {
    const double a = deg * std::numbers::pi / 180;
    const vec2 d(std::cos(a), std::sin(a));
    return strip(-10.0 * d, 10.0 * d);
}

TEST_CASE("appearance: an X is a crossing; a T, a shallow crossing and a matched overlap are not", "[filigree][appearance]") {
    SECTION("X at 90 and at 45 degrees") {
        for (const double deg : {90.0, 45.0, 31.0}) {
            INFO(deg);
            const auto r = measure({at_angle(0), at_angle(deg)});
            CHECK(r.transversal_crossings == 1);
            CHECK(r.crossings_per_instance == Approx(0.5));
        }
    }
    SECTION("shallow crossing: a near-tangent contact") {
        CHECK(measure({at_angle(0), at_angle(20)}).transversal_crossings == 0);
        appearance_options o;
        o.min_crossing_angle_deg = 10;
        CHECK(measure_appearance(std::span<const skeleton>(std::vector<skeleton>{at_angle(0), at_angle(20)}), [](vec2) { return true; }, o)
                  .transversal_crossings == 1);
    }
    SECTION("T: a strip ending on another") {
        const auto r = measure({strip({-10, 0}, {10, 0}), strip({0, 0}, {0, 10})});
        CHECK(r.transversal_crossings == 0);
        CHECK(r.free_ends == 3);  // the T's foot touches the bar
    }
    SECTION("a strip ending just past another (a stub shorter than the width)") {
        CHECK(measure({strip({-10, 0}, {10, 0}), strip({0, -0.5}, {0, 10})}).transversal_crossings == 0);
        CHECK(measure({strip({-10, 0}, {10, 0}), strip({0, -3}, {0, 10})}).transversal_crossings == 1);
    }
    SECTION("matched overlap: the same strip twice") {
        const auto r = measure({strip({-10, 0}, {10, 0}), strip({-10, 0}, {10, 0}, 1.0, 3)});
        CHECK(r.transversal_crossings == 0);
        CHECK(r.overlap_area_fraction == Approx(1.0).margin(0.02));
    }
    SECTION("outside the region nothing counts") {
        const std::vector<skeleton> s{at_angle(0), at_angle(90)};
        CHECK(measure_appearance(std::span<const skeleton>(s), [](vec2 p) { return p.x > 1; }).transversal_crossings == 0);
    }
    SECTION("one instance, or none") {
        CHECK(measure({at_angle(0)}).transversal_crossings == 0);
        CHECK(measure({}).instances == 0);
    }
}

TEST_CASE("appearance: overlap area and free ends", "[filigree][appearance]") {
    // Two 20 mm strips, 1 mm wide, crossing at right angles: they share a 1 mm square (round caps
    // lie outside it), of a union of about 2 x 20.8 - 1 mm^2.
    const auto r = measure({at_angle(0), at_angle(90)});
    const double cap = std::numbers::pi * 0.25;  // two half-discs of radius 0.5 per strip
    CHECK(r.overlap_area_fraction == Approx(1.0 / (2 * (20 + cap) - 1)).epsilon(0.1));
    CHECK(r.free_ends == 4);
    // Apart: no overlap, four free ends; touching end to side: three.
    CHECK(measure({strip({0, 0}, {10, 0}), strip({0, 5}, {10, 5})}).overlap_area_fraction == 0.0);
    CHECK(measure({strip({0, 0}, {10, 0}), strip({0, 5}, {10, 5})}).free_ends == 4);
    CHECK(measure({strip({0, 0}, {10, 0}), strip({5, 0.9}, {5, 10})}).free_ends == 3);
}

TEST_CASE("appearance: transversal_crossings of placed instances agrees with the skeleton count", "[filigree][appearance]") {
    const element e = fabsynth::test::filigree_element("spiral", 20, 0.8);
    const std::vector<element> cls{e};
    const instance a = make_instance(std::span<const element>(cls), 0, {0, 0}, constant_field{});
    for (const double dx : {4.0, 8.0, 12.0, 30.0}) {
        INFO(dx);
        const instance b = make_instance(std::span<const element>(cls), 0, {dx, 0}, constant_field{});
        const placed pa = place(e, a), pb = place(e, b);
        // Oracle: every edge pair, no box filter.
        std::size_t n = 0;
        for (const auto& f : e.edges)
            for (const auto& g : e.edges) {
                const vec2 p0 = pa.vertices[f[0]], p1 = pa.vertices[f[1]], q0 = pb.vertices[g[0]], q1 = pb.vertices[g[1]];
                if (!fabsynth::detail::segments_intersect(p0, p1, q0, q1)) continue;
                const vec2 dp = p1 - p0, dq = q1 - q0;
                if (std::abs(glm::dot(dp, dq)) < std::cos(std::numbers::pi / 6) * glm::length(dp) * glm::length(dq)) ++n;
            }
        CHECK(transversal_crossings(pa, pb, std::cos(std::numbers::pi / 6)) == n);
        if (dx < 10) CHECK(n > 0);
        if (dx > 25) CHECK(n == 0);
    }
}

TEST_CASE("crossing term: fewer strips cut across each other; an over-dense start ends with fewer instances", "[filigree][appearance][pipeline]") {
    const std::vector<element> cls{fabsynth::test::filigree_element("spiral", 20, 0.8)};
    const std::vector<double> w{1.0};
    const auto dom = planar_domain::rectangle(90, 70);
    auto run = [&](double penalty, double union_overlap, double single_overlap) {
        filigree_options o;
        o.synthesis.seed = 1;
        o.synthesis.crossing_penalty = penalty;
        o.synthesis.init.max_union_overlap = union_overlap;
        o.synthesis.init.max_single_overlap = single_overlap;
        o.reinforcement.enabled = false;
        o.previews = false;
        return make_filigree(std::span<const element>(cls), w, dom, constant_field{}, o);
    };
    const planar_filigree plain = run(0.0, 0.6, 0.3), crossing = run(5.0, 0.6, 0.3);
    WARN("crossings per instance: eq. 2 alone " << plain.appearance.crossings_per_instance << ", with the crossing term "
                                                << crossing.appearance.crossings_per_instance);
    // Measured 2026-12-06: 3.6 -> 0.94 on this case (with moves free to stack instances, eq. 2 alone
    // piles them up); the bound asks for about half of that drop.
    CHECK(crossing.appearance.crossings_per_instance < 0.6 * plain.appearance.crossings_per_instance);

    // An over-dense start (rules 1 and 2 loosened to 90% / 80%): placement may stack instances
    // completely and the duplicates are merged, so fewer instances come out than went in
    // (measured: 107 -> 53, 54 merged; the default start gives 54).
    const planar_filigree dense = run(5.0, 0.9, 0.8);
    WARN("over-dense start: " << dense.synthesis.initial.size() << " instances -> " << dense.synthesis.instances.size() << " ("
                              << dense.synthesis.duplicates_removed << " merged)");
    CHECK(dense.synthesis.initial.size() > crossing.synthesis.initial.size());
    CHECK(dense.synthesis.duplicates_removed > 0);
    CHECK(dense.synthesis.instances.size() < dense.synthesis.initial.size());
    // The per-round record (Fig. 22 and its counts) adds up to the run's totals.
    const auto& rounds = dense.synthesis.per_round;
    REQUIRE(rounds.size() == static_cast<std::size_t>(dense.synthesis.rounds));
    std::size_t merged = 0, boosted = 0;
    for (const round_record& rr : rounds) merged += rr.duplicates_removed, boosted += rr.boosted;
    CHECK(merged == dense.synthesis.duplicates_removed);
    CHECK(boosted == dense.synthesis.boosted);
    CHECK(rounds.back().instances == dense.synthesis.instances.size());
    CHECK(rounds.back().pme_per_instance == Approx(dense.synthesis.energy_per_round.back()));
}

}  // namespace appearance_test

namespace appearance_test {

// reinforce's one piece (reinforcement.hpp): a piece the domain's edge or a gap cut off is joined
// by a bridge strip when its nearest contact is within max_bridge_mm, trimmed when it is too small
// to print, dropped (and counted) otherwise.
TEST_CASE("one piece: cut-off pieces are bridged, trimmed or dropped, and counted", "[filigree][reinforce]") {
    const std::vector<element> cls{fabsynth::test::filigree_element("spiral", 20, 0.8)};
    const std::vector<double> w{1.0};
    const auto dom = planar_domain::rectangle(40, 20);
    synthesis_result syn;
    syn.skeletons = {strip({2, 10}, {38, 10}, 0.8), strip({20, 11.5}, {20, 18}, 0.8)};  // a 0.7 mm gap between the strips
    syn.instances.resize(2);
    reinforcement_options ro;
    ro.enabled = false;
    const synthesis_options so;

    const reinforcement_result joined = reinforce(cls, w, dom, constant_field{}, so, syn, ro);
    CHECK(joined.pieces_bridged == 1);
    CHECK(joined.pieces_dropped == 0);
    CHECK(joined.dropped_area_fraction == 0.0);
    const double cap = std::numbers::pi * 0.16, long_strip = 36 * 0.8 + cap, short_strip = 6.5 * 0.8 + cap;
    CHECK(area(joined.outline) > long_strip + short_strip);  // both strips, and the bridge

    ro.max_bridge_mm = -1;  // no bridges: the short strip is dropped
    const reinforcement_result apart = reinforce(cls, w, dom, constant_field{}, so, syn, ro);
    CHECK(apart.pieces_bridged == 0);
    CHECK(apart.pieces_dropped == 1);
    CHECK(apart.dropped_area_fraction == Approx(short_strip / (long_strip + short_strip)).epsilon(0.02));

    ro.max_bridge_mm = 0;  // 4 x 0.8 mm: a strip 5 mm away stays apart; a dot is trimmed
    syn.skeletons = {strip({2, 10}, {38, 10}, 0.8), strip({5, 16}, {30, 16}, 0.8), strip({35, 16}, {35.3, 16}, 0.8)};
    syn.instances.resize(3);
    const reinforcement_result far = reinforce(cls, w, dom, constant_field{}, so, syn, ro);
    CHECK(far.pieces_bridged == 0);
    CHECK(far.pieces_dropped == 1);
    CHECK(far.pieces_trimmed == 1);
}

}  // namespace appearance_test
