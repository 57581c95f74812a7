// geometry/render.hpp against hand-computed oracles: silhouette areas, shading by the Lambert
// formula, mirror symmetry of the two sides, orientation, vertex colours, the depth tie rule, an
// exactly-once fill rule on tilings, thread independence and input errors.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/render.hpp"
#include "fabsynth/io/image.hpp"
#include "fabsynth/io/mesh.hpp"
#include "support/sphere_mesh.hpp"

using namespace fabsynth;

namespace {
using rgb = std::array<std::uint8_t, 3>;

// Latitude-longitude sphere of radius r with its poles on the y axis: n_around vertices per ring,
// n_rings (even) bands, so the ring at the equator is the regular n_around-gon of radius r in the
// xz plane (the exact silhouette seen along y).
triangle_mesh uv_sphere(double r, int n_around, int n_rings) {
    triangle_mesh m;
    m.vertices.push_back({0, r, 0});
    for (int k = 1; k < n_rings; ++k) {
        const double th = M_PI * k / n_rings;
        for (int i = 0; i < n_around; ++i) {
            const double ph = 2 * M_PI * i / n_around;
            m.vertices.push_back({r * std::sin(th) * std::cos(ph), r * std::cos(th), r * std::sin(th) * std::sin(ph)});
        }
    }
    m.vertices.push_back({0, -r, 0});
    const auto ring = [&](int k, int i) { return static_cast<std::uint32_t>(1 + (k - 1) * n_around + (i % n_around)); };
    const auto south = static_cast<std::uint32_t>(m.vertices.size() - 1);
    for (int i = 0; i < n_around; ++i) {
        m.faces.push_back({0, ring(1, i + 1), ring(1, i)});
        for (int k = 1; k + 1 < n_rings; ++k) {
            m.faces.push_back({ring(k, i), ring(k, i + 1), ring(k + 1, i + 1)});
            m.faces.push_back({ring(k, i), ring(k + 1, i + 1), ring(k + 1, i)});
        }
        m.faces.push_back({south, ring(n_rings - 1, i), ring(n_rings - 1, i + 1)});
    }
    return m;
}

// Closed box [lo, hi] with outward faces (12 triangles).
triangle_mesh box_mesh(vec3 lo, vec3 hi) {
    triangle_mesh m;
    for (int i = 0; i < 8; ++i) m.vertices.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    m.faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
               {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    return m;
}

// Square in the plane y = y0 (normal +y), centre (cx, cz), half side h.
void add_square(triangle_mesh& m, double cx, double cz, double h, double y0 = 0) {
    const auto b = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back({cx - h, y0, cz - h});
    m.vertices.push_back({cx + h, y0, cz - h});
    m.vertices.push_back({cx + h, y0, cz + h});
    m.vertices.push_back({cx - h, y0, cz + h});
    m.faces.push_back({b, b + 2, b + 1});
    m.faces.push_back({b, b + 3, b + 2});
}

// Random, overlapping triangles in [-1, 1]^3 (no symmetry).
triangle_mesh soup(std::uint64_t seed, int n) {
    triangle_mesh m;
    counter_rng rng(seed);
    for (int t = 0; t < n; ++t) {
        const vec3 c(rng.uniform(-1, 0.6), rng.uniform(-1, 1), rng.uniform(-0.7, 1));
        for (int k = 0; k < 3; ++k) m.vertices.push_back(c + vec3(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)));
        const auto b = static_cast<std::uint32_t>(3 * t);
        m.faces.push_back({b, b + 1, b + 2});
    }
    return m;
}

bool is(const image8& im, int x, int y, rgb c) { return im.at(x, y, 0) == c[0] && im.at(x, y, 1) == c[1] && im.at(x, y, 2) == c[2]; }

long count_not(const image8& im, rgb bg, int x0 = 0, int x1 = -1) {
    if (x1 < 0) x1 = im.width;
    long n = 0;
    for (int y = 0; y < im.height; ++y)
        for (int x = x0; x < x1; ++x) n += !is(im, x, y, bg);
    return n;
}
}  // namespace

