#include <catch2/catch.hpp>

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/core/rng.hpp>
#include <fabsynth/core/union_find.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/surface_pattern/fabricate.hpp>
#include <fabsynth/voxel/components.hpp>
#include <fabsynth/voxel/voxelize.hpp>

#include <map>
#include <numbers>
#include <set>

#include "support/sphere_mesh.hpp"

using namespace fabsynth;
using namespace fabsynth::surface_pattern;

namespace {

constexpr double sphere_radius = 20.0;  // mm

// The shell of a sphere of radius 20 mm centred at the origin on a fitted grid of `res` voxels.
const shell_list& sphere_shell(int res) {
    static std::map<int, shell_list> cache;
    auto it = cache.find(res);
    if (it != cache.end()) return it->second;
    const triangle_mesh m = test::sphere_mesh(sphere_radius, 5);
    const grid_geometry g = fit_grid(bounding_box(m), res, 2);
    return cache.emplace(res, to_shell_list(voxelize_surface(m, g))).first->second;
}

// Brute-force nearest shell voxel of every grid voxel within distance t of the shell: the
// candidates come from a dense dilation, the nearest voxel from a linear scan of the shell voxels
// (exact integer squared distances on the cubic grid, ties to the smaller shell position).
struct nearest_table {
    std::vector<ivec3> voxel;
    std::vector<std::uint32_t> nearest;
    std::vector<std::int64_t> d2;  // squared distance in voxels^2
};
nearest_table brute_force_nearest(const shell_list& s, double t) {
    const grid_geometry& g = s.geometry;
    REQUIRE(g.spacing.x == g.spacing.y);
    REQUIRE(g.spacing.x == g.spacing.z);
    const double h = g.spacing.x;
    const auto k_max = static_cast<std::int64_t>(std::floor(t * t / (h * h)));
    const int r = static_cast<int>(std::ceil(t / h));
    std::vector<std::uint8_t> cand(static_cast<std::size_t>(g.count()), 0);
    for (const ivec3& p : s.voxels)
        for (int dz = -r; dz <= r; ++dz)
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    const ivec3 q = p + ivec3(dx, dy, dz);
                    if (g.contains(q) && dx * dx + dy * dy + dz * dz <= k_max) cand[static_cast<std::size_t>(g.index(q))] = 1;
                }
    const std::size_t n = s.voxels.size();
    std::vector<int> sx(n), sy(n), sz(n);
    for (std::size_t i = 0; i < n; ++i) sx[i] = s.voxels[i].x, sy[i] = s.voxels[i].y, sz[i] = s.voxels[i].z;
    nearest_table out;
    for (std::uint64_t c = 0; c < g.count(); ++c)
        if (cand[static_cast<std::size_t>(c)]) out.voxel.push_back(g.coord(c));
    out.nearest.resize(out.voxel.size());
    out.d2.resize(out.voxel.size());
    // every candidate has a shell voxel within t, so its nearest one has |dz| <= r: scanning the
    // shell voxels of layers z - r .. z + r (a contiguous range, the shell is in index order) finds
    // the same nearest voxel as scanning all of them
    for (std::size_t i = 1; i < n; ++i) REQUIRE(sz[i - 1] <= sz[i]);
    parallel_for(0, out.voxel.size(), [&](std::size_t k) {
        const ivec3 x = out.voxel[k];
        std::int64_t best = std::numeric_limits<std::int64_t>::max();
        std::uint32_t arg = 0;
        const auto b = static_cast<std::size_t>(std::lower_bound(sz.begin(), sz.end(), x.z - r) - sz.begin());
        const auto e = static_cast<std::size_t>(std::upper_bound(sz.begin(), sz.end(), x.z + r) - sz.begin());
        for (std::size_t i = b; i < e; ++i) {
            const std::int64_t dx = x.x - sx[i], dy = x.y - sy[i], dz = x.z - sz[i];
            const std::int64_t d = dx * dx + dy * dy + dz * dz;
            if (d < best) best = d, arg = static_cast<std::uint32_t>(i);
        }
        out.nearest[k] = arg;
        out.d2[k] = best;
    }, {.grain = 256});
    return out;
}

// The thickening by definition, from the brute-force nearest table.
std::vector<ivec3> oracle_thicken(const shell_list& s, const nearest_table& nt, const std::vector<std::uint8_t>& solid, double t) {
    const double h = s.geometry.spacing.x;
    const auto k_max = static_cast<std::int64_t>(std::floor(t * t / (h * h)));
    std::vector<ivec3> out;
    for (std::size_t k = 0; k < nt.voxel.size(); ++k) {
        const std::uint32_t i = nt.nearest[k];
        if (nt.d2[k] > k_max || !solid[i]) continue;
        if (glm::dot(s.geometry.spacing * vec3(nt.voxel[k] - s.voxels[i]), s.normals[i]) <= 0.0) out.push_back(nt.voxel[k]);
    }
    return out;
}

