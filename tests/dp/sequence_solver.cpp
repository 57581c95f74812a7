// Tests for dp/sequence_solver.hpp: optimality against brute-force enumeration on many random
// small instances (open and closed, with topology constraints, including impossible ones), the
// drift bound, the autocorrelation penalty, epsilon growth, the solver's phases and bad input.
// (The vector-pattern portal costs are tested in tests/vector_pattern/portal_cost.cpp.)
#include <catch2/catch.hpp>

#include <fabsynth/dp.hpp>
#include <fabsynth/topology.hpp>

#include "topology/random_planar.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

namespace dp = fabsynth::dp;
namespace topo = fabsynth::topology;
using topo::descriptor;

// The shipped policies satisfy the concepts; unrelated types do not.
static_assert(dp::transition_cost_policy<dp::transition_table>);
static_assert(dp::sequence_state_policy<topo::descriptor_policy>);
static_assert(dp::sequence_constraint_policy<topo::constraints, topo::descriptor_policy>);
static_assert(dp::sequence_state_policy<dp::stateless>);
static_assert(dp::sequence_constraint_policy<dp::unconstrained, dp::stateless>);
static_assert(dp::sequence_constraint_policy<dp::unconstrained, topo::descriptor_policy>);
static_assert(!dp::transition_cost_policy<std::vector<double>>);
static_assert(!dp::sequence_state_policy<topo::descriptor>);
static_assert(!dp::sequence_constraint_policy<topo::constraints, dp::stateless>);

