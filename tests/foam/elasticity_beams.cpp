// Inverse elasticity mapping (with a made-up monotone polynomial) and beam network export.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>

#include "fabsynth/foam/beams.hpp"
#include "fabsynth/foam/elasticity.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;

TEST_CASE("inverse elasticity solves P(rho, tau_min) = E", "[foam][elasticity]") {
    // made-up degree-2 table: P = 0.001 + 0.01 rho + 0.02 tau + 0.0005 rho^2 + 0.03 rho tau (increasing in rho)
    elasticity_polynomial P{2, {0.001, 0.01, 0.02, 0.0005, 0.03, 0.0}};
    P.validate();
    CHECK(P(2.0, 0.25) == Approx(0.001 + 0.02 + 0.005 + 0.002 + 0.015));
    const double tau = 0.25, rho_max = 1.0 / std::pow(0.5, 3);
    for (double rho : {0.05, 0.5, 2.0, 7.9}) {
        const double e = P(rho, tau);
        const foam_parameters fp = inverse_elasticity(P, e, tau);
        CHECK(fp.radius == tau);
        CHECK(fp.density == Approx(rho).epsilon(1e-10));
        CHECK(fp.density <= rho_max);
    }
    // out of range: clamp to the bounds or throw
    CHECK(inverse_elasticity(P, 100.0, tau).density == Approx(rho_max));
    CHECK(inverse_elasticity(P, -1.0, tau).density == 0.0);
    CHECK_THROWS_AS(inverse_elasticity(P, 100.0, tau, 0, out_of_range::throw_no_solution), no_solution);
    CHECK_THROWS_AS(inverse_elasticity(P, NAN, tau), invalid_input);
    CHECK_THROWS_AS(inverse_elasticity(P, 0.01, 0.0), invalid_input);
    elasticity_polynomial bad{4, {1, 2, 3}};
    CHECK_THROWS_AS(bad.validate(), invalid_input);
    // the shipped fit (elasticity_fit.hpp; more in elasticity_fit.cpp) is invertible at tau_min
    const auto [lo, hi] = fitted_density_range(fitted::tau_min);
    const double rho = 0.5 * (lo + hi);
    const foam_parameters fp = inverse_fitted_elasticity(fitted_elasticity()(rho, fitted::tau_min), fitted::tau_min);
    CHECK(fp.density == Approx(rho).epsilon(1e-8));
}

TEST_CASE("beam network: nodes of degree <= 4 inside, edges on Voronoi edges", "[foam][beams]") {
    const voronoi_foam f(constant_field{0.4}, constant_field{0.2}, {.cell = 2, .seed = 8});
    const box3 b({0, 0, 0}, {9, 9, 9});  // spans 2 x 2 x 2 chunks
    const beam_network net = extract_beams(f, b);
    REQUIRE(net.edges.size() == net.radii.size());
    REQUIRE(net.edges.size() > 100);
    std::vector<int> degree(net.nodes.size(), 0);
    for (const auto& e : net.edges) ++degree[e[0]], ++degree[e[1]];
    std::map<int, int> hist;
    const box3 inner = b.inflated(-1e-6);
    for (std::size_t i = 0; i < net.nodes.size(); ++i) {
        const vec3 p = net.nodes[i];
        // chunks of 4 cells: 9 mm splits into two 4.5 mm chunks; edges crossing x/y/z = 4.5 get a node there
        const bool on_chunk_face = std::abs(p.x - 4.5) < 1e-6 || std::abs(p.y - 4.5) < 1e-6 || std::abs(p.z - 4.5) < 1e-6;
        if (inner.contains(p) && !on_chunk_face) ++hist[degree[i]];
    }
    // interior nodes are Voronoi vertices: in general position exactly 4 edges meet
    CHECK(hist.size() == 1);
    CHECK(hist.begin()->first == 4);
    // every edge midpoint is on the foam's beam axis: distance to the edges is 0
    for (std::size_t e = 0; e < net.edges.size(); e += 17) {
        const vec3 m = 0.5 * (net.nodes[net.edges[e][0]] + net.nodes[net.edges[e][1]]);
        CHECK(f.distance_to_edges(m, 0.2) < 1e-9);
        CHECK(net.radii[e] == 0.2);
    }
}