TEST_CASE("render: a sphere's silhouette is the disk of the fitted radius", "[geometry][render]") {
    const rgb bg{0, 255, 0};  // no grey shade of the surface can be this
    render_options opt{.width = 400, .height = 400, .supersample = 1, .background = bg, .margin = 0.05};
    SECTION("along the poles: the equator polygon exactly") {
        const int n = 256;
        const triangle_mesh m = uv_sphere(3.0, n, 64);
        const image8 im = render_shaded(m, {.direction = {0, -1, 0}, .up = {0, 0, 1}}, opt);
        REQUIRE(im.width == 400);
        REQUIRE(im.height == 400);
        REQUIRE(im.channels == 3);
        const double r = 0.9 * 400 / 2;  // the equator spans the image less the margins
        const double polygon = 0.5 * n * std::sin(2 * M_PI / n) * r * r;
        const double covered = static_cast<double>(count_not(im, bg));
        CHECK(std::abs(covered - polygon) < 0.005 * polygon);
        double sx = 0, sy = 0;
        for (int y = 0; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x)
                if (!is(im, x, y, bg)) sx += x + 0.5, sy += y + 0.5;
        CHECK(sx / covered == Approx(200).margin(0.25));
        CHECK(sy / covered == Approx(200).margin(0.25));
    }
    SECTION("from an oblique direction: pi r^2 of the projected extent") {
        const triangle_mesh m = test::sphere_mesh(1.0, 5);
        const render_view view{.direction = {1, 2, -3}, .up = {0, 1, 1}};
        // Independent frame: the extent of the projected vertices gives the scale.
        const vec3 d = glm::normalize(view.direction);
        const vec3 u = glm::normalize(view.up - glm::dot(view.up, d) * d), right = glm::cross(d, u);
        double lo = 1e9, hi = -1e9, lo_v = 1e9, hi_v = -1e9;
        for (const vec3& p : m.vertices) {
            lo = std::min(lo, glm::dot(p, right)), hi = std::max(hi, glm::dot(p, right));
            lo_v = std::min(lo_v, glm::dot(p, u)), hi_v = std::max(hi_v, glm::dot(p, u));
        }
        const double r = 0.9 * 400 / std::max(hi - lo, hi_v - lo_v);  // pixels for radius 1
        const double covered = static_cast<double>(count_not(render_shaded(m, view, opt), bg));
        CHECK(std::abs(covered - M_PI * r * r) < 0.015 * M_PI * r * r);  // the inscribed polyhedron is a bit smaller
    }
}

TEST_CASE("render: a cube seen along a face normal is a uniform square of the Lambert brightness", "[geometry][render]") {
    const triangle_mesh cube = box_mesh({-1, -1, -1}, {1, 1, 1});
    const rgb bg{10, 20, 30};
    render_options opt{.width = 200, .height = 200, .background = bg, .margin = 0.1};
    const auto expect_square = [&](const image8& im, double intensity) {
        // 2 mm fill 0.8 * 200 px: pixels [20, 180) both ways, boundaries between sample centres
        int wrong = 0;
        for (int y = 0; y < 200; ++y)
            for (int x = 0; x < 200; ++x) {
                const bool inside = x >= 20 && x < 180 && y >= 20 && y < 180;
                for (int c = 0; c < 3; ++c) {
                    const double want = inside ? opt.base_colour[c] * intensity : bg[c];
                    wrong += std::abs(im.at(x, y, c) - want) > 0.5 + 1e-9;
                }
            }
        CHECK(wrong == 0);
    };
    const double cos_default = 1.0 / glm::length(vec3(-0.4, 0.6, 1.0));  // n = camera z for the facing side
    SECTION("default light, from -y and from +x") {
        expect_square(render_shaded(cube, {.direction = {0, -1, 0}, .up = {0, 0, 1}}, opt), 0.25 + 0.75 * cos_default);
        expect_square(render_shaded(cube, {.direction = {-1, 0, 0}, .up = {0, 0, 1}}, opt), 0.25 + 0.75 * cos_default);
        expect_square(render_shaded(cube, {.direction = {0, 0, -7}, .up = {0, 3, 0}}, opt), 0.25 + 0.75 * cos_default);
    }
    SECTION("light from the side: ambient only; light from the eye: ambient + diffuse") {
        opt.light = {1, 0, 0};
        expect_square(render_shaded(cube, {}, opt), 0.25);
        opt.light = {0, 0, 2}, opt.ambient = 0.1, opt.diffuse = 0.5;
        expect_square(render_shaded(cube, {}, opt), 0.6);
        opt.supersample = 1;
        expect_square(render_shaded(cube, {}, opt), 0.6);
    }
    SECTION("two faces at 45 degrees: each has its own cosine, +x face on the left") {
        // Eye at +x+y: right = (-1, 1, 0)/sqrt2, so the x = 1 face (normal (-1, 0, 1)/sqrt2 in camera
        // space) is the left half and the y = 1 face ((1, 0, 1)/sqrt2) the right half.
        opt.supersample = 1;
        const image8 im = render_shaded(cube, {.direction = {-1, -1, 0}, .up = {0, 0, 1}}, opt);
        const vec3 l = glm::normalize(vec3(-0.4, 0.6, 1.0));
        const double left = 0.25 + 0.75 * std::max(0.0, (-l.x + l.z) / std::sqrt(2.0));
        const double right = 0.25 + 0.75 * std::max(0.0, (l.x + l.z) / std::sqrt(2.0));
        REQUIRE(left > right + 0.1);
        for (int y : {60, 100, 140})  // the 2 mm height is 160 / (2 sqrt2) px per mm: rows 43.4..156.6
            for (auto [x, intensity] : {std::pair{40, left}, {90, left}, {110, right}, {160, right}})
                for (int c = 0; c < 3; ++c) CHECK(std::abs(im.at(x, y, c) - opt.base_colour[c] * intensity) <= 0.5 + 1e-9);
        CHECK(is(im, 100, 40, bg));
        CHECK(is(im, 100, 160, bg));
    }
}