double shell_volume(double r_out, double r_in) { return 4.0 / 3.0 * std::numbers::pi * (r_out * r_out * r_out - r_in * r_in * r_in); }

// Independent component oracle on a dense padded box: union-find of equal-occupancy cells joined
// by the edges of the Freudenthal split (offsets in {0,1}^3 \ {0}). Returns the number of solid
// pieces and the number of (solid piece, empty region) pairs that touch = surface components.
struct topology_oracle {
    int solid_pieces = 0;
    int surfaces = 0;
};
topology_oracle freudenthal_oracle(const voxel_set& s) {
    ivec3 lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::lowest());
    for (const ivec3& p : s.voxels) lo = glm::min(lo, p), hi = glm::max(hi, p);
    lo -= 1, hi += 1;
    const ivec3 d = hi - lo + 1;
    const auto idx = [&](ivec3 p) {
        p -= lo;
        return static_cast<std::size_t>(p.x) + static_cast<std::size_t>(d.x) * (static_cast<std::size_t>(p.y) + static_cast<std::size_t>(d.y) * static_cast<std::size_t>(p.z));
    };
    const std::size_t n = static_cast<std::size_t>(d.x) * static_cast<std::size_t>(d.y) * static_cast<std::size_t>(d.z);
    std::vector<std::uint8_t> occ(n, 0);
    for (const ivec3& p : s.voxels) occ[idx(p)] = 1;
    union_find uf(n);
    std::vector<std::pair<std::size_t, std::size_t>> contacts;
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x)
                for (int o = 1; o < 8; ++o) {
                    const ivec3 p(x, y, z), q = p + ivec3(o & 1, (o >> 1) & 1, (o >> 2) & 1);
                    if (q.x > hi.x || q.y > hi.y || q.z > hi.z) continue;
                    if (occ[idx(p)] == occ[idx(q)]) uf.unite(static_cast<std::uint32_t>(idx(p)), static_cast<std::uint32_t>(idx(q)));
                    else contacts.push_back(occ[idx(p)] ? std::pair{idx(p), idx(q)} : std::pair{idx(q), idx(p)});
                }
    topology_oracle out;
    std::set<std::uint32_t> solid_roots;
    for (const ivec3& p : s.voxels) solid_roots.insert(uf.find(static_cast<std::uint32_t>(idx(p))));
    out.solid_pieces = static_cast<int>(solid_roots.size());
    std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (const auto& [a, b] : contacts) pairs.insert({uf.find(static_cast<std::uint32_t>(a)), uf.find(static_cast<std::uint32_t>(b))});
    out.surfaces = static_cast<int>(pairs.size());
    return out;
}

// Grid voxels whose centres voxelize_solid finds inside m, against the set: {missing, extra}.
std::pair<std::int64_t, std::int64_t> inside_mismatch(const triangle_mesh& m, const voxel_set& s) {
    const auto inside = voxelize_solid(m, s.geometry);
    const block_mask mask(s.geometry, s.voxels);
    std::int64_t missing = 0, extra = 0;
    for (std::uint64_t i = 0; i < s.geometry.count(); ++i) {
        const ivec3 p = s.geometry.coord(i);
        const bool in = inside.get(p) != 0, want = mask.contains(p);
        missing += want && !in;
        extra += in && !want;
    }
    return {missing, extra};
}

std::string format_g(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

bool sorted_by_index(const voxel_set& s) {
    for (std::size_t i = 1; i < s.voxels.size(); ++i)
        if (s.geometry.index(s.voxels[i - 1]) >= s.geometry.index(s.voxels[i])) return false;
    return true;
}

}  // namespace