namespace {

// ---- one random instance ---------------------------------------------------------------------
struct instance {
    std::vector<double> widths;
    std::vector<descriptor> pieces;
    dp::transition_table table;
    topo::constraints want;
    dp::sequence_options opt;
};

instance random_instance(fabsynth::counter_rng& rng, bool closed) {
    instance in;
    const std::size_t n = 2 + rng.uniform_int(4);  // 2..5 pieces
    std::vector<std::size_t> lc(n), rc(n);
    auto portals = [&] { return rng.uniform() < 0.3 ? std::size_t{0} : 1 + rng.uniform_int(2); };
    for (std::size_t i = 0; i < n; ++i) {
        lc[i] = portals(), rc[i] = portals();
        if (!closed && i == 0) lc[i] = 0;  // a natural left end
        const std::uint32_t extra = rng.uniform() < 0.2 ? 1 : 0;  // sometimes an island or a hole inside
        in.pieces.push_back(fabsynth_test::random_planar_piece(rng, lc[i], rc[i], extra, extra));
        in.widths.push_back(static_cast<double>(1 + rng.uniform_int(3)));
    }
    in.table = dp::transition_table(n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (rc[i] == lc[j] && rng.uniform() < 0.9)
                // Multiples of 1/64: every sum is exact, so DP and brute force agree to the last bit.
                in.table.set(i, j, static_cast<double>(rng.uniform_int(64)) / 64.0, static_cast<double>(rng.uniform_int(5)) - 2.0);
    const std::uint64_t c = rng.uniform_int(3), h = rng.uniform_int(3);
    if (c) in.want.components = static_cast<std::uint32_t>(c);
    if (h) in.want.holes = static_cast<std::uint32_t>(h - 1);
    in.want.closed_loop = closed && rng.uniform() < 0.4;
    in.opt.target_length = static_cast<double>(3 + rng.uniform_int(8));
    in.opt.epsilon = rng.uniform() < 0.5 ? 0.5 : 1.0;
    in.opt.epsilon_max = in.opt.epsilon + static_cast<double>(rng.uniform_int(3));
    in.opt.epsilon_growth = 1.5;
    in.opt.length_resolution = 1.0;
    in.opt.closed = closed;
    if (!closed && rng.uniform() < 0.3) in.opt.first_pieces = {0};
    if (!closed && rng.uniform() < 0.3) in.opt.last_pieces = {n - 1, 0};
    return in;
}

// ---- brute force: every sequence up to the length bound, evaluated by the glue-graph oracle ----
struct brute_result {
    bool found = false;
    double cost = 0, length = 0, epsilon = 0;
    std::size_t nodes = 0;
};

bool contains(const std::vector<std::size_t>& v, std::size_t x) { return std::find(v.begin(), v.end(), x) != v.end(); }

// Drift: every prefix's accumulated offset stays in (-H/2, H/2) (checked only if H is finite).
brute_result brute_force(const instance& in, std::size_t node_limit) {
    const auto& o = in.opt;
    const double l_max = o.target_length + o.epsilon_max;
    const std::size_t n = in.widths.size();
    struct cand {
        double distance, cost;
    };
    std::vector<cand> cands;
    brute_result r;
    std::vector<std::size_t> seq;
    std::function<void(double, double, double)> dfs = [&](double length, double cost, double drift) {
        if (++r.nodes > node_limit) return;
        const double distance = std::abs(length - o.target_length);
        std::vector<descriptor> ds;
        for (std::size_t p : seq) ds.push_back(in.pieces[p]);
        if (distance <= o.epsilon_max) {
            if (!o.closed) {
                const auto t = fabsynth_test::oracle(ds, false);
                const bool finished = ds.front().left().empty() && ds.back().right().empty();
                if (finished && (o.last_pieces.empty() || contains(o.last_pieces, seq.back())) &&
                    (!in.want.components || t.components == *in.want.components) &&
                    (!in.want.holes || t.holes == *in.want.holes))
                    cands.push_back({distance, cost});
            } else if (in.table.compatible(seq.back(), seq.front()) &&
                       ds.front().left().size() == ds.back().right().size()) {
                const auto t = fabsynth_test::oracle(ds, true);
                if ((!in.want.components || t.components == *in.want.components) &&
                    (!in.want.holes || t.holes == *in.want.holes) && (!in.want.closed_loop || t.rings > 0))
                    cands.push_back({distance, cost + in.table.cost(seq.back(), seq.front())});
            }
        }
        for (std::size_t j = 0; j < n; ++j) {
            if (!in.table.compatible(seq.back(), j) || length + in.widths[j] > l_max) continue;
            const double d = drift + in.table.offset(seq.back(), j);
            if (!(std::abs(d) < o.offset_range / 2)) continue;
            seq.push_back(j);
            dfs(length + in.widths[j], cost + in.table.cost(seq[seq.size() - 2], j), d);
            seq.pop_back();
        }
    };
    for (std::size_t s = 0; s < n; ++s) {
        if (!o.closed && !o.first_pieces.empty() && !contains(o.first_pieces, s)) continue;
        if (in.widths[s] > l_max) continue;
        seq = {s};
        dfs(in.widths[s], 0.0, 0.0);
    }
    if (cands.empty()) return r;
    double d_min = std::numeric_limits<double>::infinity();
    for (const auto& c : cands) d_min = std::min(d_min, c.distance);
    double eps = o.epsilon;
    while (eps < d_min && eps < o.epsilon_max) eps = std::min(eps * o.epsilon_growth, o.epsilon_max);
    r.found = true;
    r.cost = std::numeric_limits<double>::infinity();
    for (const auto& c : cands)
        if (c.distance <= eps) r.cost = std::min(r.cost, c.cost);
    r.epsilon = eps;
    return r;
}

// Independent re-evaluation of a returned sequence.
void check_valid(const instance& in, const std::vector<std::size_t>& seq, double cost, double length) {
    REQUIRE(!seq.empty());
    double c = 0, l = in.widths[seq[0]];
    for (std::size_t i = 1; i < seq.size(); ++i) {
        REQUIRE(in.table.compatible(seq[i - 1], seq[i]));
        c += in.table.cost(seq[i - 1], seq[i]);
        l += in.widths[seq[i]];
    }
    std::vector<descriptor> ds;
    for (std::size_t p : seq) ds.push_back(in.pieces[p]);
    if (in.opt.closed) {
        REQUIRE(in.table.compatible(seq.back(), seq.front()));
        c += in.table.cost(seq.back(), seq.front());
        const auto t = fabsynth_test::oracle(ds, true);
        if (in.want.components) CHECK(t.components == *in.want.components);
        if (in.want.holes) CHECK(t.holes == *in.want.holes);
        if (in.want.closed_loop) CHECK(t.rings > 0);
    } else {
        CHECK(ds.front().left().empty());
        CHECK(ds.back().right().empty());
        const auto t = fabsynth_test::oracle(ds, false);
        if (in.want.components) CHECK(t.components == *in.want.components);
        if (in.want.holes) CHECK(t.holes == *in.want.holes);
        if (!in.opt.first_pieces.empty()) CHECK(contains(in.opt.first_pieces, seq.front()));
        if (!in.opt.last_pieces.empty()) CHECK(contains(in.opt.last_pieces, seq.back()));
    }
    CHECK(c == cost);
    CHECK(l == length);
    CHECK(std::abs(l - in.opt.target_length) <= in.opt.epsilon_max);
}

void run_random_instances(bool closed, std::uint64_t seed, int count) {
    fabsynth::counter_rng rng(seed);
    int solved = 0, impossible = 0, skipped = 0;
    for (int trial = 0; trial < count; ++trial) {
        const instance in = random_instance(rng, closed);
        const brute_result bf = brute_force(in, 200000);
        if (bf.nodes > 200000) {
            ++skipped;
            continue;
        }
        topo::descriptor_policy policy(in.pieces);
        INFO("trial " << trial << " n=" << in.widths.size() << " L=" << in.opt.target_length);
        if (!bf.found) {
            CHECK_THROWS_AS(dp::solve_sequence(in.widths, in.table, policy, in.want, in.opt), fabsynth::no_solution);
            ++impossible;
            continue;
        }
        const auto r = dp::solve_sequence(in.widths, in.table, policy, in.want, in.opt);
        CHECK(r.cost == bf.cost);  // exact: costs are dyadic
        // Counting only the constrained counters shrinks the table but not the optimum.
        auto lean = topo::descriptor_policy::for_constraints(in.pieces, in.want);
        const auto rl = dp::solve_sequence(in.widths, in.table, lean, in.want, in.opt);
        CHECK(rl.cost == bf.cost);
        CHECK(rl.stats.entries <= r.stats.entries);
        CHECK(r.epsilon == bf.epsilon);
        CHECK(r.penalty == 0.0);
        check_valid(in, r.pieces, r.cost, r.length);
        CHECK(std::abs(r.length - in.opt.target_length) <= r.epsilon);
        if (closed) {
            REQUIRE(r.cycle);
            if (in.want.closed_loop) CHECK(r.cycle->winds());
        }
        ++solved;
    }
    CHECK(skipped < count / 10);
    CHECK(solved > count / 10);  // both outcomes are exercised
    CHECK(impossible > count / 10);
}

}  // namespace

TEST_CASE("DP cost equals brute force on random open instances", "[dp]") {
    run_random_instances(false, 1234, 1500);
}

TEST_CASE("DP cost equals brute force on random closed-curve instances", "[dp]") {
    run_random_instances(true, 4321, 1000);
}

TEST_CASE("stateless DP equals brute force for plain sequence assembly", "[dp]") {
    fabsynth::counter_rng rng(99);
    for (int trial = 0; trial < 200; ++trial) {
        instance in = random_instance(rng, false);
        // No topology: every piece is an empty descriptor, so any compatible run is valid.
        for (auto& d : in.pieces) d = descriptor();
        in.want = {};
        const brute_result bf = brute_force(in, 200000);
        if (bf.nodes > 200000) continue;
        if (!bf.found) {
            CHECK_THROWS_AS(dp::solve_sequence(std::span<const double>(in.widths), in.table, in.opt), fabsynth::no_solution);
            continue;
        }
        const auto r = dp::solve_sequence(std::span<const double>(in.widths), in.table, in.opt);
        CHECK(r.cost == bf.cost);
        check_valid(in, r.pieces, r.cost, r.length);
    }
}

TEST_CASE("the offset drift bound is honoured and never beats brute force", "[dp]") {
    fabsynth::counter_rng rng(555);
    int both = 0;
    for (int trial = 0; trial < 1000; ++trial) {
        instance in = random_instance(rng, false);
        in.opt.offset_range = 1.0 + static_cast<double>(rng.uniform_int(6));  // offsets are integers in [-2, 2]
        const brute_result bf = brute_force(in, 200000);
        if (bf.nodes > 200000) continue;
        topo::descriptor_policy policy(in.pieces);
        std::optional<dp::sequence_result<topo::descriptor_policy::state, topo::loop_closure>> r;
        try {
            r = dp::solve_sequence(in.widths, in.table, policy, in.want, in.opt);
        } catch (const fabsynth::no_solution&) {
        }
        if (!r) continue;  // the drift bound is a heuristic: the DP may miss a valid sequence
        REQUIRE(bf.found);  // but whatever it returns is valid, so brute force finds one too
        check_valid(in, r->pieces, r->cost, r->length);
        CHECK(r->cost >= bf.cost);
        REQUIRE(r->offsets.size() == r->pieces.size());
        double drift = 0;
        for (std::size_t i = 0; i < r->pieces.size(); ++i) {
            if (i) drift += in.table.offset(r->pieces[i - 1], r->pieces[i]);
            CHECK(r->offsets[i] == drift);
            CHECK(std::abs(drift) < in.opt.offset_range / 2);
        }
        ++both;
    }
    CHECK(both > 30);
}

TEST_CASE("the autocorrelation penalty breaks up a cheap periodic cycle", "[dp]") {
    // Eight interchangeable pieces; 0 -> 1 -> 0 costs nothing, everything else 0.3.
    const std::size_t n = 8;
    std::vector<double> widths(n, 1.0);
    dp::transition_table t(n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) t.set(i, j, (i + j == 1) ? 0.0 : 0.3);
    auto autocorrelation = [](const std::vector<std::size_t>& s, std::size_t window, double sigma) {
        double a = 0;
        for (std::size_t lag = 1; lag <= window && lag < s.size(); ++lag) {
            double sum = 0;
            for (std::size_t i = 0; i + lag < s.size(); ++i)
                sum += std::exp(-std::abs(static_cast<double>(s[i]) - static_cast<double>(s[i + lag])) / sigma);
            a = std::max(a, sum);
        }
        return a;
    };
    dp::sequence_options opt{.target_length = 30, .epsilon = 0.5, .epsilon_max = 0.5, .length_resolution = 1};
    const auto plain = dp::solve_sequence(std::span<const double>(widths), t, opt);
    CHECK(plain.cost == 0.0);
    opt.autocorrelation_weight = 1.0;
    opt.autocorrelation_window = 8;
    const auto varied = dp::solve_sequence(std::span<const double>(widths), t, opt);
    const double a_plain = autocorrelation(plain.pieces, 8, 0.5), a_varied = autocorrelation(varied.pieces, 8, 0.5);
    CHECK(a_varied < 0.8 * a_plain);
    CHECK(varied.cost > 0.0);
    CHECK(varied.penalty == Approx(a_varied).epsilon(1e-5));
    CHECK(varied.length == 30.0);
    // The penalised objective is no worse than keeping the periodic answer.
    CHECK(varied.cost + varied.penalty <= plain.cost + a_plain + 1e-9);
}

TEST_CASE("epsilon grows only up to epsilon_max", "[dp]") {
    std::vector<double> widths{10.0};
    dp::transition_table t(1);
    t.set(0, 0, 1.0);
    dp::sequence_options opt{.target_length = 35, .epsilon = 1, .epsilon_growth = 2, .epsilon_max = 10};
    const auto r = dp::solve_sequence(std::span<const double>(widths), t, opt);
    CHECK(r.epsilon == 8.0);  // 1, 2, 4, 8 >= |30 - 35|
    CHECK(r.length == 30.0);  // 30 and 40 are equally far; 30 is cheaper
    opt.epsilon_max = 4;
    CHECK_THROWS_AS(dp::solve_sequence(std::span<const double>(widths), t, opt), fabsynth::no_solution);

    // One piece that cannot repeat: the only pattern is 10 mm long for a 100 mm curve. Refused.
    dp::transition_table lone(1);
    CHECK_THROWS_AS(dp::solve_sequence(std::span<const double>(widths), lone, {.target_length = 100}),
                    fabsynth::no_solution);
    // A curve shorter than every piece.
    CHECK_THROWS_AS(dp::solve_sequence(std::span<const double>(widths), t, {.target_length = 3}), fabsynth::no_solution);
}

TEST_CASE("closed curves: rings, contradictory targets and loops that cannot close", "[dp]") {
    // Piece 0: a straight bar; piece 1: an arch opening left + an arch opening right (never a ring).
    std::vector<descriptor> pieces{descriptor({0}, {0}), descriptor({0, 0}, {1, 1})};
    std::vector<double> widths{1.0, 1.0};
    dp::transition_table t(2);
    t.set(0, 0, 0.5);
    t.set(1, 1, 0.25);
    topo::descriptor_policy policy(pieces);
    dp::sequence_options opt{.target_length = 6, .epsilon = 0.5, .epsilon_max = 0.5, .closed = true, .length_resolution = 1};
    const auto ring = dp::solve_sequence(widths, t, policy, topo::constraints{.components = 1, .closed_loop = true}, opt);
    CHECK(ring.pieces == std::vector<std::size_t>(6, 0));
    CHECK(ring.cost == 3.0);  // six transitions including the closing one
    REQUIRE(ring.cycle);
    CHECK(ring.cycle->winds());
    CHECK(ring.cycle->holes == 0);
    // Beads (arch pairs make little rings): six beads, each with a hole, none going around.
    const auto beads = dp::solve_sequence(widths, t, policy, topo::constraints{.components = 6}, opt);
    CHECK(beads.pieces == std::vector<std::size_t>(6, 1));
    CHECK(beads.cycle->components == 6);
    CHECK(beads.cycle->holes == 6);
    CHECK_FALSE(beads.cycle->winds());
    // Contradictory: 6 components and a closed loop.
    CHECK_THROWS_AS(dp::solve_sequence(widths, t, policy, topo::constraints{.components = 6, .closed_loop = true}, opt),
                    fabsynth::no_solution);
    // Open curves cannot use these pieces at all (open portals at both ends).
    opt.closed = false;
    CHECK_THROWS_AS(dp::solve_sequence(widths, t, policy, topo::constraints{}, opt), fabsynth::no_solution);
}

TEST_CASE("bad input is refused with invalid_input", "[dp]") {
    std::vector<double> w{1.0, 2.0};
    dp::transition_table t(2);
    t.set(0, 1, 1.0);
    t.set(1, 0, 1.0);
    auto solve = [&](std::vector<double> widths, dp::sequence_options o) {
        return dp::solve_sequence(std::span<const double>(widths), t, o);
    };
    using fabsynth::invalid_input;
    const double nan = std::nan("");
    CHECK_THROWS_AS(solve({1.0, nan}, {.target_length = 10}), invalid_input);
    CHECK_THROWS_AS(solve({1.0, 0.0}, {.target_length = 10}), invalid_input);
    CHECK_THROWS_AS(solve({1.0}, {.target_length = 10}), invalid_input);  // table has 2 pieces
    CHECK_THROWS_AS(solve({}, {.target_length = 10}), invalid_input);
    CHECK_THROWS_AS(solve(w, {.target_length = nan}), invalid_input);
    CHECK_THROWS_AS(solve(w, {.target_length = -3}), invalid_input);
    CHECK_THROWS_AS(solve(w, {.target_length = 10, .epsilon = 2, .epsilon_max = 1}), invalid_input);
    CHECK_THROWS_AS(solve(w, {.target_length = 10, .epsilon_growth = 1.0}), invalid_input);
    CHECK_THROWS_AS(solve(w, {.target_length = 10, .offset_range = 0}), invalid_input);
    CHECK_THROWS_AS(solve(w, {.target_length = 10, .offset_range = nan}), invalid_input);
    CHECK_THROWS_AS(solve(w, {.target_length = 10, .autocorrelation_weight = -1}), invalid_input);
    CHECK_THROWS_AS(solve(w, {.target_length = 10, .length_resolution = 1.5}), invalid_input);
    CHECK_THROWS_AS(solve(w, {.target_length = 10, .first_pieces = {2}}), invalid_input);
    CHECK_THROWS_AS(solve(w, {.target_length = 10, .closed = true, .first_pieces = {0}}), invalid_input);
    CHECK_THROWS_AS(t.set(0, 0, nan), invalid_input);
    CHECK_THROWS_AS(t.set(0, 0, -1.0), invalid_input);
    CHECK_THROWS_AS(t.set(0, 5, 1.0), invalid_input);
    // Table size limit: refused quickly instead of allocating without bound.
    CHECK_THROWS_AS(solve(w, {.target_length = 1e6, .max_entries = 1000}), invalid_input);
    // Components = 0 cannot be met by any pattern.
    topo::descriptor_policy p({descriptor(), descriptor()});
    CHECK_THROWS_AS(dp::solve_sequence(w, t, p, topo::constraints{.components = 0}, {.target_length = 10}), invalid_input);
}

TEST_CASE("the progress callback is called and can cancel", "[dp]") {
    std::vector<double> widths{1.0, 2.0};
    dp::transition_table t(2);
    for (std::size_t i = 0; i < 2; ++i)
        for (std::size_t j = 0; j < 2; ++j) t.set(i, j, 1.0);
    dp::stateless st;
    int calls = 0;
    double last = -1;
    bool monotone = true;
    const auto r = dp::solve_sequence(std::span<const double>(widths), t, st, dp::unconstrained{}, {.target_length = 50},
                                      [&](double f, std::string_view) {
                                          monotone = monotone && f >= last && f <= 1.0;
                                          last = f;
                                          ++calls;
                                      });
    CHECK(calls > 10);
    CHECK(monotone);
    CHECK(std::abs(r.length - 50) <= 2.5);
    CHECK_THROWS_AS(dp::solve_sequence(std::span<const double>(widths), t, st, dp::unconstrained{},
                                       {.target_length = 50}, [](double f, std::string_view) { return f < 0.5; }),
                    fabsynth::cancelled);
}

TEST_CASE("a mid-size topology instance: valid, deterministic, statistics filled", "[dp]") {
    fabsynth::counter_rng rng(31337);
    const std::size_t n = 12;
    std::vector<std::size_t> lc(n), rc(n);
    instance in;
    for (std::size_t i = 0; i < n; ++i) {
        lc[i] = i == 0 ? 0 : 1 + rng.uniform_int(3);
        rc[i] = i == n - 1 ? 0 : 1 + rng.uniform_int(3);
        in.pieces.push_back(fabsynth_test::random_planar_piece(rng, lc[i], rc[i], 0, i % 4 == 0 ? 1 : 0));
        in.widths.push_back(2.0 + static_cast<double>(rng.uniform_int(5)));
    }
    in.table = dp::transition_table(n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (rc[i] == lc[j]) in.table.set(i, j, rng.uniform(), rng.uniform(-1, 1));
    in.want = {.components = 1};
    in.opt = {.target_length = 120, .offset_range = 6, .first_pieces = {0}, .last_pieces = {n - 1}};
    topo::descriptor_policy p1(in.pieces), p2(in.pieces);
    const auto a = dp::solve_sequence(in.widths, in.table, p1, in.want, in.opt);
    const auto b = dp::solve_sequence(in.widths, in.table, p2, in.want, in.opt);
    CHECK(a.pieces == b.pieces);
    CHECK(a.cost == b.cost);
    in.opt.epsilon_max = 0.2 * 120;
    check_valid(in, a.pieces, a.cost, a.length);
    CHECK(a.pieces.front() == 0);
    CHECK(a.pieces.back() == n - 1);
    CHECK(a.stats.entries > 0);
    CHECK(a.stats.candidates > 0);
    CHECK(a.stats.peak_bytes > a.stats.entries * 40);
    const descriptor final_d = p1.to_descriptor(a.state);
    CHECK(final_d.finished());
    CHECK(final_d.enclosed() == 1);
}

TEST_CASE("solver phases: defaults, epsilon growth and the choice among candidates", "[dp]") {
    // check_inputs resolves the defaults: epsilon 0.05 L, epsilon_max 0.2 L, q = shortest width.
    dp::transition_table t(2);
    t.set(0, 1, 1.0);
    const std::vector<double> w{3.0, 2.0};
    const auto lim = dp::detail::check_inputs(std::span<const double>(w), t, {.target_length = 100});
    CHECK(lim.pieces == 2);
    CHECK(lim.epsilon == Approx(5.0));
    CHECK(lim.epsilon_max == Approx(20.0));
    CHECK(lim.resolution == 2.0);
    CHECK(lim.longest == Approx(120.0));
    CHECK(lim.window == 0);
    const auto succ = dp::detail::successor_lists(t, 2);
    REQUIRE(succ[0].size() == 1);
    CHECK(succ[0][0].piece == 1);
    CHECK(succ[1].empty());

    struct cand {
        double distance, total;
    };
    const std::vector<cand> c{{3.0, 1.0}, {1.2, 5.0}, {1.0, 7.0}};
    // 0.5 grows by 1.25 until it admits the nearest candidate (distance 1.0): ... 0.9765625, 1.220703125.
    const double eps = dp::detail::grown_epsilon(c, 0.5, 10.0, 1.25);
    CHECK(eps == Approx(1.220703125));
    const cand* best = dp::detail::cheapest_within(c, eps);
    REQUIRE(best != nullptr);
    CHECK(best->total == 5.0);  // the two within eps: the cheaper one
    CHECK(dp::detail::grown_epsilon(c, 0.5, 0.8, 1.25) == 0.8);  // never beyond epsilon_max
    CHECK(dp::detail::cheapest_within(c, 0.8) == nullptr);
}