TEST_CASE("render: the back view is the mirror image of the front view's silhouette", "[geometry][render]") {
    triangle_mesh m = soup(11, 40);
    const rgb bg{0, 255, 0};
    const render_options opt{.width = 160, .height = 120, .supersample = 1, .background = bg, .gap = 7};
    for (const render_view& view : {render_view{}, render_view{.direction = {0.3, 1, -0.2}, .up = {1, 0, 1}}}) {
        const image8 im = render_two_sides(m, view, opt);
        REQUIRE(im.width == 2 * 160 + 7);
        REQUIRE(im.height == 120);
        CHECK(count_not(im, bg, 160, 167) == 0);  // the gap
        long covered = 0, mirror_diff = 0, self_diff = 0;
        for (int y = 0; y < 120; ++y)
            for (int x = 0; x < 160; ++x) {
                const bool front = !is(im, x, y, bg), back = !is(im, 167 + 159 - x, y, bg), front_mirror = !is(im, 159 - x, y, bg);
                covered += front;
                mirror_diff += front != back;
                self_diff += front != front_mirror;
            }
        REQUIRE(covered > 2000);
        CHECK(mirror_diff <= covered / 500);  // only ties of the fill rule may differ
        CHECK(self_diff > covered / 10);      // the mesh is not symmetric itself
    }
    // The same as two render_shaded calls with the opposite direction.
    const image8 both = render_two_sides(m, {}, opt);
    const image8 back = render_shaded(m, {.direction = {0, 1, 0}, .up = {0, 0, 1}}, opt);
    long diff = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x)
            for (int c = 0; c < 3; ++c) diff += both.at(167 + x, y, c) != back.at(x, y, c);
    CHECK(diff <= 20);
}

TEST_CASE("render: the picture is upright and not mirrored", "[geometry][render]") {
    // Red square at +x, +z; blue square at -x, -z, both in the plane y = 0.
    triangle_mesh m;
    add_square(m, 0.5, 0.5, 0.3);
    add_square(m, -0.5, -0.5, 0.3);
    std::vector<rgb> colours(8, rgb{0, 0, 255});
    for (int i = 0; i < 4; ++i) colours[static_cast<std::size_t>(i)] = {255, 0, 0};
    const render_options opt{.width = 100, .height = 100, .supersample = 1, .light = {0, 0, 1}, .ambient = 0, .diffuse = 1};
    const auto quadrant = [&](const render_view& v) {  // {upper-left, upper-right, lower-left, lower-right} colours
        const image8 im = render_shaded(m, v, opt, colours);
        std::array<rgb, 4> q{};
        int k = 0;
        for (int y : {25, 75})
            for (int x : {25, 75}) q[static_cast<std::size_t>(k++)] = {im.at(x, y, 0), im.at(x, y, 1), im.at(x, y, 2)};
        return q;
    };
    const rgb red{255, 0, 0}, blue{0, 0, 255}, white{255, 255, 255};
    // Looking along -y with z up, +x is on the left (the eye stands at +y).
    CHECK(quadrant({.direction = {0, -1, 0}, .up = {0, 0, 1}}) == std::array<rgb, 4>{red, white, white, blue});
    CHECK(quadrant({.direction = {0, 1, 0}, .up = {0, 0, 1}}) == std::array<rgb, 4>{white, red, blue, white});
    CHECK(quadrant({.direction = {0, -1, 0}, .up = {0, 0, -1}}) == std::array<rgb, 4>{blue, white, white, red});
    // render_two_sides: front on the left, back on the right.
    const image8 both = render_two_sides(m, {}, {.width = 100, .height = 100, .supersample = 1, .light = {0, 0, 1}, .ambient = 0, .diffuse = 1, .gap = 0}, colours);
    CHECK(is(both, 25, 25, red));
    CHECK(is(both, 175, 25, red));
    CHECK(is(both, 125, 75, blue));
}

