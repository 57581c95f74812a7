// Oracle: the published result of Dong, Tang & Zhao, "A 149 line homogenization code for
// three-dimensional cellular materials written in MATLAB" (J. Eng. Mater. Technol. 2019), as
// given in the README of the authors' code: the 'grid' (simple cubic) wireframe, unit cell of
// side 1, 40 voxels per axis, strut radius 0.1, lambda = 115.4, mu = 79.6 gives density 8.5% and
// C11 = 7.1876, C12 = 0.3875, C44 = 0.1489 (all other entries 0 to 4 decimals).
// Their voxel rule: a voxel is solid iff its centre is within the radius of a strut segment.
#include <catch2/catch.hpp>

#include <fabsynth/fem/homogenization.hpp>

#include <algorithm>
#include <array>
#include <vector>

using namespace fabsynth;

namespace {

double segment_distance(const vec3& p, const vec3& a, const vec3& b) {
    const vec3 ab = b - a;
    const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
    return glm::length(p - (a + t * ab));
}

}  // namespace

TEST_CASE("simple cubic lattice at 40^3 reproduces the published homo3D tensor", "[fem][homogenization][slow]") {
    const int n = 40;
    const double radius = 0.1;
    // The 12 edges of the unit cube (the 'grid' wireframe).
    const std::array<vec3, 8> v{vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1),
                                vec3(1, 0, 1), vec3(0, 1, 1), vec3(1, 1, 0), vec3(1, 1, 1)};
    const int struts[12][2] = {{0, 1}, {0, 2}, {0, 3}, {3, 4}, {3, 5}, {2, 6}, {2, 5}, {5, 7}, {1, 6}, {1, 4}, {4, 7}, {6, 7}};
    std::vector<double> density(static_cast<std::size_t>(n * n * n), 0.0);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const vec3 c((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n);
                for (const auto& s : struts)
                    if (segment_distance(c, v[static_cast<std::size_t>(s[0])], v[static_cast<std::size_t>(s[1])]) <= radius) {
                        density[static_cast<std::size_t>(i + n * (j + n * k))] = 1.0;
                        break;
                    }
            }
    const double lambda = 115.4, mu = 79.6;  // the values the published run used
    const fem::isotropic_material material{mu * (3 * lambda + 2 * mu) / (lambda + mu), lambda / (2 * (lambda + mu))};
    const fem::density_view grid(ivec3(n), vec3(1.0 / n), density);
    fem::homogenization_options opt;
    opt.solver.tolerance = 1e-10;
    const auto h = fem::homogenize(grid, material, opt);

    CHECK(h.volume_fraction == Approx(0.085).margin(0.0005));
    CHECK(h.C(0, 0) == Approx(7.1876).margin(0.0001));
    CHECK(h.C(0, 1) == Approx(0.3875).margin(0.0001));
    CHECK(h.C(3, 3) == Approx(0.1489).margin(0.0001));
    for (int a = 0; a < 3; ++a) {
        CHECK(h.C(a, a) == Approx(h.C(0, 0)).epsilon(1e-9));
        CHECK(h.C(a + 3, a + 3) == Approx(h.C(3, 3)).epsilon(1e-9));
    }
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) {
            const bool nonzero = (r < 3 && c < 3) || r == c;
            if (!nonzero) CHECK(std::abs(h.C(r, c)) < 1e-4);
        }
}
