// Tests for vector_pattern/pieces.hpp and vector_pattern/reeb_slicing.hpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/io/svg.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"
#include "fabsynth/vector_pattern/pieces.hpp"
#include "fabsynth/vector_pattern/reeb_slicing.hpp"
#include "fabsynth/topology/descriptor.hpp"
#include "support/vector_band.hpp"

using namespace fabsynth;
using vector_pattern::exemplar;

namespace {

// Cuts off the uniform positions by an irrational-ish fraction, so they miss grid-aligned edges.
std::vector<double> offset_cuts(const exemplar& ex, int t) {
    std::vector<double> c;
    for (int k = 1; k <= t; ++k) c.push_back(ex.bounds.lo.x + ex.width() * (k + 0.1234567) / (t + 1));
    return c;
}

// Oracle: solid intervals of the line x = c, from the crossings of every ring edge with the line and
// a point-in-polygon test at the middle of each gap between consecutive crossings.
std::vector<std::pair<double, double>> solid_intervals(const exemplar& ex, double c) {
    std::vector<double> ys;
    for (const auto& p : ex.polygons)
        for (const ring2* r : [&] {
                 std::vector<const ring2*> v{&p.outer};
                 for (const auto& h : p.holes) v.push_back(&h);
                 return v;
             }())
            for (std::size_t i = 0; i < r->size(); ++i) {
                const vec2 a = (*r)[i], b = (*r)[(i + 1) % r->size()];
                if ((a.x - c) * (b.x - c) < 0.0) ys.push_back(a.y + (b.y - a.y) * (c - a.x) / (b.x - a.x));
            }
    std::sort(ys.begin(), ys.end());
    std::vector<std::pair<double, double>> out;
    for (std::size_t i = 0; i + 1 < ys.size(); ++i) {
        const vec2 mid(c, 0.5 * (ys[i] + ys[i + 1]));
        bool solid = false;
        for (const auto& p : ex.polygons) solid = solid || point_in_polygon(p, mid);
        if (!solid) continue;
        if (!out.empty() && out.back().second == ys[i]) out.back().second = ys[i + 1];
        else out.emplace_back(ys[i], ys[i + 1]);
    }
    return out;
}

// Oracle for piece topology: rasterize the piece (pixel centres, even-odd scanlines), then flood
// fill: solid components with 4-connectivity, empty components with 8-connectivity that do not
// reach the raster border are holes. Returns {components, holes}.
std::pair<int, int> raster_topology(const std::vector<polygon_with_holes>& polys, double pixel) {
    const box2 b = bounding_box(polys);
    const int nx = static_cast<int>(std::ceil(b.size().x / pixel)) + 4, ny = static_cast<int>(std::ceil(b.size().y / pixel)) + 4;
    const vec2 o = b.lo - vec2(2 * pixel);
    std::vector<std::uint8_t> img(static_cast<std::size_t>(nx * ny), 0);
    // Even-odd scanlines through the pixel centres of each row (pixel centre inside = solid).
    std::vector<double> xs;
    for (int j = 0; j < ny; ++j) {
        const double y = o.y + (j + 0.5) * pixel;
        xs.clear();
        for (const auto& poly : polys)
            for (const ring2* r : [&] {
                     std::vector<const ring2*> v{&poly.outer};
                     for (const auto& h : poly.holes) v.push_back(&h);
                     return v;
                 }())
                for (std::size_t i = 0; i < r->size(); ++i) {
                    const vec2 a = (*r)[i], b = (*r)[(i + 1) % r->size()];
                    if ((a.y > y) != (b.y > y)) xs.push_back(a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y));
                }
        std::sort(xs.begin(), xs.end());
        for (std::size_t k = 0; k + 1 < xs.size(); k += 2)
            for (int i = 0; i < nx; ++i) {
                const double x = o.x + (i + 0.5) * pixel;
                if (x >= xs[k] && x < xs[k + 1]) img[static_cast<std::size_t>(j * nx + i)] = 1;
            }
    }
    std::vector<int> label(img.size(), -1);
    auto fill = [&](int s, std::uint8_t v, bool eight) {
        bool border = false;
        std::vector<int> stack{s};
        label[static_cast<std::size_t>(s)] = 1;
        while (!stack.empty()) {
            const int k = stack.back();
            stack.pop_back();
            const int x = k % nx, y = k / nx;
            if (x == 0 || y == 0 || x == nx - 1 || y == ny - 1) border = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    if ((dx == 0 && dy == 0) || (!eight && dx != 0 && dy != 0)) continue;
                    const int X = x + dx, Y = y + dy;
                    if (X < 0 || Y < 0 || X >= nx || Y >= ny) continue;
                    const int q = Y * nx + X;
                    if (img[static_cast<std::size_t>(q)] != v || label[static_cast<std::size_t>(q)] >= 0) continue;
                    label[static_cast<std::size_t>(q)] = 1;
                    stack.push_back(q);
                }
        }
        return border;
    };
    int comps = 0, holes = 0;
    for (int k = 0; k < nx * ny; ++k) {
        if (label[static_cast<std::size_t>(k)] >= 0) continue;
        if (img[static_cast<std::size_t>(k)]) fill(k, 1, false), ++comps;
        else if (!fill(k, 0, true)) ++holes;
    }
    return {comps, holes};
}

}  // namespace