TEST_CASE("render: vertex colours are interpolated and scaled by the shading", "[geometry][render]") {
    SECTION("an all-red mesh on black is red only") {
        const triangle_mesh m = test::sphere_mesh(2.0, 3);
        const std::vector<rgb> red(m.num_vertices(), rgb{255, 0, 0});
        const image8 im = render_two_sides(m, {.direction = {1, -1, 0.5}, .up = {0, 0, 1}}, {.width = 120, .height = 90, .background = {0, 0, 0}}, red);
        long lit = 0;
        bool only_red = true;
        for (int y = 0; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x) {
                only_red = only_red && im.at(x, y, 1) == 0 && im.at(x, y, 2) == 0;
                lit += im.at(x, y, 0) > 0;
            }
        CHECK(only_red);
        CHECK(lit > 2 * 3000);
    }
    SECTION("a left-to-right gradient is linear") {
        triangle_mesh m;
        add_square(m, 0, 0, 1);  // vertices 0, 3 at x = -1 (right side seen from +y), 1, 2 at x = +1
        const std::vector<rgb> c{{0, 0, 255}, {255, 0, 0}, {255, 0, 0}, {0, 0, 255}};
        const render_options opt{.width = 200, .height = 200, .light = {0, 0, 1}, .ambient = 0, .diffuse = 1, .margin = 0.1};
        const image8 im = render_shaded(m, {}, opt, c);  // along -y: +x (red) on the left
        int bad = 0;
        for (int y : {21, 100, 178})
            for (int x = 20; x < 180; ++x) {
                const double t = (x + 0.5 - 20) / 160;  // 0 at the left edge (x = +1), 1 at the right
                bad += std::abs(im.at(x, y, 0) - 255 * (1 - t)) > 1.0 || std::abs(im.at(x, y, 2) - 255 * t) > 1.0 || im.at(x, y, 1) != 0;
            }
        CHECK(bad == 0);
    }
}

TEST_CASE("render: the nearer surface wins, equal depths go to the lower face index", "[geometry][render]") {
    const render_options opt{.width = 64, .height = 64, .supersample = 1, .light = {0, 0, 1}, .ambient = 0, .diffuse = 1};
    const rgb red{255, 0, 0}, blue{0, 0, 255};
    const std::vector<rgb> colours{red, red, red, red, blue, blue, blue, blue};
    const auto all = [](const image8& im, rgb c) {
        for (int y = 4; y < 60; ++y)
            for (int x = 4; x < 60; ++x)
                if (!is(im, x, y, c)) return false;
        return true;
    };
    triangle_mesh same;  // two coincident squares: red (faces 0, 1) then blue (faces 2, 3)
    add_square(same, 0, 0, 1);
    add_square(same, 0, 0, 1);
    CHECK(all(render_shaded(same, {}, opt, colours), red));
    std::swap(same.faces[0], same.faces[2]), std::swap(same.faces[1], same.faces[3]);  // blue first now
    CHECK(all(render_shaded(same, {}, opt, colours), blue));

    triangle_mesh stacked;  // red at y = 0, blue in front of it (nearer the eye at +y), in both orders
    add_square(stacked, 0, 0, 1, 0.0);
    add_square(stacked, 0, 0, 1, 0.5);
    CHECK(all(render_shaded(stacked, {}, opt, colours), blue));
    std::swap(stacked.faces[0], stacked.faces[2]), std::swap(stacked.faces[1], stacked.faces[3]);
    CHECK(all(render_shaded(stacked, {}, opt, colours), blue));
    CHECK(all(render_shaded(stacked, {.direction = {0, 1, 0}, .up = {0, 0, 1}}, opt, colours), red));  // from behind
}

