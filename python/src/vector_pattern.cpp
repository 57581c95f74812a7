// SPDX-License-Identifier: MIT
// fabsynth.vector_pattern: exemplars from SVG (vector_pattern/exemplar.hpp) and make_pattern, the
// pipeline in one call (vector_pattern/pipeline.hpp), along a line, a circle, a planar curve, in a
// rectangle, along a curve in space or on a surface (embossed or carved).
#include "common.hpp"

#include <fabsynth/geometry/curve.hpp>
#include <fabsynth/geometry/space_curve.hpp>
#include <fabsynth/io/svg.hpp>
#include <fabsynth/vector_pattern.hpp>

#include <filesystem>

namespace fabsynth::python {
namespace {

namespace vp = fabsynth::vector_pattern;

}  // namespace

void bind_vector_pattern(py::module_& m) {
    py::class_<vp::exemplar>(m, "Exemplar", "A vector exemplar: filled shapes forming a band along x (mm).")
        .def_property_readonly("height", &vp::exemplar::height, "Height of the band (the SVG's units).");
    m.def("exemplar_from_svg", [](const std::filesystem::path& path) {
        const vp::exemplar ex = vp::exemplar_from_svg(io::read_svg(path));
        if (!(ex.height() > 0.0)) throw invalid_input(path.string() + ": the exemplar has no height");
        return ex;
    }, py::arg("path"), "The exemplar of an SVG drawing's filled shapes (a band along x), as curve_patterns reads it.");

    py::class_<vp::pattern_result, std::shared_ptr<vp::pattern_result>>(m, "PatternResult", "What make_pattern returns.")
        .def_property_readonly("drawn", [](const vp::pattern_result& r) { return polygons_to(r.drawn); },
                               "The drawing in the plane (mm, y down as in SVG): [(outer n x 2, [holes])].")
        .def_property_readonly("view", [](const vp::pattern_result& r) { return py::make_tuple(r.view.lo.x, r.view.lo.y, r.view.hi.x, r.view.hi.y); })
        .def_property_readonly("mesh", [](const vp::pattern_result& r) { return mesh_to(r.mesh); }, "(V, F): the printable watertight solid (mm).")
        .def_property_readonly("preview", [](const vp::pattern_result& r) {
            image8 copy = r.preview;
            return image_to(std::move(copy));
        }, "Planar forms: grey coverage of the drawing; 3D forms: an RGB render from two sides.")
        .def_property_readonly("report", [](const vp::pattern_result& r) {
            py::dict d;
            d["band_length_mm"] = r.band_length, d["closed"] = r.closed, d["natural_length_mm"] = r.natural_length, d["stretch"] = r.stretch;
            d["rings"] = r.rings, d["components"] = r.synthesis.components, d["holes"] = r.synthesis.holes;
            d["winding_components"] = r.synthesis.rings, d["input_pieces"] = r.synthesis.input_pieces, d["pieces"] = r.synthesis.sequence.size();
            d["cost"] = r.synthesis.cost, d["epsilon_mm"] = r.synthesis.epsilon, d["dp_entries"] = r.synthesis.dp_entries;
            d["dp_peak_bytes"] = r.synthesis.dp_peak_bytes, d["dp_seconds"] = r.synthesis.dp_seconds;
            d["edge_crossings"] = r.edge_crossings, d["cut_open"] = r.cut_open, d["in_space"] = r.in_space;
            d["solid_components"] = r.solid.components, d["solid_genus"] = r.solid.genus;
            return d;
        });

    m.def("make_pattern", [](const vp::exemplar& ex, double height, const std::optional<double>& line, const std::optional<double>& circle,
                             const std::optional<darray>& curve, const std::optional<std::vector<double>>& rect, const std::optional<darray>& curve3d,
                             const std::optional<py::tuple>& surface, const std::optional<darray>& points, bool closed, bool closed_loop,
                             const std::optional<std::uint32_t>& components, const std::optional<std::uint32_t>& holes, std::uint64_t seed,
                             double thickness, double tolerance, const std::string& slicing, double beta, double twist_deg,
                             const std::optional<double>& emboss, const std::optional<double>& carve, const std::optional<double>& shell,
                             const std::optional<double>& cell, const py::object& progress) {
        const int forms = int(line.has_value()) + int(circle.has_value()) + int(curve.has_value()) + int(rect.has_value()) + int(curve3d.has_value()) +
                          int(surface.has_value());
        if (forms != 1) throw invalid_input("give exactly one of line, circle, curve, rect, curve3d, surface");
        if (slicing != "reeb" && slicing != "uniform") throw invalid_input("slicing must be 'reeb' or 'uniform', got '" + slicing + "'");
        if (emboss && carve) throw invalid_input("emboss and carve exclude each other");
        if ((emboss || carve || points) && !surface) throw invalid_input("emboss, carve and points apply to a surface");
        if (surface && !emboss && !carve) throw invalid_input("a surface needs emboss=relief height or carve=shell thickness (mm)");
        if (closed_loop && (rect || line)) throw invalid_input("closed_loop needs a closed curve");
        vp::pattern_options po;
        po.band_height = height, po.thickness = thickness, po.chord_tolerance = tolerance;
        po.synthesis.components = components, po.synthesis.holes = holes, po.synthesis.closed_loop = closed_loop, po.synthesis.seed = seed;
        po.synthesis.beta = beta, po.synthesis.slicing = slicing == "uniform" ? vp::slicing_method::uniform : vp::slicing_method::reeb;
        if (!surface) vp::require_separate_shapes(ex, "exemplar");  // an extruded band of touching shapes is no closed solid
        vp::pattern_where where;
        if (line) {
            where = vp::along_planar_curve{planar_curve::line(*line)};
        } else if (circle) {
            where = vp::along_planar_curve{planar_curve::circle(*circle, {*circle + height, *circle + height})};  // as curve_patterns places it
        } else if (curve) {
            where = vp::along_planar_curve{planar_curve::polyline(points_from<vec2>(*curve, "curve"), closed)};
        } else if (rect) {
            if (rect->size() != 2) throw invalid_input("rect must be (width, height) in mm");
            where = vp::in_rectangle{(*rect)[0], (*rect)[1]};
        } else if (curve3d) {
            where = vp::along_space_curve{space_curve::polyline(points_from<vec3>(*curve3d, "curve3d"), closed, {.twist_degrees = twist_deg})};
        } else {
            if (surface->size() != 2) throw invalid_input("surface must be (V, F)");
            if (!points) throw invalid_input("a surface needs points: n x 3 points (mm) the band's curve passes through");
            po.decoration.mode = emboss ? decoration_mode::emboss : decoration_mode::carve;
            po.decoration.shell = emboss ? shell.value_or(2.0) : *carve;
            po.decoration.height = emboss.value_or(1.0);
            po.decoration.cell = cell.value_or(0.0);
            po.decoration.cell = vp::decoration_cell(po);
            where = vp::on_surface{.surface = mesh_from((*surface)[0].cast<darray>(), (*surface)[1].cast<py::array>()),
                                   .points = points_from<vec3>(*points, "points"), .closed = closed};
        }
        return released(progress, [&](python_progress& p) { return std::make_shared<vp::pattern_result>(vp::make_pattern(ex, where, po, p)); });
    }, py::arg("exemplar"), py::kw_only(), py::arg("height"), py::arg("line") = py::none(), py::arg("circle") = py::none(), py::arg("curve") = py::none(),
          py::arg("rect") = py::none(), py::arg("curve3d") = py::none(), py::arg("surface") = py::none(), py::arg("points") = py::none(),
          py::arg("closed") = false, py::arg("closed_loop") = false, py::arg("components") = py::none(), py::arg("holes") = py::none(),
          py::arg("seed") = 0, py::arg("thickness") = 1.0, py::arg("tolerance") = 0.0, py::arg("slicing") = "reeb", py::arg("beta") = 0.0,
          py::arg("twist_deg") = 0.0, py::arg("emboss") = py::none(), py::arg("carve") = py::none(), py::arg("shell") = py::none(),
          py::arg("cell") = py::none(), py::arg("progress") = py::none(),
          "A topology-constrained vector pattern (Zhou et al. 2014, vector_pattern/pipeline.hpp): the exemplar scaled to the band\n"
          "height `height` (mm) and synthesized along exactly one of: line=L (mm), circle=r (mm; closed), curve=n x 2 points\n"
          "(mm; closed=True joins the ends), rect=(w, h) (mm, §6.2), curve3d=n x 3 points (mm; twist_deg), surface=(V, F) with\n"
          "points=n x 3 on it (mm) and emboss=relief height (shell=its shell, default 2) or carve=shell thickness (mm; cell:\n"
          "grid spacing). components, holes: exact topology; closed_loop: a component winds around a closed curve; seed;\n"
          "thickness (mm, planar forms and space curves); tolerance (mm chord error, 0 = H/1000); slicing ('reeb', 'uniform');\n"
          "beta (§3.7). Equal to curve_patterns with the same options. progress: False cancels; Ctrl-C raises KeyboardInterrupt.");
}

}  // namespace fabsynth::python