TEST_CASE("slicing conserves the exemplar and finds the portals on every cut", "[pattern][pieces]") {
    for (const char* f : test::bundled_vector_files) {
        INFO(f);
        const exemplar ex = test::load_vector_exemplar(f);
        const auto cuts = offset_cuts(ex, 7);
        const auto pieces = vector_pattern::slice(ex, cuts);
        REQUIRE(pieces.size() == 8);
        // Area conservation and union == exemplar (symmetric difference ~ 0).
        double sum = 0.0;
        std::vector<polygon_with_holes> all;
        for (const auto& p : pieces) {
            sum += area(p.polygons);
            all.insert(all.end(), p.polygons.begin(), p.polygons.end());
            for (const auto& poly : p.polygons)
                for (const vec2& v : poly.outer) CHECK((v.x >= p.x0 && v.x <= p.x1));
        }
        CHECK(std::abs(sum - ex.area()) <= 1e-9 * ex.area());
        for (auto& p : all) orient(p);
        const auto u = polygon_boolean(clip_op::union_, to_rings(all), fill_rule::nonzero, {}, fill_rule::nonzero,
                                       std::nullopt, false);
        CHECK(std::abs(area(u) - ex.area()) <= 1e-9 * ex.area());
        CHECK(area(polygon_xor(u, ex.polygons)) <= 1e-9 * ex.area());
        CHECK(u.size() == ex.components());
        // Portals: counts and endpoint heights against the line/ring intersection oracle.
        for (std::size_t i = 0; i < cuts.size(); ++i) {
            INFO("cut " << i << " at x = " << cuts[i]);
            const auto iv = solid_intervals(ex, pieces[i].x1);
            const auto& r = pieces[i].right;
            const auto& l = pieces[i + 1].left;
            REQUIRE(r.size() == iv.size());
            REQUIRE(l.size() == iv.size());
            for (std::size_t k = 0; k < iv.size(); ++k) {
                CHECK(r[k].top == Approx(iv[k].first).margin(1e-9));
                CHECK(r[k].bottom == Approx(iv[k].second).margin(1e-9));
                CHECK(l[k].top == r[k].top);
                CHECK(l[k].bottom == r[k].bottom);
                // Outline is straight across the cut here (cuts avoid vertices): tangents agree.
                CHECK(glm::dot(l[k].tangent_top, r[k].tangent_top) == Approx(1.0).margin(1e-6));
                CHECK(glm::dot(l[k].tangent_bottom, r[k].tangent_bottom) == Approx(1.0).margin(1e-6));
                CHECK(r[k].tangent_top.x >= 0.0);
            }
            CHECK(pieces[i].heights(vector_pattern::piece_side::right).size() == 2 * iv.size());
        }
        // Descriptors: gluing all pieces gives back the exemplar's topology (components still
        // touching the band's two open ends count once each).
        topology::descriptor d = pieces[0].descriptor();
        for (std::size_t i = 1; i < pieces.size(); ++i) d = merge(d, pieces[i].descriptor());
        CHECK(d.enclosed() + d.open_components() == ex.components());
        CHECK(d.holes() == ex.holes());
    }
}