TEST_CASE("thicken_inward: sphere shell equals the brute-force definition, volume near the analytic shell",
          "[surface_pattern][fabricate]") {
    const shell_list& s = sphere_shell(64);
    const grid_geometry& g = s.geometry;
    const double h = g.spacing.x, t = 2.0;  // t / h = 3.2: no offset lies near the threshold
    const std::size_t n = s.voxels.size();
    INFO("shell voxels " << n << ", spacing " << h << " mm");
    REQUIRE(n > 10000);
    const nearest_table nt = brute_force_nearest(s, t);

    // fully solid
    const std::vector<std::uint8_t> all(n, 1);
    const voxel_set full = thicken_inward(g, s.voxels, s.normals, all, t);
    CHECK(sorted_by_index(full));
    CHECK(full.geometry == g);
    const std::vector<ivec3> want = oracle_thicken(s, nt, all, t);
    REQUIRE(full.voxels.size() == want.size());
    CHECK(full.voxels == want);
    // every shell voxel is in (it is its own nearest voxel)
    const block_mask full_mask(g, full.voxels);
    for (const ivec3& p : s.voxels) REQUIRE(full_mask.contains(p));
    // volume: the result is the shell layer plus t inward. The conservative shell is a layer of
    // L = (shell voxels * h^3) / (4 pi R^2) ~ 1.5 h around the surface, so the solid is close to
    // the spherical shell from R + L/2 down to R - L/2 - t; the analytic shell of thickness t below
    // the surface, 4/3 pi (R^3 - (R - t)^3), misses the layer (ratio ~ (t + L) / t).
    const double v = full.volume(), R = sphere_radius;
    const double layer = static_cast<double>(n) * h * h * h / (4.0 * std::numbers::pi * R * R);
    const double v_t = shell_volume(R, R - t), v_layer = shell_volume(R + 0.5 * layer, R - 0.5 * layer - t);
    WARN("thickened sphere: " << full.size() << " voxels, " << v << " mm^3; 4/3 pi (R^3 - (R - t)^3) = " << v_t << " (ratio "
                              << v / v_t << "); shell layer L = " << layer / h << " voxels, shell from R + L/2 to R - L/2 - t: "
                              << v_layer << " (ratio " << v / v_layer << ")");
    CHECK(v > v_t);
    CHECK(v == Approx(v_layer).epsilon(0.05));
    // radial extent of the voxel centres: no voxel deeper than t + one voxel below the surface
    double rmin = 1e9, rmax = 0;
    for (const ivec3& p : full.voxels) {
        const double r = glm::length(g.center(p));
        rmin = std::min(rmin, r), rmax = std::max(rmax, r);
    }
    WARN("centre radii in [" << rmin << ", " << rmax << "] mm");
    CHECK(rmin > R - t - std::sqrt(3.0) * h);
    CHECK(rmax < R + std::sqrt(3.0) * 0.5 * h + 1e-9);

    // half solid (solid iff z > 0) and a random pattern: equal to the definition; an empty shell
    // voxel never becomes solid; every voxel's nearest shell voxel is solid
    std::vector<std::uint8_t> half(n), random(n);
    counter_rng rng(17);
    for (std::size_t i = 0; i < n; ++i) {
        half[i] = g.center(s.voxels[i]).z > 0 ? 1 : 0;
        random[i] = rng.uniform() < 0.5 ? 1 : 0;
    }
    for (const auto* pattern : {&half, &random}) {
        const voxel_set th = thicken_inward(g, s.voxels, s.normals, *pattern, t);
        CHECK(th.voxels == oracle_thicken(s, nt, *pattern, t));
        const block_mask m(g, th.voxels);
        for (std::size_t i = 0; i < n; ++i)
            if (!(*pattern)[i]) REQUIRE_FALSE(m.contains(s.voxels[i]));
        std::map<std::uint64_t, std::uint32_t> nearest;
        for (std::size_t k = 0; k < nt.voxel.size(); ++k) nearest[g.index(nt.voxel[k])] = nt.nearest[k];
        for (const ivec3& p : th.voxels) REQUIRE((*pattern)[nearest.at(g.index(p))] == 1);
    }
    // half: no voxel below z = -one column of thickness
    const voxel_set top = thicken_inward(g, s.voxels, s.normals, half, t);
    for (const ivec3& p : top.voxels) REQUIRE(g.center(p).z > -t - h);
    // nothing solid: nothing at all
    CHECK(thicken_inward(g, s.voxels, s.normals, std::vector<std::uint8_t>(n, 0), t).empty());
}

