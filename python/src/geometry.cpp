// SPDX-License-Identifier: MIT
// fabsynth.geometry: geometry/simplify.hpp and geometry/hausdorff.hpp on (V, F) meshes.
#include "common.hpp"

#include <fabsynth/geometry/hausdorff.hpp>
#include <fabsynth/geometry/simplify.hpp>

namespace fabsynth::python {

void bind_geometry(py::module_& m) {
    m.def("simplify_mesh", [](const darray& V, const py::array& F, double tolerance, int attempts) {
        const triangle_mesh mesh = mesh_from(V, F);
        simplify_report rep;
        triangle_mesh out;
        {
            py::gil_scoped_release nogil;
            out = simplify_mesh(mesh, {.tolerance = tolerance, .attempts = attempts}, &rep);
        }
        py::dict report;
        report["raw_triangles"] = rep.raw_faces, report["triangles"] = rep.faces, report["simplified"] = rep.simplified;
        report["tolerance_mm"] = rep.tolerance, report["hausdorff_mm"] = rep.hausdorff.upper, report["hausdorff_measured_mm"] = rep.hausdorff.lower;
        report["runs"] = rep.attempts, report["warning"] = rep.warning;
        py::array_t<std::int64_t> source(static_cast<py::ssize_t>(out.vertices.size()));
        std::int64_t* s = source.mutable_data();
        for (std::size_t i = 0; i < out.vertices.size(); ++i) s[i] = rep.source.empty() ? static_cast<std::int64_t>(i) : rep.source[i];
        const py::tuple vf = mesh_to(out);
        return py::make_tuple(vf[0], vf[1], source, report);
    }, py::arg("V"), py::arg("F"), py::arg("tolerance") = 0.05, py::arg("attempts") = 4,
          "Fewer triangles, the same solid (geometry/simplify.hpp): the result keeps the topology (watertightness,\n"
          "components, boundary loops, genus), has no self-intersection, and lies within `tolerance` mm of (V, F)\n"
          "both ways (a certified Hausdorff bound). Every result vertex is an input vertex at its exact position.\n\n"
          "Returns (V2, F2, source, report): source[i] is the input vertex of result vertex i (to carry colours\n"
          "or other per-vertex data over); report has raw_triangles, triangles, simplified, tolerance_mm,\n"
          "hausdorff_mm (bound), hausdorff_measured_mm, runs, warning. When no run passes the checks, (V, F) is\n"
          "returned with simplified False and the reason in warning. Raises InvalidInput for tolerance <= 0,\n"
          "attempts < 1 or a malformed mesh.");
    m.def("hausdorff_distance", [](const darray& Va, const py::array& Fa, const darray& Vb, const py::array& Fb, double precision) {
        const triangle_mesh a = mesh_from(Va, Fa), b = mesh_from(Vb, Fb);
        hausdorff_interval h;
        {
            py::gil_scoped_release nogil;
            h = hausdorff_distance(a, b, {.precision = precision});
        }
        return py::make_tuple(h.lower, h.upper);
    }, py::arg("Va"), py::arg("Fa"), py::arg("Vb"), py::arg("Fb"), py::arg("precision") = 0.01,
          "Two-sided Hausdorff distance of two triangle meshes as (lower, upper), mm: a distance attained at a sample\n"
          "and a certified bound, upper - lower <= precision (geometry/hausdorff.hpp).");
}

}  // namespace fabsynth::python