TEST_CASE("piece topology matches a raster flood-fill count", "[pattern][pieces]") {
    for (const char* f : {"greek_key.svg", "zigzag.svg", "hearts.svg", "pearls.svg"}) {
        INFO(f);
        const exemplar ex = test::load_vector_exemplar(f);
        const auto pieces = vector_pattern::slice(ex, offset_cuts(ex, 5));
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            INFO("piece " << i);
            const auto [c, h] = raster_topology(pieces[i].polygons, 0.25);
            CHECK(static_cast<std::size_t>(c) == pieces[i].components());
            CHECK(static_cast<std::uint32_t>(h) == pieces[i].holes());
            // enclosed: components without a portal, checked against polygons not touching the sides.
            std::uint32_t enclosed = 0;
            for (const auto& p : pieces[i].polygons) {
                const box2 b = bounding_box(p.outer);
                enclosed += (b.lo.x > pieces[i].x0 && b.hi.x < pieces[i].x1) ? 1u : 0u;
            }
            CHECK(pieces[i].enclosed == enclosed);
        }
    }
}

TEST_CASE("piece topology matches a raster count on the large exemplars", "[pattern][pieces][slow]") {
    // vine.svg is left out: its spiral tendrils come within 0.036 mm of themselves, so a cut through a
    // spiral leaves a tiny hole behind a bridge thinner than any affordable pixel (checked by hand:
    // hole area 0.043 mm^2 at 0.036 mm from the outline); the descriptor test above covers it.
    for (const char* f : {"lace_scallop.svg", "quatrefoil.svg"}) {
        INFO(f);
        const exemplar ex = test::load_vector_exemplar(f);
        const auto pieces = vector_pattern::slice(ex, offset_cuts(ex, 3));
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            INFO("piece " << i);
            const auto [c, h] = raster_topology(pieces[i].polygons, 0.05);
            CHECK(static_cast<std::size_t>(c) == pieces[i].components());
            CHECK(static_cast<std::uint32_t>(h) == pieces[i].holes());
        }
    }
}

TEST_CASE("uniform slicing spaces t cuts W/(t+1) apart", "[pattern][pieces]") {
    const exemplar ex = test::load_vector_exemplar("zigzag.svg");
    const auto c = vector_pattern::uniform_cuts(ex, 5);
    REQUIRE(c.size() == 5);
    for (std::size_t k = 0; k < c.size(); ++k) CHECK(c[k] == Approx(80.0 * static_cast<double>(k + 1)));
    const auto pieces = vector_pattern::slice(ex, c);
    REQUIRE(pieces.size() == 6);
    for (const auto& p : pieces) {
        CHECK(p.width() == Approx(80.0));
        // The chevron band (y in [10,30] at x = 0 mod 40, a parallelogram strip 20 high): one portal
        // of height 20 on each side.
        REQUIRE(p.left.size() == 1);
        REQUIRE(p.right.size() == 1);
        CHECK(p.left[0].width() == Approx(20.0));
    }
    CHECK(vector_pattern::uniform_cuts(ex, 0).empty());
    CHECK_THROWS_AS(vector_pattern::slice(ex, std::vector<double>{100.0, 50.0}), invalid_input);
    CHECK_THROWS_AS(vector_pattern::slice(ex, std::vector<double>{0.0}), invalid_input);
    CHECK_THROWS_AS(vector_pattern::slice(ex, std::vector<double>{std::nan("")}), invalid_input);
}

namespace {
exemplar rect_with_hole(double hx0, double hx1, double hy0, double hy1) {
    vector_pattern::exemplar_shape s;
    s.subpaths = {ring2{{0, 0}, {100, 0}, {100, 20}, {0, 20}}, ring2{{hx0, hy0}, {hx1, hy0}, {hx1, hy1}, {hx0, hy1}}};
    s.closed = {true, true};
    s.rule = fill_rule::evenodd;
    return vector_pattern::make_exemplar({s});
}
}  // namespace