TEST_CASE("thicken_inward: anisotropic spacing, thicker offsets, threads and bad input", "[surface_pattern][fabricate]") {
    const shell_list& s = sphere_shell(64);
    const std::size_t n = s.voxels.size();
    const std::vector<std::uint8_t> all(n, 1);
    // a thickness of exactly 3 voxels includes the offset (3, 0, 0)
    const double h = s.geometry.spacing.x;
    const voxel_set three = thicken_inward(s.geometry, s.voxels, s.normals, all, 3.0 * h);
    const voxel_set more = thicken_inward(s.geometry, s.voxels, s.normals, all, 3.0 * h * (1 + 1e-9));
    CHECK(three == more);
    // a thickness of 7.5 voxels on a coarser shell: columns taller than a slab, still the definition
    {
        const shell_list& c = sphere_shell(32);
        const double tc = 7.5 * c.geometry.spacing.x;
        std::vector<std::uint8_t> pat(c.voxels.size());
        for (std::size_t i = 0; i < pat.size(); ++i) pat[i] = c.voxels[i].y % 5 < 3 ? 1 : 0;
        const nearest_table nt = brute_force_nearest(c, tc);
        CHECK(thicken_inward(c.geometry, c.voxels, c.normals, pat, tc).voxels == oracle_thicken(c, nt, pat, tc));
    }
    // 1 and 2 threads agree bit for bit
    set_num_threads(1);
    const voxel_set one = thicken_inward(s.geometry, s.voxels, s.normals, all, 2.5);
    set_num_threads(2);
    const voxel_set two = thicken_inward(s.geometry, s.voxels, s.normals, all, 2.5);
    set_num_threads(0);
    CHECK(one == two);

    // anisotropic grid: result still includes the whole solid shell and excludes empty shell voxels
    grid_geometry ga = s.geometry;
    ga.spacing = vec3(h, 1.5 * h, 0.75 * h);
    std::vector<std::uint8_t> half(n);
    for (std::size_t i = 0; i < n; ++i) half[i] = s.voxels[i].x % 7 < 4 ? 1 : 0;
    const voxel_set an = thicken_inward(ga, s.voxels, s.normals, half, 2.0 * h);
    const block_mask am(ga, an.voxels);
    for (std::size_t i = 0; i < n; ++i) REQUIRE(am.contains(s.voxels[i]) == (half[i] == 1));
    CHECK(sorted_by_index(an));

    // bad input
    const grid_geometry& g = s.geometry;
    try {
        (void)thicken_inward(g, s.voxels, s.normals, all, 0.5 * h);
        FAIL("no exception");
    } catch (const invalid_input& e) {
        const std::string msg = e.what();
        CHECK(msg.find("below one voxel spacing") != std::string::npos);
        CHECK(msg.find(format_g(0.5 * h) + " mm") != std::string::npos);
        CHECK(msg.find(format_g(h) + " mm") != std::string::npos);
    }
    CHECK_THROWS_AS(thicken_inward(g, s.voxels, s.normals, all, std::nan("")), invalid_input);
    CHECK_THROWS_AS(thicken_inward(g, s.voxels, s.normals, all, INFINITY), invalid_input);
    CHECK_THROWS_AS(thicken_inward(g, s.voxels, s.normals, all, 1000.0 * h), invalid_input);
    CHECK_THROWS_AS(thicken_inward(g, s.voxels, s.normals, std::vector<std::uint8_t>(n - 1, 1), 2.0), invalid_input);
    CHECK_THROWS_AS(thicken_inward(g, s.voxels, std::span(s.normals).first(n - 1), all, 2.0), invalid_input);
    std::vector<std::uint8_t> bad_flag = all;
    bad_flag[5] = 2;
    CHECK_THROWS_AS(thicken_inward(g, s.voxels, s.normals, bad_flag, 2.0), invalid_input);
    std::vector<vec3> bad_n = s.normals;
    bad_n[3] = vec3(0.0);
    CHECK_THROWS_AS(thicken_inward(g, s.voxels, bad_n, all, 2.0), invalid_input);
    bad_n[3] = vec3(std::nan(""), 0, 0);
    CHECK_THROWS_AS(thicken_inward(g, s.voxels, bad_n, all, 2.0), invalid_input);
    std::vector<ivec3> dup = s.voxels;
    dup[1] = dup[0];
    CHECK_THROWS_AS(thicken_inward(g, dup, s.normals, all, 2.0), invalid_input);
    std::vector<ivec3> out = s.voxels;
    out[0] = g.dims;
    CHECK_THROWS_AS(thicken_inward(g, out, s.normals, all, 2.0), invalid_input);
    grid_geometry bad_g = g;
    bad_g.spacing.y = -1;
    CHECK_THROWS_AS(thicken_inward(bad_g, s.voxels, s.normals, all, 2.0), invalid_input);
    // an empty shell is fine
    CHECK(thicken_inward(g, {}, {}, {}, 2.0).empty());
}

