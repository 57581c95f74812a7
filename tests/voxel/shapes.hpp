#pragma once
// Test helpers for the voxel and marching-cubes tests: mesh loading with scale normalisation and
// independent geometric oracles (written separately from the library code they check).
#include <fabsynth/geometry/mesh.hpp>
#include <fabsynth/io/mesh.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace fabsynth::test {

/// Reads data/meshes/<name> and scales it so its longest side is `size` mm, centred at the origin.
inline triangle_mesh load_normalized(const std::string& name, double size = 100.0) {
    triangle_mesh m = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/" + name);
    const box3 b = bounding_box(m);
    const vec3 ext = b.size();
    const double s = size / std::max({ext.x, ext.y, ext.z});
    for (auto& v : m.vertices) v = (v - b.center()) * s;
    return m;
}

/// Independent triangle/box test: clip the triangle polygon by the 6 half-spaces of the box grown by
/// `tol` on each side (Sutherland-Hodgman) and report whether anything is left. Uses a different
/// method from the separating-axis test in the library.
inline bool clip_intersects(const box3& box, const vec3& a, const vec3& b, const vec3& c, double tol) {
    std::vector<vec3> poly{a, b, c};
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            std::vector<vec3> out;
            const double lim = side == 0 ? box.lo[axis] - tol : box.hi[axis] + tol;
            auto in = [&](const vec3& p) { return side == 0 ? p[axis] >= lim : p[axis] <= lim; };
            for (std::size_t i = 0; i < poly.size(); ++i) {
                const vec3 p = poly[i], q = poly[(i + 1) % poly.size()];
                if (in(p)) out.push_back(p);
                if (in(p) != in(q)) {
                    const double t = (lim - p[axis]) / (q[axis] - p[axis]);
                    vec3 x = p + t * (q - p);
                    x[axis] = lim;
                    out.push_back(x);
                }
            }
            poly = std::move(out);
            if (poly.empty()) return false;
        }
    }
    return true;
}

/// Generalised winding number of a closed mesh at p (sum of signed solid angles / 4 pi; Van
/// Oosterom & Strackee 1983 formula for the solid angle of a triangle).
inline double winding_number(const triangle_mesh& m, const vec3& p) {
    double w = 0;
    for (const auto& t : m.faces) {
        const vec3 a = m.vertices[t[0]] - p, b = m.vertices[t[1]] - p, c = m.vertices[t[2]] - p;
        const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
        const double num = glm::dot(a, glm::cross(b, c));
        const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
        w += 2.0 * std::atan2(num, den);
    }
    return w / (4.0 * std::numbers::pi);
}

}  // namespace fabsynth::test