TEST_CASE("Reeb slicing of hand-made exemplars gives the hand-derived cuts", "[pattern][reeb]") {
    SECTION("plate with one hole") {
        // Interior events: 40 (the column splits around the hole) and 58 (it merges again); the
        // plate's ends at 0 and 100 are the band's cut ends, not events. Cut: (40 + 58) / 2 = 49.
        const exemplar ex = rect_with_hole(40, 58, 5, 15);
        auto r = vector_pattern::reeb_slicing(ex, {.pixel = 0.5, .group_distance = 1.0});
        REQUIRE(r.events.size() == 2);
        CHECK(r.events[0] == Approx(40.0));
        CHECK(r.events[1] == Approx(58.0));
        REQUIRE(r.cuts.size() == 1);
        CHECK(r.cuts[0] == Approx(49.0));
        const auto pieces = vector_pattern::slice(ex, r.cuts);
        REQUIRE(pieces.size() == 2);
        // The band's two ends are cut too (as in data/vector/), so the end pieces have a portal there.
        CHECK(pieces[0].left.size() == 1);
        CHECK(pieces[0].right.size() == 2);
        CHECK(pieces[1].left.size() == 2);
        CHECK(pieces[1].right.size() == 1);
        CHECK(pieces[0].right[0].component == pieces[0].right[1].component);
        CHECK(pieces[0].holes() == 0);  // the hole is split: no piece holds it whole
        CHECK(pieces[0].right[0].width() == Approx(5.0));
        const topology::descriptor d = merge(pieces[0].descriptor(), pieces[1].descriptor());
        CHECK(d.left().size() == 1);
        CHECK(d.right().size() == 1);
        CHECK(d.open_components() == 1);
        CHECK(d.enclosed() == 0);
        CHECK(d.holes() == 1);
        // Paper default grouping 0.2 W = 20: 40 and 58 are 18 apart and form one group at 49, so a
        // single attacher and no cut.
        r = vector_pattern::reeb_slicing(ex, {.pixel = 0.5});
        REQUIRE(r.attachers.size() == 1);
        CHECK(r.attachers[0] == Approx(49.0));
        CHECK(r.cuts.empty());
    }
    SECTION("plate with two holes") {
        // Events 20, 30 | 60, 70 -> with grouping 15: attachers 25 and 65 -> cut 45.
        vector_pattern::exemplar_shape s;
        s.subpaths = {ring2{{0, 0}, {100, 0}, {100, 20}, {0, 20}}, ring2{{20, 5}, {30, 5}, {30, 15}, {20, 15}},
                      ring2{{60, 5}, {70, 5}, {70, 15}, {60, 15}}};
        s.rule = fill_rule::evenodd;
        const exemplar ex = vector_pattern::make_exemplar({s});
        const auto r = vector_pattern::reeb_slicing(ex, {.pixel = 0.5, .group_distance = 15.0});
        REQUIRE(r.attachers.size() == 2);
        CHECK(r.attachers[0] == Approx(25.0));
        CHECK(r.attachers[1] == Approx(65.0));
        REQUIRE(r.cuts.size() == 1);
        CHECK(r.cuts[0] == Approx(45.0));
        const auto pieces = vector_pattern::slice(ex, r.cuts);
        CHECK(pieces[0].holes() == 1);
        CHECK(pieces[1].holes() == 1);
    }
    SECTION("two separate blocks") {
        vector_pattern::exemplar_shape a{{ring2{{0, 0}, {30, 0}, {30, 10}, {0, 10}}}, {true}, fill_rule::nonzero, ""};
        vector_pattern::exemplar_shape b{{ring2{{50, 0}, {100, 0}, {100, 10}, {50, 10}}}, {true}, fill_rule::nonzero, ""};
        const exemplar ex = vector_pattern::make_exemplar({a, b});
        // Interior events: 30 (the first block ends), 50 (the second begins) -> cut 40.
        const auto r = vector_pattern::reeb_slicing(ex, {.pixel = 0.25, .group_distance = 2.0});
        REQUIRE(r.cuts.size() == 1);
        CHECK(r.cuts[0] == Approx(40.0));
        const auto pieces = vector_pattern::slice(ex, r.cuts);
        CHECK(pieces[0].left.size() == 1);
        CHECK(pieces[0].right.size() == 0);
        CHECK(pieces[1].left.size() == 0);
        CHECK(pieces[1].right.size() == 1);
    }
}