TEST_CASE("render: the fill rule covers a tiling exactly once", "[geometry][render]") {
    using namespace detail::render;
    // A G x G grid of cells of 3 samples (768 fixed-point units), interior vertices jittered by
    // multiples of 64 (so many land on sample centres and many edges pass through them), cells cut
    // along a random diagonal, half of the triangles given clockwise.
    const int G = 24;
    const std::int64_t cell = 3 * unit, size = G * cell;
    std::vector<point> p;
    for (int j = 0; j <= G; ++j)
        for (int i = 0; i <= G; ++i) {
            point q{i * cell, j * cell};
            if (i > 0 && i < G && j > 0 && j < G)
                q.x += 64 * static_cast<std::int64_t>(hash64(1, i, j) % 7) - 192, q.y += 64 * static_cast<std::int64_t>(hash64(2, i, j) % 7) - 192;
            p.push_back(q);
        }
    const auto at = [&](int i, int j) { return p[static_cast<std::size_t>(j * (G + 1) + i)]; };
    std::vector<std::array<point, 3>> tris;
    for (int j = 0; j < G; ++j)
        for (int i = 0; i < G; ++i) {
            const point a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            if (hash64(3, i, j) & 1) tris.push_back({a, b, c}), tris.push_back({a, c, d});
            else tris.push_back({a, b, d}), tris.push_back({b, c, d});
        }
    const std::int64_t n = size / unit;  // samples per side; the outer boundary lies between centres
    std::vector<int> hits(static_cast<std::size_t>(n * n), 0);
    bool weights_ok = true;
    for (std::size_t t = 0; t < tris.size(); ++t) {
        point a = tris[t][0], b = tris[t][1], c = tris[t][2];
        REQUIRE(edge(a, b, c.x, c.y) > 0);  // the jitter keeps every triangle positive (a true tiling)
        if (hash64(4, t) & 1) std::swap(b, c);
        for_each_covered_sample(a, b, c, 0, n, n, [&](std::int64_t i, std::int64_t j, std::int64_t wa, std::int64_t wb, std::int64_t wc, std::int64_t area) {
            ++hits[static_cast<std::size_t>(j * n + i)];
            const std::int64_t px = i * unit + half, py = j * unit + half;
            const std::int64_t s = edge(a, b, c.x, c.y) > 0 ? 1 : -1;  // weights are oriented edge functions
            weights_ok = weights_ok && wa >= 0 && wb >= 0 && wc >= 0 && wa + wb + wc == area && wa == s * edge(b, c, px, py) &&
                         wb == s * edge(c, a, px, py) && wc == s * edge(a, b, px, py);
        });
    }
    long wrong = 0;
    for (int h : hits) wrong += h != 1;
    CHECK(wrong == 0);
    CHECK(weights_ok);

    // A fan around a vertex exactly at a sample centre, and band clipping: the rows come in parts.
    const point centre{10 * unit + half, 10 * unit + half};
    std::vector<int> fan(400, 0);
    for (int k = 0; k < 7; ++k) {
        const double a0 = 2 * M_PI * k / 7, a1 = 2 * M_PI * (k + 1) / 7;
        const point u{centre.x + std::llround(2000 * std::cos(a0)), centre.y + std::llround(2000 * std::sin(a0))};
        const point v{centre.x + std::llround(2000 * std::cos(a1)), centre.y + std::llround(2000 * std::sin(a1))};
        for (std::int64_t r0 = 0; r0 < 20; r0 += 3)
            for_each_covered_sample(centre, u, v, r0, r0 + 3, 20, [&](std::int64_t i, std::int64_t j, auto...) { ++fan[static_cast<std::size_t>(j * 20 + i)]; });
    }
    CHECK(fan[10 * 20 + 10] == 1);
    for (int h : fan) CHECK(h <= 1);
}

TEST_CASE("render: the same image for 1 and 2 threads", "[geometry][render]") {
    triangle_mesh m = test::sphere_mesh(1.0, 4);
    const triangle_mesh s = soup(5, 300);
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), s.vertices.begin(), s.vertices.end());
    for (auto f : s.faces) m.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
    for (std::size_t f = 0; f < 200; ++f) m.faces.push_back(m.faces[f * 3]);  // exact duplicates: depth ties
    std::vector<rgb> colours(m.num_vertices());
    for (std::size_t i = 0; i < colours.size(); ++i)
        colours[i] = {static_cast<std::uint8_t>(hash64(9, i) & 255), static_cast<std::uint8_t>(hash64(10, i) & 255), 128};
    const render_options opt{.width = 300, .height = 227, .supersample = 3};
    set_num_threads(1);
    const image8 one = render_two_sides(m, {.direction = {1, 2, -1}, .up = {0, 0, 1}}, opt, colours);
    set_num_threads(2);
    const image8 two = render_two_sides(m, {.direction = {1, 2, -1}, .up = {0, 0, 1}}, opt, colours);
    set_num_threads(3);
    const image8 three = render_two_sides(m, {.direction = {1, 2, -1}, .up = {0, 0, 1}}, opt, colours);
    set_num_threads(0);
    CHECK(one == two);
    CHECK(one == three);
}

