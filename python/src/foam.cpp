// SPDX-License-Identifier: MIT
// fabsynth.foam: foam/evaluator.hpp (voronoi_foam), foam/frame.hpp (a foam filling a closed mesh
// with its surface frame), foam/slice_stack.hpp, foam/beams.hpp and the shipped elasticity fit
// (foam/elasticity.hpp). The foam's options are foam_slicer's: density or density_x, radius, cell,
// seed, elasticity (the values are E/Es, mapped to densities by the fit at the radius).
#include "common.hpp"

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/foam.hpp>
#include <fabsynth/geometry/distance.hpp>

#include <algorithm>

namespace fabsynth::python {
namespace {

using namespace fabsynth::foam;
using value_field = variant_field<constant_field, linear_field>;
using density_field = variant_field<value_field, elasticity_density_field<value_field>>;
using foam_type = voronoi_foam<density_field, constant_field>;

struct foam_params {
    double density = 0.2;
    std::vector<double> density_x;
    double radius = 0.25;
    double cell = 2.0;
    std::uint64_t seed = 1;
    bool elasticity = false;
};

/// A foam and the parameters it was made from (for pickling: workers rebuild it from them).
class py_foam {
public:
    explicit py_foam(foam_params p) : p_(std::move(p)), foam_(make(p_)) {}
    [[nodiscard]] const foam_params& params() const noexcept { return p_; }
    [[nodiscard]] const foam_type& foam() const noexcept { return foam_; }

private:
    static foam_type make(const foam_params& p) {
        value_field values{constant_field{p.density}};
        double lo = p.density, hi = p.density;
        if (!p.density_x.empty()) {
            if (p.density_x.size() != 4) throw invalid_input("density_x must be (rho0, rho1, x0, x1)");
            const linear_field f{.axis = 0, .v0 = p.density_x[0], .v1 = p.density_x[1], .x0 = p.density_x[2], .x1 = p.density_x[3]};
            if (!(f.x0 != f.x1)) throw invalid_input("density_x: x0 and x1 must differ");
            values.field = f, lo = std::min(f.v0, f.v1), hi = std::max(f.v0, f.v1);
        }
        density_field rho{values};
        if (p.elasticity) rho.field = elasticity_density_field<value_field>(values, p.radius, lo, hi);
        return foam_type(rho, constant_field{p.radius}, {.cell = p.cell, .seed = p.seed});
    }
    foam_params p_;
    foam_type foam_;
};

/// A foam inside a closed mesh, with its frame (foam/frame.hpp), and what it was made from.
class py_mesh_foam {
public:
    py_mesh_foam(std::shared_ptr<const py_foam> foam, triangle_mesh mesh, double frame, std::vector<cut_plane> cuts)
        : foam_(std::move(foam)), distance_(std::make_unique<mesh_distance>(std::move(mesh))),
          framed_(std::make_unique<framed_foam<foam_type>>(foam_->foam(), *distance_, frame_options{.thickness = frame, .cuts = std::move(cuts)})) {}
    [[nodiscard]] const py_foam& foam() const noexcept { return *foam_; }
    [[nodiscard]] std::shared_ptr<const py_foam> foam_ptr() const noexcept { return foam_; }
    [[nodiscard]] const triangle_mesh& mesh() const noexcept { return distance_->mesh(); }
    [[nodiscard]] const framed_foam<foam_type>& object() const noexcept { return *framed_; }

private:
    std::shared_ptr<const py_foam> foam_;
    std::unique_ptr<mesh_distance> distance_;  // on the heap: framed_foam keeps a reference
    std::unique_ptr<framed_foam<foam_type>> framed_;
};

slice_options slicing(int supersample) {
    if (supersample < 1 || supersample > 16) throw invalid_input("supersample must be in [1, 16], got " + std::to_string(supersample));
    return {.supersample = supersample};
}

/// Slices at the heights zs through any object with for_each_slice (both foams), as a list of arrays.
template <class Object>
py::list slices_of(const Object& obj, const std::vector<double>& zs, const std::vector<double>& region, double pixel, int supersample,
                   const py::object& progress) {
    const box2 r = box2_from(region, "region");
    const slice_options so = slicing(supersample);
    for (std::size_t k = 1; k < zs.size(); ++k)
        if (!(zs[k] > zs[k - 1])) throw invalid_input("slice heights must increase");
    std::vector<image8> images(zs.size());
    released(progress, [&](python_progress& p) {
        obj.for_each_slice(zs, r, pixel, [&](std::size_t k, image8& img) {
            images[k] = std::move(img);
            report_progress(p, static_cast<double>(k + 1) / static_cast<double>(zs.size()), "slices");
        }, so);
    });
    py::list out;
    for (image8& img : images) out.append(image_to(std::move(img)));
    return out;
}

template <class Object>
py::array_t<bool> contains_of(const Object& obj, const darray& points) {
    if (points.ndim() != 2 || points.shape(1) != 3) throw invalid_input("points must be an n x 3 array (mm)");
    // the C-contiguous float64 buffer is read in place as vec3s (three doubles, no padding), and the
    // answers written straight into the bool array (one byte each): no copy of 10^6 points
    static_assert(sizeof(vec3) == 3 * sizeof(double) && sizeof(bool) == 1);
    const std::span<const vec3> pts(reinterpret_cast<const vec3*>(points.data()), static_cast<std::size_t>(points.shape(0)));
    py::array_t<bool> out(static_cast<py::ssize_t>(pts.size()));
    const std::span<std::uint8_t> o(reinterpret_cast<std::uint8_t*>(out.mutable_data()), pts.size());
    py::gil_scoped_release nogil;
    if constexpr (std::is_same_v<Object, foam_type>) {
        obj.contains(pts, o);  // the batch query: block by block, in parallel; writes 0 or 1
    } else {
        parallel_for(0, pts.size(), [&](std::size_t i) { o[i] = obj.contains(pts[i]) ? 1 : 0; }, {.grain = 1024});
    }
    return out;
}

py::dict params_dict(const foam_params& p) {  // the keyword arguments of Foam(...)
    py::dict d;
    d["density"] = p.density;
    d["density_x"] = p.density_x.empty() ? py::object(py::none()) : py::object(py::cast(p.density_x));
    d["radius"] = p.radius, d["cell"] = p.cell, d["seed"] = p.seed, d["elasticity"] = p.elasticity;
    return d;
}

foam_params params_from(double density, const std::optional<std::vector<double>>& density_x, double radius, double cell, std::uint64_t seed, bool elasticity) {
    return {.density = density, .density_x = density_x.value_or(std::vector<double>{}), .radius = radius, .cell = cell, .seed = seed, .elasticity = elasticity};
}

py::dict plan_dict(const box3& box, double pixel, double layer, int count) {
    const slice_stack st = plan_slice_stack(box, pixel, layer, count);
    py::dict d;
    d["region"] = py::make_tuple(st.region.lo.x, st.region.lo.y, st.region.hi.x, st.region.hi.y);
    d["pixel"] = st.pixel, d["layer"] = st.layer, d["z0"] = st.z0, d["layers"] = st.layers, d["selected"] = st.selected;
    return d;
}

constexpr const char* slice_doc =
    "Slice at height z (mm) over region (x0, y0, x1, y1) (mm) with square pixels of side `pixel` (mm).\n\n"
    "Returns a uint8 array (h, w), h = ceil((y1 - y0) / pixel), w = ceil((x1 - x0) / pixel); pixel [j, i] is\n"
    "centred at (x0 + (i + 1/2) pixel, y0 + (j + 1/2) pixel, z), so row 0 is at y0. 255 = solid, 0 = empty;\n"
    "with supersample s > 1, 255 x the covered fraction of s x s samples.";
constexpr const char* slices_doc =
    "Slices at the increasing heights zs (mm), as slice() gives each, in one pass that builds the foam's\n"
    "edges once per slab: a list of uint8 arrays. progress(fraction, stage) is called as slices finish;\n"
    "returning False cancels (fabsynth.Cancelled), Ctrl-C raises KeyboardInterrupt.";

}  // namespace

void bind_foam(py::module_& m) {
    py::class_<py_foam, std::shared_ptr<py_foam>>(m, "Foam",
        "A procedural Voronoi foam (Martinez et al. 2016) filling all of space: beams of radius `radius` (mm)\n"
        "along the Voronoi edges of jittered seeds of density `density` (seeds/mm^3) or, with density_x =\n"
        "(rho0, rho1, x0, x1), a density linear in x between x0 and x1 (constant outside). cell: coarse cell\n"
        "side (mm, >= radius), seed: random seed. elasticity=True: the density values are relative Young's\n"
        "moduli E/Es, mapped to densities by the shipped fit at `radius` (paper §4.2). The options and results\n"
        "are foam_slicer's.")
        .def(py::init([](double density, std::optional<std::vector<double>> density_x, double radius, double cell, std::uint64_t seed, bool elasticity) {
                 return std::make_shared<py_foam>(params_from(density, density_x, radius, cell, seed, elasticity));
             }),
             py::kw_only(), py::arg("density") = 0.2, py::arg("density_x") = py::none(), py::arg("radius") = 0.25, py::arg("cell") = 2.0,
             py::arg("seed") = 1, py::arg("elasticity") = false)
        .def_property_readonly("params", [](const py_foam& f) { return params_dict(f.params()); }, "The keyword arguments the foam was made with (Foam(**params) makes it again).")
        .def("contains", [](const py_foam& f, const darray& points) { return contains_of(f.foam(), points); }, py::arg("points"),
             "Solid (True) or empty at each of the n x 3 points (mm): a bool array of n.")
        .def("slice", [](const py_foam& f, double z, const std::vector<double>& region, double pixel, int supersample) {
            const box2 r = box2_from(region, "region");
            const slice_options so = slicing(supersample);
            image8 img;
            {
                py::gil_scoped_release nogil;
                img = f.foam().slice(z, r, pixel, so);
            }
            return image_to(std::move(img));
        }, py::arg("z"), py::arg("region"), py::arg("pixel"), py::arg("supersample") = 1, slice_doc)
        .def("_slices", [](const py_foam& f, const std::vector<double>& zs, const std::vector<double>& region, double pixel, int supersample, const py::object& progress) {
            return slices_of(f.foam(), zs, region, pixel, supersample, progress);
        }, py::arg("zs"), py::arg("region"), py::arg("pixel"), py::arg("supersample") = 1, py::arg("progress") = py::none(), slices_doc)
        .def("seeds", [](const py_foam& f, const std::vector<double>& box) {
            const box3 b = box3_from(box, "box");
            std::vector<vec3> s;
            {
                py::gil_scoped_release nogil;
                s = f.foam().seeds().seeds_in_box(b);
            }
            return points_to(s);
        }, py::arg("box"), "Every seed in box (x0, y0, z0, x1, y1, z1) (mm): an n x 3 float64 array, as foam_slicer seeds writes it.")
        .def("beams", [](const py_foam& f, const std::vector<double>& box) {
            const box3 b = box3_from(box, "box");
            beam_network net;
            {
                py::gil_scoped_release nogil;
                net = extract_beams(f.foam(), b);
            }
            py::array_t<std::int64_t> edges({static_cast<py::ssize_t>(net.edges.size()), py::ssize_t{2}});
            for (std::size_t i = 0; i < net.edges.size(); ++i) edges.mutable_data()[2 * i] = net.edges[i][0], edges.mutable_data()[2 * i + 1] = net.edges[i][1];
            py::dict d;
            d["nodes"] = points_to(net.nodes), d["edges"] = edges, d["radii"] = py::array_t<double>(static_cast<py::ssize_t>(net.radii.size()), net.radii.data());
            return d;
        }, py::arg("box"),
             "The beam network clipped to box (x0, y0, z0, x1, y1, z1) (mm): dict(nodes=n x 3 float64 mm,\n"
             "edges=m x 2 int64 node indices, radii=m float64 mm).")
        ;  // pickled by fabsynth/foam.py (from `params`)

    py::class_<py_mesh_foam, std::shared_ptr<py_mesh_foam>>(m, "MeshFoam",
        "A foam inside a closed mesh with a frame (a shell of `frame` mm along the surface, 0 = none), open\n"
        "where cut planes (point, normal) remove what lies on their normal's side: foam_slicer slice's object.")
        .def(py::init([](const std::shared_ptr<const py_foam>& foam, const darray& V, const py::array& F, double frame, const std::vector<std::pair<std::vector<double>, std::vector<double>>>& cuts) {
                 std::vector<cut_plane> planes;
                 for (const auto& [p, n] : cuts) {
                     if (p.size() != 3 || n.size() != 3) throw invalid_input("a cut is (point, normal), each 3 numbers (mm)");
                     planes.push_back({{p[0], p[1], p[2]}, {n[0], n[1], n[2]}});
                 }
                 return std::make_shared<py_mesh_foam>(foam, mesh_from(V, F), frame, std::move(planes));
             }),
             py::arg("foam"), py::arg("V"), py::arg("F"), py::kw_only(), py::arg("frame") = 0.5,
             py::arg("cuts") = std::vector<std::pair<std::vector<double>, std::vector<double>>>{})
        .def_property_readonly("foam", &py_mesh_foam::foam_ptr)
        .def_property_readonly("frame", [](const py_mesh_foam& o) { return o.object().options().thickness; })
        .def_property_readonly("mesh", [](const py_mesh_foam& o) { return mesh_to(o.mesh()); }, "(V, F) of the closed mesh.")
        .def_property_readonly("cuts", [](const py_mesh_foam& o) {
            py::list cuts;
            for (const cut_plane& c : o.object().options().cuts)
                cuts.append(py::make_tuple(py::make_tuple(c.point.x, c.point.y, c.point.z), py::make_tuple(c.normal.x, c.normal.y, c.normal.z)));
            return cuts;
        }, "The cut planes as (point, unit normal) pairs.")
        .def("contains", [](const py_mesh_foam& o, const darray& points) { return contains_of(o.object(), points); }, py::arg("points"),
             "Solid (True: frame or foam inside the mesh and its cuts) at each of the n x 3 points (mm).")
        .def("_slices", [](const py_mesh_foam& o, const std::vector<double>& zs, const std::vector<double>& region, double pixel, int supersample, const py::object& progress) {
            return slices_of(o.object(), zs, region, pixel, supersample, progress);
        }, py::arg("zs"), py::arg("region"), py::arg("pixel"), py::arg("supersample") = 1, py::arg("progress") = py::none(), slices_doc)
        .def("plan", [](const py_mesh_foam& o, double pixel, double layer, int count) { return plan_dict(bounding_box(o.mesh()), pixel, layer, count); },
             py::arg("pixel"), py::arg("layer") = 0.0, py::arg("count") = 0,
             "The slice stack through the mesh's bounding box, as foam_slicer plans it (see fabsynth.foam.plan).")
        ;  // pickled by fabsynth/foam.py (from foam.params, mesh, frame, cuts)

    m.def("plan", [](const std::vector<double>& box, double pixel, double layer, int count) { return plan_dict(box3_from(box, "box"), pixel, layer, count); },
          py::arg("box"), py::arg("pixel"), py::arg("layer") = 0.0, py::arg("count") = 0,
          "Plans a slice stack through box (x0, y0, z0, x1, y1, z1) (mm), foam/slice_stack.hpp: dict(region=(x0, y0,\n"
          "x1, y1) mm (the box grown by one pixel), pixel (mm), layer (mm; 0 = the pixel size), z0 (mm), layers,\n"
          "selected=the layer indices to slice: all of them, or `count` evenly spaced). Layer k is sliced at\n"
          "z0 + (k + 1/2) layer.");
    m.def("elasticity", [](const darray& density, double radius) {
        const elasticity_polynomial P = fitted_elasticity();
        darray out(std::vector<py::ssize_t>(density.shape(), density.shape() + density.ndim()));
        for (py::ssize_t i = 0; i < density.size(); ++i) out.mutable_data()[i] = P(density.data()[i], radius);
        return out;
    }, py::arg("density"), py::arg("radius"),
          "The shipped fit E/Es = P(rho, tau) (foam/elasticity_fit.hpp, paper §4.2) at densities rho (seeds/mm^3,\n"
          "any array shape) and radius tau (mm): relative Young's moduli, same shape.");
    m.def("density_for_elasticity", [](const darray& e, double radius) {
        darray out(std::vector<py::ssize_t>(e.shape(), e.shape() + e.ndim()));
        for (py::ssize_t i = 0; i < e.size(); ++i) out.mutable_data()[i] = inverse_fitted_elasticity(e.data()[i], radius).density;
        return out;
    }, py::arg("e"), py::arg("radius"),
          "Densities (seeds/mm^3) whose fitted modulus at radius tau (mm, inside the fit's radii) is E/Es = e (any\n"
          "array shape); targets outside reachable_elasticity(radius) are clamped to its ends.");
    m.def("reachable_elasticity", [](double radius) {
        const auto [lo, hi] = fitted_density_range(radius);
        const elasticity_polynomial P = fitted_elasticity();
        return py::make_tuple(P(lo, radius), P(hi, radius));
    }, py::arg("radius"), "(E/Es at the lowest, at the highest fitted density) at radius tau (mm).");
}

}  // namespace fabsynth::python
