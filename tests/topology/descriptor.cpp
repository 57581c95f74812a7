// Tests for topology/descriptor.hpp: canonical form, merge (Fig. 4, Fig. 5), loop closing (Fig. 6),
// associativity, and agreement with an independent glue-graph oracle on random planar pieces.
#include <catch2/catch.hpp>

#include <fabsynth/topology.hpp>

#include "topology/random_planar.hpp"

#include <vector>

using fabsynth::topology::descriptor;
using fabsynth::topology::loop_closure;
namespace topo = fabsynth::topology;

TEST_CASE("descriptors are canonical: equal topologies compare and hash equal", "[topology]") {
    const descriptor a({7, 3}, {3, 9, 9}, 2, 1), b({0, 1}, {1, 2, 2}, 2, 1);
    CHECK(a == b);
    CHECK(a.hash() == b.hash());
    CHECK(std::vector<topo::portal_id>(a.left().begin(), a.left().end()) == std::vector<topo::portal_id>{0, 1});
    CHECK(std::vector<topo::portal_id>(a.right().begin(), a.right().end()) == std::vector<topo::portal_id>{1, 2, 2});
    CHECK(a.open_components() == 3);
    CHECK(a.open_portals() == 5);
    CHECK_FALSE(a == descriptor({0, 1}, {1, 2, 2}, 2, 0));   // counters matter
    CHECK_FALSE(a == descriptor({0, 1}, {0, 2, 2}, 2, 1));   // connectivity matters
    CHECK_FALSE(descriptor({0}, {0, 1}) == descriptor({0, 1}, {1}));  // the side split matters
    // Many portals take the hash-map path of canonicalisation; the result is the same form.
    std::vector<std::uint32_t> left, right;
    for (std::uint32_t k = 0; k < 40; ++k) left.push_back(1000 - k / 2), right.push_back(1000 - k / 4);
    const descriptor big(left, right);
    CHECK(big.left()[0] == 0);
    CHECK(big.left()[2] == 1);
    CHECK(big.right()[0] == 0);
    CHECK(big.open_components() == 20);
}

TEST_CASE("Fig. 4: joining two pieces closes the 'g' and its hole", "[topology]") {
    // (a): four components: one passes through (left 0 -> right 0), one ends inside (left 1 only),
    // two start inside: the top of the 'g' (right 1 and 2, an arch opening to the right) and its
    // tail (right 3). (b): two components: one passes through, one ends inside joining left 1..3.
    const descriptor a({0, 1}, {0, 2, 2, 3});
    const descriptor b({0, 1, 1, 1}, {0});
    const descriptor ab = merge(a, b);
    // (d): three components remain, one of them closed; one portal on the right; one hole.
    CHECK(ab == descriptor({0, 1}, {0}, 1, 1));
    CHECK(ab.enclosed() + ab.open_components() == 3);
    CHECK(ab.right().size() == 1);
}

TEST_CASE("Fig. 5: equal component counts, different descriptors, different results", "[topology]") {
    const descriptor start({}, {0, 1});
    const descriptor split_f({0, 1}, {0, 1, 1});  // bottom strand forks: right ids 0,1,1
    const descriptor split_j({0, 1}, {0, 0, 1});  // top strand forks:    right ids 0,0,1
    const descriptor end({0, 1, 1}, {});          // top portal capped alone, the lower two joined
    const descriptor f = merge(start, split_f), j = merge(start, split_j);
    CHECK(f.open_components() == j.open_components());  // same number of components so far...
    CHECK_FALSE(f == j);                                // ...but different topology
    const descriptor h = merge(f, end), l = merge(j, end);
    CHECK(h.finished());
    CHECK(l.finished());
    CHECK(h.enclosed() == 2);  // (h): two components and one hole
    CHECK(h.holes() == 1);
    CHECK(l.enclosed() == 1);  // (l): a single component without holes
    CHECK(l.holes() == 0);
    // The inset of §3.4: matching portal counts is not enough. Two parallel strands capped at both
    // ends by pieces that keep them apart give two components, not one.
    const descriptor open2({}, {0, 1}), bars({0, 1}, {0, 1}), close2({0, 1}, {});
    const descriptor r = merge(merge(open2, bars), close2);
    CHECK(r.finished());
    CHECK(r.enclosed() == 2);
    CHECK(r.holes() == 0);
    // A ring: one arch opening right, one closing it: one component, one hole.
    const descriptor ring = merge(descriptor({}, {0, 0}), descriptor({0, 0}, {}));
    CHECK(ring == descriptor({}, {}, 1, 1));
}