TEST_CASE("remove_specks: removes exactly the planted small groups and keeps the big ones", "[surface_pattern][fabricate]") {
    const shell_list& s = sphere_shell(64);
    const grid_geometry& g = s.geometry;
    const double h = g.spacing.x;
    const std::size_t n = s.voxels.size();
    // big component: the cap z > R / 2 (extent ~ 2 * 17 mm)
    std::vector<std::uint8_t> solid(n, 0);
    for (std::size_t i = 0; i < n; ++i) solid[i] = g.center(s.voxels[i]).z > 0.5 * sphere_radius ? 1 : 0;
    // planted groups on the lower half: all shell voxels in a box of k^3 voxels around a seed,
    // seeds far apart (no 26-contact between groups or with the cap)
    struct group {
        int k;
        std::vector<std::size_t> members;
        double extent = 0;
    };
    std::vector<group> groups;
    const std::vector<vec3> dirs = {{1, 0, -1}, {-1, 0, -1}, {0, 1, -1}, {0, -1, -1}, {1, 1, 0}, {-1, -1, 0}, {0, 0, -1}, {-1, 1, 0}};
    const std::vector<int> ks = {1, 2, 3, 4, 9, 12, 1, 2};
    for (std::size_t d = 0; d < dirs.size(); ++d) {
        const vec3 target = glm::normalize(dirs[d]) * sphere_radius;
        std::size_t seed = 0;
        for (std::size_t i = 0; i < n; ++i)
            if (glm::length(g.center(s.voxels[i]) - target) < glm::length(g.center(s.voxels[seed]) - target)) seed = i;
        group gr{ks[d], {}};
        ivec3 lo(1 << 30), hi(-(1 << 30));
        for (std::size_t i = 0; i < n; ++i) {
            const ivec3 o = s.voxels[i] - s.voxels[seed];
            if (glm::all(glm::greaterThanEqual(o, ivec3(-(gr.k - 1) / 2))) && glm::all(glm::lessThanEqual(o, ivec3(gr.k / 2)))) {
                gr.members.push_back(i);
                lo = glm::min(lo, s.voxels[i]), hi = glm::max(hi, s.voxels[i]);
            }
        }
        for (int a = 0; a < 3; ++a) gr.extent = std::max(gr.extent, (hi[a] - lo[a] + 1) * h);
        for (std::size_t i : gr.members) solid[i] = 1;
        groups.push_back(gr);
    }
    // independent check of the planting: each group is one 26-component of its own
    sparse_voxel_grid<std::uint8_t> grid(g, 0);
    for (std::size_t i = 0; i < n; ++i)
        if (solid[i]) grid.set(s.voxels[i], 1);
    const auto cc = label_components<connectivity::c26>(grid, [](std::uint8_t v) { return v != 0; });
    REQUIRE(cc.count == static_cast<int>(groups.size()) + 1);

    const double min_feature = 5.5 * h;
    std::vector<std::uint8_t> after = solid;
    const speck_report rep = remove_specks(g, s.voxels, after, min_feature);
    std::set<std::size_t> expect_removed;
    int expect_components = 0;
    int kept = 0;
    for (const auto& gr : groups) {
        INFO("group of box " << gr.k << ": " << gr.members.size() << " voxels, extent " << gr.extent / h << " voxels");
        if (gr.extent < min_feature) {
            expect_removed.insert(gr.members.begin(), gr.members.end());
            ++expect_components;
        } else {
            ++kept;
        }
    }
    CHECK(expect_components == 6);  // boxes of 1, 2, 3, 4, 1 and 2 voxels
    CHECK(kept == 2);               // boxes of 9 and 12 voxels
    CHECK(rep.removed_components == expect_components);
    CHECK(rep.removed_voxels == static_cast<std::int64_t>(expect_removed.size()));
    CHECK(rep.components_left == 1 + kept);
    CHECK(rep.sizes_left.size() == static_cast<std::size_t>(rep.components_left));
    std::int64_t left = 0;
    for (auto v : rep.sizes_left) left += v;
    CHECK(left == static_cast<std::int64_t>(std::count(after.begin(), after.end(), 1)));
    for (std::size_t i = 0; i < n; ++i) REQUIRE(after[i] == (expect_removed.count(i) ? 0 : solid[i]));
    // idempotent, and 0 removes nothing
    std::vector<std::uint8_t> again = after;
    CHECK(remove_specks(g, s.voxels, again, min_feature).removed_components == 0);
    CHECK(again == after);
    std::vector<std::uint8_t> keep = solid;
    CHECK(remove_specks(g, s.voxels, keep, 0.0).removed_voxels == 0);
    CHECK(keep == solid);
    // bad input
    CHECK_THROWS_AS(remove_specks(g, s.voxels, std::span(keep).first(n - 1), 1.0), invalid_input);
    CHECK_THROWS_AS(remove_specks(g, s.voxels, keep, -1.0), invalid_input);
    CHECK_THROWS_AS(remove_specks(g, s.voxels, keep, std::nan("")), invalid_input);
    keep[0] = 7;
    CHECK_THROWS_AS(remove_specks(g, s.voxels, keep, 1.0), invalid_input);
}