TEST_CASE("render: bad input throws invalid_input", "[geometry][render]") {
    const triangle_mesh cube = box_mesh({0, 0, 0}, {1, 2, 3});
    CHECK_THROWS_AS(render_shaded(triangle_mesh{}, {}), invalid_input);
    CHECK_THROWS_WITH(render_shaded(triangle_mesh{}, {}), Catch::Contains("no faces"));
    triangle_mesh bad = cube;
    bad.vertices[3].y = std::nan("");
    CHECK_THROWS_WITH(render_shaded(bad, {}), Catch::Contains("vertex 3 is not finite"));
    bad = cube;
    bad.faces[5][1] = 8;
    CHECK_THROWS_WITH(render_two_sides(bad, {}), Catch::Contains("face 5 indexes missing vertex 8"));
    CHECK_THROWS_WITH(render_shaded(cube, {.direction = {0, 0, 0}}), Catch::Contains("view direction"));
    CHECK_THROWS_WITH(render_shaded(cube, {.direction = {0, 0, INFINITY}}), Catch::Contains("view direction"));
    CHECK_THROWS_WITH(render_shaded(cube, {.up = {0, 0, 0}}), Catch::Contains("up vector"));
    CHECK_THROWS_WITH(render_shaded(cube, {.direction = {0, 0, 2}, .up = {0, 0, -1}}), Catch::Contains("parallel"));
    CHECK_THROWS_WITH(render_shaded(cube, {}, {.width = 0}), Catch::Contains("image size"));
    CHECK_THROWS_WITH(render_shaded(cube, {}, {.height = 8193}), Catch::Contains("image size"));
    CHECK_THROWS_WITH(render_shaded(cube, {}, {.supersample = 5}), Catch::Contains("supersample"));
    CHECK_THROWS_WITH(render_shaded(cube, {}, {.light = {0, 0, 0}}), Catch::Contains("light"));
    CHECK_THROWS_WITH(render_shaded(cube, {}, {.ambient = -0.1}), Catch::Contains("ambient"));
    CHECK_THROWS_WITH(render_shaded(cube, {}, {.diffuse = NAN}), Catch::Contains("diffuse"));
    CHECK_THROWS_WITH(render_shaded(cube, {}, {.margin = 0.5}), Catch::Contains("margin"));
    CHECK_THROWS_WITH(render_two_sides(cube, {}, {.gap = -1}), Catch::Contains("gap"));
    const std::vector<rgb> few(7);
    CHECK_THROWS_WITH(render_shaded(cube, {}, {}, few), Catch::Contains("7 vertex colours given for 8 vertices"));
    triangle_mesh point;  // every vertex at one place
    point.vertices = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
    point.faces = {{0, 1, 2}};
    CHECK_THROWS_WITH(render_shaded(point, {}), Catch::Contains("single point"));
    // A flat mesh seen edge-on is fine (it draws nothing).
    triangle_mesh flat;
    add_square(flat, 0, 0, 1);
    const image8 im = render_shaded(flat, {.direction = {1, 0, 0}, .up = {0, 0, 1}}, {.width = 20, .height = 10});
    CHECK(count_not(im, {255, 255, 255}) == 0);
}

// Not run by default: writes the bunny's two sides to the test tmp dir for a person to look at.
TEST_CASE("render: bunny preview", "[.][render_preview]") {
    const triangle_mesh m = io::read_mesh(FABSYNTH_DATA_DIR "/meshes/bunny_lowres.obj");
    const std::filesystem::path dir = std::filesystem::path(FABSYNTH_TEST_TMP) / "render";
    std::filesystem::create_directories(dir);
    io::write_png(dir / "bunny_two_sides.png", render_two_sides(m, {.direction = {0, 0, -1}, .up = {0, 1, 0}}, {.width = 400, .height = 400}));
    triangle_mesh z_up = m;  // as the tools see a print: z up, the default view from +y
    rotate_y_up_to_z_up(z_up);
    io::write_png(dir / "bunny_z_up.png", render_two_sides(z_up, {}, {.width = 400, .height = 400}));
    std::cout << "wrote " << (dir / "bunny_two_sides.png") << "\n";
}