TEST_CASE("Fig. 6: closing a loop tells a ring from a merely connected pattern", "[topology]") {
    // Top: component 0 runs from the left end to the right end: closing makes a ring.
    const loop_closure top = close_loop(descriptor({0, 1}, {0, 2}));
    CHECK(top.winds());
    CHECK(top.rings == 1);
    CHECK(top.components == 2);
    CHECK(top.holes == 0);
    // Bottom: the diagonal strand (id 1) meets stubs on the other side of the seam: one component,
    // connected from start to end, but it does not go around: not closed.
    const loop_closure bottom = close_loop(descriptor({0, 1}, {1, 2}));
    CHECK_FALSE(bottom.winds());
    CHECK(bottom.components == 1);
    CHECK(bottom.holes == 0);
    // Two parallel rails: two rings, no hole inside the band.
    CHECK(close_loop(descriptor({0, 1}, {0, 1})) == loop_closure{2, 0, 2});
    // A ladder with one rung (both rails joined inside): one ring, and one hole between the rails.
    CHECK(close_loop(descriptor({0, 0}, {0, 0})) == loop_closure{1, 1, 1});
    // Rails crossing over: left 0 -> right 1 and left 1 -> right 0 glue into a single ring.
    CHECK(close_loop(descriptor({0, 1}, {1, 0})) == loop_closure{1, 0, 1});
    // Counters of the run carry over; an empty run closes into nothing.
    CHECK(close_loop(descriptor({}, {}, 3, 2)) == loop_closure{3, 2, 0});
}

TEST_CASE("merge and close_loop reject mismatched portal counts", "[topology]") {
    CHECK_THROWS_AS(merge(descriptor({}, {0, 1}), descriptor({0}, {})), fabsynth::invalid_input);
    CHECK_THROWS_AS(close_loop(descriptor({0}, {0, 0})), fabsynth::invalid_input);
    std::vector<std::uint32_t> huge(descriptor::max_portals + 1, 0);
    CHECK_THROWS_AS(descriptor(huge, {}), fabsynth::invalid_input);
}

TEST_CASE("merge is associative and agrees with the glue-graph oracle", "[topology]") {
    fabsynth::counter_rng rng(20141105);
    for (int trial = 0; trial < 400; ++trial) {
        const std::size_t len = 2 + rng.uniform_int(5);
        std::vector<std::size_t> sides(len + 1);
        for (auto& s : sides) s = rng.uniform_int(5);
        std::vector<descriptor> seq;
        for (std::size_t i = 0; i < len; ++i) seq.push_back(fabsynth_test::random_planar_piece(rng, sides[i], sides[i + 1]));
        // Left fold vs right fold vs a split in the middle.
        descriptor left_fold = seq[0];
        for (std::size_t i = 1; i < len; ++i) left_fold = merge(left_fold, seq[i]);
        descriptor right_fold = seq[len - 1];
        for (std::size_t i = len - 1; i-- > 0;) right_fold = merge(seq[i], right_fold);
        const std::size_t mid = 1 + rng.uniform_int(len - 1);
        descriptor a = seq[0], b = seq[mid];
        for (std::size_t i = 1; i < mid; ++i) a = merge(a, seq[i]);
        for (std::size_t i = mid + 1; i < len; ++i) b = merge(b, seq[i]);
        REQUIRE(left_fold == right_fold);
        REQUIRE(left_fold == merge(a, b));

        const auto o = fabsynth_test::oracle(seq, false);
        CHECK(left_fold.enclosed() + left_fold.open_components() == o.components);
        CHECK(left_fold.holes() == o.holes);
        CHECK(left_fold == descriptor(o.left_labels, o.right_labels, left_fold.enclosed(), left_fold.holes()));

        // Loops: same portal count at both ends. Closing is invariant under rotation of the run.
        if (sides.front() == sides.back()) {
            const loop_closure c = close_loop(left_fold);
            const auto ol = fabsynth_test::oracle(seq, true);
            CHECK(c.components == ol.components);
            CHECK(c.holes == ol.holes);
            CHECK(c.rings == ol.rings);
            CHECK(close_loop(merge(b, a)) == c);
        }
    }
}