TEST_CASE("mesh_voxels: thickened sphere shells give watertight meshes matching the voxels", "[surface_pattern][fabricate]") {
    const shell_list& s = sphere_shell(64);
    const grid_geometry& g = s.geometry;
    const std::size_t n = s.voxels.size();
    const double t = 2.0;
    std::vector<std::uint8_t> all(n, 1), half(n), rings(n);
    for (std::size_t i = 0; i < n; ++i) {
        const vec3 c = g.center(s.voxels[i]);
        half[i] = c.z > 0 ? 1 : 0;
        rings[i] = static_cast<int>(std::floor((c.z + 22.0) / 4.0)) % 2 == 1 ? 1 : 0;  // 5 bands 4 mm high in |z| < 18
    }
    struct expect {
        const char* name;
        const std::vector<std::uint8_t>* pattern;
        int pieces, surfaces;
    };
    for (const expect& e : {expect{"full", &all, 1, 2}, expect{"half", &half, 1, 1}, expect{"rings", &rings, 5, 5}}) {
        const voxel_set v = thicken_inward(g, s.voxels, s.normals, *e.pattern, t);
        const topology_oracle o = freudenthal_oracle(v);
        const auto c6 = set_components(v, connectivity::c6{}), c26 = set_components(v, connectivity::c26{});
        const auto cm = set_components(v, mesh_connectivity{});
        INFO(e.name << ": " << v.size() << " voxels, components c6 " << c6.count << " c26 " << c26.count << " mesh " << cm.count);
        CHECK(cm.count == o.solid_pieces);
        CHECK(o.solid_pieces == e.pieces);
        CHECK(o.surfaces == e.surfaces);
        // these sets have no diagonal-only contacts: all three connectivities agree
        CHECK(c6.count == e.pieces);
        CHECK(c26.count == e.pieces);
        std::int64_t total = 0;
        for (auto sz : cm.sizes) total += sz;
        CHECK(total == static_cast<std::int64_t>(v.size()));

        const triangle_mesh raw = mesh_voxels(v, 0);
        const triangle_mesh smooth = mesh_voxels(v, 10);
        for (const triangle_mesh* m : {&raw, &smooth}) {
            const auto topo = analyze_topology(*m);
            CHECK(topo.is_watertight());
            CHECK(topo.components == static_cast<std::size_t>(e.surfaces));
            CHECK(signed_volume(*m) > 0);
        }
        CHECK(raw.faces == smooth.faces);
        // volume of the raw surface: corners cut, so a little below the voxel volume
        const double vr = signed_volume(raw), vs = signed_volume(smooth);
        const auto [miss0, extra0] = inside_mismatch(raw, v);
        const auto [miss1, extra1] = inside_mismatch(smooth, v);
        WARN(e.name << ": " << v.size() << " voxels (" << v.volume() << " mm^3); raw mesh " << raw.num_faces() << " faces, volume "
                    << vr << " (ratio " << vr / v.volume() << "), smoothed volume " << vs << " (ratio " << vs / v.volume()
                    << "); centres misclassified: raw " << miss0 << " missing + " << extra0 << " extra, smoothed " << miss1
                    << " missing + " << extra1 << " extra (" << 100.0 * static_cast<double>(miss1 + extra1) / static_cast<double>(v.size())
                    << "%)");
        CHECK(miss0 == 0);
        CHECK(extra0 == 0);
        CHECK(static_cast<double>(miss1 + extra1) < 0.01 * static_cast<double>(v.size()));  // measured 0
        CHECK(vr == Approx(v.volume()).epsilon(0.1));
        CHECK(vs == Approx(vr).epsilon(0.05));
    }
}

TEST_CASE("mesh_voxels: thin and random sets, centres inside the mesh before and after smoothing", "[surface_pattern][fabricate]") {
    // the one-voxel shell itself (no thickening) and random sets full of single voxels: the raw
    // surface still separates solid and empty centres exactly; smoothing moves thin features most
    const shell_list& s = sphere_shell(64);
    const voxel_set thin = make_voxel_set(s.geometry, s.voxels);
    std::int64_t miss_raw = 0, miss_smooth = 0, total = 0;
    {
        const auto [m0, e0] = inside_mismatch(mesh_voxels(thin, 0), thin);
        const triangle_mesh sm = mesh_voxels(thin, 10);
        CHECK(is_watertight(sm));
        const auto [m1, e1] = inside_mismatch(sm, thin);
        WARN("one-voxel sphere shell: " << thin.size() << " voxels; centres misclassified raw " << m0 << " + " << e0
                                        << ", smoothed (10 pairs) " << m1 << " missing + " << e1 << " extra ("
                                        << 100.0 * static_cast<double>(m1 + e1) / static_cast<double>(thin.size()) << "%)");
        CHECK(m0 + e0 == 0);
        CHECK(static_cast<double>(m1 + e1) < 0.01 * static_cast<double>(thin.size()));  // measured 0
    }
    const grid_geometry g{ivec3(24), vec3(0.0), vec3(0.5)};
    for (int seed = 0; seed < 5; ++seed) {
        counter_rng rng(41, static_cast<std::uint64_t>(seed));
        std::vector<ivec3> vox;
        for (int z = 2; z < 22; ++z)
            for (int y = 2; y < 22; ++y)
                for (int x = 2; x < 22; ++x)
                    if (rng.uniform() < 0.3) vox.push_back({x, y, z});
        const voxel_set v = make_voxel_set(g, vox);
        const auto [m0, e0] = inside_mismatch(mesh_voxels(v, 0), v);
        const auto [m1, e1] = inside_mismatch(mesh_voxels(v, 10), v);
        miss_raw += m0 + e0, miss_smooth += m1 + e1, total += static_cast<std::int64_t>(v.size());
    }
    WARN("random sets (density 0.3): " << total << " voxels; centres misclassified raw " << miss_raw << ", smoothed (10 pairs) "
                                       << miss_smooth << " (" << 100.0 * static_cast<double>(miss_smooth) / static_cast<double>(total)
                                       << "%)");
    CHECK(miss_raw == 0);
    CHECK(static_cast<double>(miss_smooth) < 0.01 * static_cast<double>(total));  // measured 0
}