TEST_CASE("thin portals below the width threshold are filtered out", "[pattern][reeb]") {
    // A plate whose first slot leaves 1 mm bars, the second 4 mm bars: events 10, 40 | 60, 90 ->
    // cuts 25, 50, 75; the cut at 25 crosses two 1 mm bars, the one at 75 two 4 mm bars.
    vector_pattern::exemplar_shape s;
    s.subpaths = {ring2{{0, 0}, {100, 0}, {100, 20}, {0, 20}}, ring2{{10, 1}, {40, 1}, {40, 19}, {10, 19}},
                  ring2{{60, 4}, {90, 4}, {90, 16}, {60, 16}}};
    s.rule = fill_rule::evenodd;
    const exemplar ex = vector_pattern::make_exemplar({s});
    auto r = vector_pattern::reeb_slicing(ex, {.pixel = 0.5, .group_distance = 1.0});
    REQUIRE(r.cuts.size() == 3);
    r = vector_pattern::reeb_slicing(ex, {.pixel = 0.5, .group_distance = 1.0, .min_portal_width = 2.0});
    REQUIRE(r.cuts.size() == 2);
    CHECK(r.cuts[0] == Approx(50.0));
    CHECK(r.cuts[1] == Approx(75.0));
    r = vector_pattern::reeb_slicing(ex, {.pixel = 0.5, .group_distance = 1.0, .min_portal_width = 5.0});
    REQUIRE(r.cuts.size() == 1);
    CHECK(r.cuts[0] == Approx(50.0));
    const std::vector<double> cuts{25.0, 50.0, 75.0};
    CHECK(vector_pattern::filter_thin_cuts(ex, cuts, 0.5).size() == 3);
    CHECK(vector_pattern::filter_thin_cuts(ex, cuts, 1.5).size() == 2);
    CHECK_THROWS_AS(vector_pattern::filter_thin_cuts(ex, cuts, -1.0), invalid_input);
}

TEST_CASE("Reeb slicing of bundled exemplars yields no topologically trivial piece", "[pattern][reeb]") {
    // Periods from data/README.md. Group at a tenth of the period (instead of 0.2 W, which on these
    // 6-11 period bands chains every event into one group).
    const std::pair<const char*, double> cases[] = {{"greek_key.svg", 80.0}, {"hearts.svg", 160.0}, {"pearls.svg", 44.0}};
    for (const auto& [f, period] : cases) {
        INFO(f);
        const exemplar ex = test::load_vector_exemplar(f);
        const auto r = vector_pattern::reeb_slicing(ex, {.group_distance = 0.1 * period, .min_portal_width = 0.5});
        REQUIRE(r.cuts.size() >= 2);
        CHECK(std::is_sorted(r.cuts.begin(), r.cuts.end()));
        const auto pieces = vector_pattern::slice(ex, r.cuts);
        for (double c : r.cuts)
            for (const auto& [t, b] : vector_pattern::cross_section(ex, c)) CHECK(b - t >= 0.5);
        double sum = 0.0;
        for (const auto& p : pieces) sum += area(p.polygons);
        CHECK(std::abs(sum - ex.area()) <= 1e-9 * ex.area());
        // §5.2: no piece is topologically trivial (every component passing straight through with one
        // portal per side, nothing enclosed, no hole).
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            const auto& p = pieces[i];
            bool trivial = p.left.size() == p.right.size() && p.holes() == 0 && p.enclosed == 0;
            for (std::size_t k = 0; trivial && k < p.left.size(); ++k) {
                trivial = p.left[k].component == p.right[k].component;
                for (std::size_t m = 0; m < p.left.size(); ++m)
                    if (m != k && p.left[m].component == p.left[k].component) trivial = false;
            }
            INFO("piece " << i << " [" << p.x0 << ", " << p.x1 << "]");
            CHECK_FALSE(trivial);
        }
    }
    const exemplar ex = test::load_vector_exemplar("zigzag.svg");
    CHECK_THROWS_AS(vector_pattern::reeb_slicing(ex, {.pixel = 1e-6}), invalid_input);  // raster too large
    CHECK_THROWS_AS(vector_pattern::reeb_slicing(ex, {.pixel = std::nan("")}), invalid_input);
}