TEST_CASE("descriptor_policy memoised states match direct merges", "[topology]") {
    fabsynth::counter_rng rng(77);
    std::vector<descriptor> pieces;
    std::vector<std::size_t> lc, rc;
    for (int i = 0; i < 8; ++i) {
        const std::size_t l = rng.uniform_int(4), r = rng.uniform_int(4);
        lc.push_back(l), rc.push_back(r);
        pieces.push_back(fabsynth_test::random_planar_piece(rng, l, r));
    }
    topo::descriptor_policy policy(pieces);
    for (int trial = 0; trial < 300; ++trial) {
        std::size_t p = rng.uniform_int(pieces.size());
        auto s = policy.start(p);
        REQUIRE(s);
        descriptor d = pieces[p];
        for (int step = 0; step < 12; ++step) {
            const std::size_t q = rng.uniform_int(pieces.size());
            const auto next = policy.extend(*s, q);
            if (lc[q] != d.right().size()) {
                CHECK_FALSE(next);
                continue;
            }
            REQUIRE(next);
            d = merge(d, pieces[q]);
            s = next;
            REQUIRE(policy.to_descriptor(*s) == d);
            if (d.left().size() == d.right().size()) CHECK(policy.close(*s) == close_loop(d));
            else CHECK_FALSE(policy.close(*s));
        }
    }
    CHECK(policy.num_shapes() < 2000);
    CHECK_THROWS_AS(policy.start(99), fabsynth::invalid_input);
}

TEST_CASE("constraints prune and accept as documented", "[topology]") {
    topo::descriptor_policy p({descriptor({}, {0}), descriptor({0}, {}), descriptor({}, {}, 1, 0)});
    const topo::constraints one{.components = 1, .holes = 0};
    const auto open = *p.start(0);
    const auto done = *p.extend(open, 1);
    CHECK(one.viable(p, open));
    CHECK_FALSE(one.accept_open(p, open));  // an open portal remains
    CHECK(one.accept_open(p, done));
    const auto two = *p.extend(done, 2);  // an island: a second component
    CHECK_FALSE(one.viable(p, two));
    CHECK_FALSE(one.viable(p, *p.extend(*p.start(2), 0)));  // island + open strand: >= 2 components
    CHECK(topo::constraints{.components = 2}.accept_open(p, two));
    CHECK_THROWS_AS((topo::constraints{.components = 0}.validate(p)), fabsynth::invalid_input);
    one.validate(p);
    // A policy that does not count holes cannot serve a hole constraint; for_constraints counts what is needed.
    topo::descriptor_policy no_holes({descriptor({}, {0, 0}), descriptor({0, 0}, {})}, {.components = true, .holes = false});
    CHECK_THROWS_AS(one.validate(no_holes), fabsynth::invalid_input);
    auto lean = topo::descriptor_policy::for_constraints({descriptor({}, {0, 0}), descriptor({0, 0}, {})},
                                                         topo::constraints{.components = 1});
    CHECK(lean.counts().components);
    CHECK_FALSE(lean.counts().holes);
    const auto ring = *lean.extend(*lean.start(0), 1);
    CHECK(ring.holes == 0);  // not counted
    CHECK(ring.enclosed == 1);
    CHECK(no_holes.extend(*no_holes.start(0), 1)->holes == 0);
    const topo::constraints ring_wanted{.components = 1, .closed_loop = true};
    CHECK(ring_wanted.accept_cycle(p, loop_closure{1, 0, 1}));
    CHECK_FALSE(ring_wanted.accept_cycle(p, loop_closure{1, 0, 0}));
}