TEST_CASE("mesh_voxels: pieces follow the Freudenthal diagonals, not 26-connectivity", "[surface_pattern][fabricate]") {
    const grid_geometry g{ivec3(12), vec3(0.0), vec3(0.5)};
    struct pair_case {
        ivec3 other;
        int pieces;
    };
    // offsets from (5, 5, 5): all 26-neighbours; joined iff the offset or its negative is in {0,1}^3
    for (const pair_case& c : {pair_case{{6, 6, 5}, 1}, pair_case{{6, 4, 5}, 2}, pair_case{{4, 4, 5}, 1}, pair_case{{6, 6, 6}, 1},
                               pair_case{{4, 4, 4}, 1}, pair_case{{6, 6, 4}, 2}, pair_case{{4, 6, 6}, 2}, pair_case{{6, 5, 5}, 1},
                               pair_case{{5, 6, 6}, 1}, pair_case{{5, 4, 6}, 2}}) {
        const voxel_set v = make_voxel_set(g, {ivec3(5), c.other});
        INFO("voxel (5,5,5) and (" << c.other.x << "," << c.other.y << "," << c.other.z << ")");
        CHECK(set_components(v).count == 1);  // 26-connected in every case
        CHECK(set_components(v, mesh_connectivity{}).count == c.pieces);
        const triangle_mesh m = mesh_voxels(v, 0);
        const auto topo = analyze_topology(m);
        CHECK(topo.is_watertight());
        CHECK(topo.components == static_cast<std::size_t>(c.pieces));
        CHECK(analyze_topology(mesh_voxels(v, 5)).components == static_cast<std::size_t>(c.pieces));
    }
    // random sets: surfaces and pieces equal the dense oracle; 26 <= mesh <= 6 component counts
    int differs26 = 0, differs6 = 0;
    for (int seed = 0; seed < 30; ++seed) {
        counter_rng rng(99, static_cast<std::uint64_t>(seed));
        std::vector<ivec3> vox;
        const double density = 0.15 + 0.02 * seed;
        for (int z = 1; z < 11; ++z)
            for (int y = 1; y < 11; ++y)
                for (int x = 1; x < 11; ++x)
                    if (rng.uniform() < density) vox.push_back({x, y, z});
        const voxel_set v = make_voxel_set(g, vox);
        const topology_oracle o = freudenthal_oracle(v);
        const int c6 = set_components(v, connectivity::c6{}).count, c26 = set_components(v).count;
        const int cm = set_components(v, mesh_connectivity{}).count;
        INFO("seed " << seed << ": " << v.size() << " voxels, c6 " << c6 << " c26 " << c26 << " mesh " << cm);
        CHECK(cm == o.solid_pieces);
        CHECK(c26 <= cm);
        CHECK(cm <= c6);
        differs26 += c26 != cm, differs6 += c6 != cm;
        const triangle_mesh m = mesh_voxels(v, 3);
        const auto topo = analyze_topology(m);
        CHECK(topo.is_watertight());
        CHECK(topo.components == static_cast<std::size_t>(o.surfaces));
    }
    CHECK(differs26 > 0);  // the random sets do show the difference
    CHECK(differs6 > 0);
}

TEST_CASE("set_components matches voxel/components.hpp on random sets", "[surface_pattern][fabricate]") {
    const grid_geometry g{ivec3(17, 9, 13), vec3(1.0), vec3(0.3)};
    for (int seed = 0; seed < 10; ++seed) {
        counter_rng rng(5, static_cast<std::uint64_t>(seed));
        voxel_grid<std::uint8_t> dense(g, 0);
        std::vector<ivec3> vox;
        for (std::uint64_t i = 0; i < g.count(); ++i)
            if (rng.uniform() < 0.25) vox.push_back(g.coord(i)), dense.set(g.coord(i), 1);
        const voxel_set v = make_voxel_set(g, vox);
        const auto a = set_components(v, connectivity::c26{});
        const auto b = label_components<connectivity::c26>(dense, [](std::uint8_t x) { return x != 0; });
        REQUIRE(a.count == b.count);
        CHECK(a.sizes == b.sizes);
        for (std::size_t i = 0; i < v.size(); ++i) REQUIRE(a.labels[i] == b.labels.get(v.voxels[i]));
        const auto a6 = set_components(v, connectivity::c6{});
        const auto b6 = label_components<connectivity::c6>(dense, [](std::uint8_t x) { return x != 0; });
        CHECK(a6.count == b6.count);
        CHECK(a6.sizes == b6.sizes);
    }
}

