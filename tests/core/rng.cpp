#include <catch2/catch.hpp>

#include <fabsynth/core/rng.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

using namespace fabsynth;

TEST_CASE("mix64 matches the published SplitMix64 reference stream", "[core][rng]") {
    // SplitMix64 with state 0: the first outputs are mix64(k * golden_gamma), k = 1, 2, 3.
    // Reference values from Vigna's splitmix64.c seeded with 0 (also used by xoshiro's seeding).
    CHECK(mix64(1 * golden_gamma) == 0xe220a8397b1dcdafULL);
    CHECK(mix64(2 * golden_gamma) == 0x6e789e6aa1b965f4ULL);
    CHECK(mix64(3 * golden_gamma) == 0x06c45d188009454fULL);
}

TEST_CASE("hash RNG golden values are fixed forever", "[core][rng]") {
    // Changing these breaks every seeded result users have stored: never update them casually.
    CHECK(hash64(0) == 0xe220a8397b1dcdafULL);  // = mix64(golden_gamma)
    counter_rng r(42, 1, -2, 3);
    const std::uint64_t a = r.next_u64(), b = r.next_u64();
    counter_rng r2(42, 1, -2, 3);
    CHECK(r2.next_u64() == a);
    CHECK(r2.next_u64() == b);
    CHECK(hash64(42, 1, -2, 3) != hash64(42, 1, -2, 4));
    CHECK(hash64(42, 1, 2) != hash64(42, 2, 1));
    CHECK(hash64(1, 0) != hash64(1));
    static_assert(hash64(7, 1, 2, 3) == hash64(7, 1, 2, 3), "constexpr");
    // Pinned outputs (computed once by this implementation; they guard against accidental change).
    CHECK(hash64(1, 2, 3) == 0xb33e7ad2cc083d6fULL);
}

TEST_CASE("uniform draws are uniform in [0,1)", "[core][rng]") {
    counter_rng r(2024);
    const int n = 200000;
    std::vector<int> bins(20, 0);
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const double u = r.uniform();
        REQUIRE(u >= 0.0);
        REQUIRE(u < 1.0);
        sum += u;
        ++bins[static_cast<int>(u * 20)];
    }
    CHECK(sum / n == Approx(0.5).margin(0.005));
    double chi2 = 0;
    for (int c : bins) chi2 += (c - n / 20.0) * (c - n / 20.0) / (n / 20.0);
    CHECK(chi2 < 45.0);  // 19 dof: p ~ 1e-3
    counter_rng q(5);
    for (int i = 0; i < 1000; ++i) REQUIRE(q.uniform_int(7) < 7);
    double m = 0, s = 0;
    counter_rng g(9);
    for (int i = 0; i < n; ++i) {
        const double x = g.normal();
        m += x, s += x * x;
    }
    CHECK(m / n == Approx(0).margin(0.01));
    CHECK(s / n == Approx(1).margin(0.02));
}

TEST_CASE("mulhi64 equals the 128-bit product's high word", "[core][rng]") {
    counter_rng r(77);
    for (int i = 0; i < 10000; ++i) {
        const std::uint64_t a = r.next_u64(), b = r.next_u64();
        __extension__ using u128 = unsigned __int128;
        REQUIRE(mulhi64(a, b) == static_cast<std::uint64_t>((u128(a) * b) >> 64));
    }
    CHECK(mulhi64(~0ULL, ~0ULL) == ~0ULL - 1);
}