TEST_CASE("fabrication is deterministic for 1 and 2 threads; bad voxel sets throw", "[surface_pattern][fabricate]") {
    const shell_list& s = sphere_shell(64);
    std::vector<std::uint8_t> pattern(s.voxels.size());
    for (std::size_t i = 0; i < pattern.size(); ++i) pattern[i] = (s.voxels[i].x / 4 + s.voxels[i].y / 4) % 2 == 0 ? 1 : 0;
    auto run = [&](unsigned threads) {
        set_num_threads(threads);
        std::vector<std::uint8_t> p = pattern;
        (void)remove_specks(s.geometry, s.voxels, p, 1.5);
        voxel_set v = thicken_inward(s.geometry, s.voxels, s.normals, p, 1.8);
        triangle_mesh m = mesh_voxels(v, 10);
        set_num_threads(0);
        return std::pair{v, m};
    };
    const auto one = run(1), two = run(2);
    CHECK(one.first == two.first);
    CHECK(one.second == two.second);
    CHECK(is_watertight(one.second));

    const grid_geometry g{ivec3(8), vec3(0.0), vec3(1.0)};
    CHECK(mesh_voxels(voxel_set{g, {}}).empty());
    CHECK_THROWS_AS(mesh_voxels(voxel_set{g, {{1, 1, 1}, {0, 1, 1}}}), invalid_input);  // not sorted
    CHECK_THROWS_AS(mesh_voxels(voxel_set{g, {{1, 1, 1}, {1, 1, 1}}}), invalid_input);  // repeated
    CHECK_THROWS_AS(mesh_voxels(voxel_set{g, {{1, 1, 8}}}), invalid_input);             // outside
    CHECK_THROWS_AS(mesh_voxels(voxel_set{g, {{1, 1, 1}}}, -1), invalid_input);
    CHECK_THROWS_AS(mesh_voxels(voxel_set{g, {{1, 1, 1}}}, taubin_options{.iterations = 1, .lambda = 0.5, .mu = -0.2}), invalid_input);
    CHECK_THROWS_AS(set_components(voxel_set{g, {{2, 1, 1}, {1, 1, 1}}}), invalid_input);
    CHECK_THROWS_AS(make_voxel_set(g, {{1, 1, -1}}), invalid_input);
    // a voxel on the grid border still meshes (the sampled box may leave the grid)
    const triangle_mesh corner = mesh_voxels(make_voxel_set(g, {{0, 0, 0}, {7, 7, 7}}), 2);
    CHECK(is_watertight(corner));
    CHECK(analyze_topology(corner).components == 2);
}

TEST_CASE("join_diagonal_contacts: voxels touching along an edge the mesh does not follow become one printed piece",
          "[surface_pattern][fabricate]") {
    grid_geometry g;
    g.dims = {8, 8, 8};
    g.spacing = vec3(1.0);
    for (const ivec3 o : {ivec3(1, -1, 0), ivec3(1, 1, -1), ivec3(-1, 1, 1)}) {
        INFO(o.x << " " << o.y << " " << o.z);
        fabsynth::surface_pattern::voxel_set s = fabsynth::surface_pattern::make_voxel_set(g, {ivec3(3, 3, 3), ivec3(3, 3, 3) + o});
        CHECK(fabsynth::surface_pattern::set_components(s).count == 1);
        CHECK(fabsynth::surface_pattern::set_components(s, fabsynth::surface_pattern::mesh_connectivity{}).count == 2);
        CHECK(fabsynth::surface_pattern::join_diagonal_contacts(s) == 1);
        CHECK(fabsynth::surface_pattern::set_components(s, fabsynth::surface_pattern::mesh_connectivity{}).count == 1);
        CHECK(analyze_topology(fabsynth::surface_pattern::mesh_voxels(s, 0)).is_watertight());
    }
    fabsynth::surface_pattern::voxel_set joined = fabsynth::surface_pattern::make_voxel_set(g, {ivec3(3, 3, 3), ivec3(4, 4, 3)});  // along a Freudenthal diagonal: nothing to do
    CHECK(fabsynth::surface_pattern::join_diagonal_contacts(joined) == 0);
}
