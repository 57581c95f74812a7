// SPDX-License-Identifier: MIT
// fabsynth.filigree: elements from SVG drawings (filigree/element.hpp) and the pipeline in one call,
// in a planar domain (filigree/pipeline.hpp) or on a base surface (filigree/surface/pipeline.hpp).
// Options are filigree_options' fields as keyword arguments with the library's defaults.
#include "common.hpp"

#include <fabsynth/filigree.hpp>
#include <fabsynth/filigree/surface/pipeline.hpp>
#include <fabsynth/io/svg.hpp>

#include <filesystem>
#include <numbers>

namespace fabsynth::python {
namespace {

namespace fg = fabsynth::filigree;

py::dict record_to(const fg::structural_record& r) {
    py::dict d;
    d["analysed"] = r.analysed, d["thickness_mm"] = r.thickness, d["strong"] = r.strong, d["weak_nodes_final"] = r.weak_nodes_final;
    d["yield_mpa"] = r.yield_mpa, d["max_von_mises_before_mpa"] = r.max_von_mises_before, d["max_von_mises_after_mpa"] = r.max_von_mises_after;
    d["weak_fraction_phase1"] = r.weak_fraction_phase1, d["inserted_per_round"] = r.inserted_per_round;
    d["thickness_phase2"] = r.thickness_phase2, d["weak_fraction_phase2"] = r.weak_fraction_phase2;
    d["pieces_dropped"] = r.pieces_dropped, d["pieces_bridged"] = r.pieces_bridged, d["pieces_trimmed"] = r.pieces_trimmed;
    d["dropped_area_fraction"] = r.dropped_area_fraction, d["fem_nodes"] = r.fem_nodes, d["solver"] = r.solver, d["seconds"] = r.seconds;
    return d;
}

py::dict seconds_to(const fg::filigree_timings& t) {
    py::dict d;
    d["initialization"] = t.synthesis.initialization, d["placement"] = t.synthesis.placement, d["boosting"] = t.synthesis.boosting;
    d["topology_cut"] = t.synthesis.topology_cut, d["structure"] = t.structure, d["mesh"] = t.mesh, d["previews"] = t.previews, d["total"] = t.total;
    return d;
}

u8array picture(const image8& img) {
    image8 copy = img;
    return image_to(std::move(copy));
}

fg::filigree_options options_from(std::uint64_t seed, double sigma_d, double sigma_f, int max_rounds, double crossing_penalty, std::size_t max_elements,
                                  bool structure, const std::string& material, double thickness_mm, double max_thickness_mm, double pressure_pa,
                                  double max_bridge_mm, bool previews) {
    fg::filigree_options o;
    o.synthesis.seed = seed, o.synthesis.sigma_d = sigma_d, o.synthesis.sigma_f = sigma_f, o.synthesis.max_rounds = max_rounds;
    o.synthesis.crossing_penalty = crossing_penalty, o.synthesis.init.max_elements = max_elements;
    o.reinforcement.enabled = structure, o.reinforcement.material = fg::parse_material(material), o.reinforcement.thickness = thickness_mm;
    o.reinforcement.max_thickness = max_thickness_mm, o.reinforcement.pressure_pa = pressure_pa, o.reinforcement.max_bridge_mm = max_bridge_mm;
    o.previews = previews;
    return o;
}

std::vector<double> weights_of(const std::vector<fg::element>& classes, const std::optional<std::vector<double>>& weights) {
    return weights ? *weights : std::vector<double>(classes.size(), 1.0);
}

// The keyword arguments both forms share (the doc strings list them once).
#define FABSYNTH_FILIGREE_COMMON_ARGS                                                                                                              \
    py::arg("seed") = 1, py::arg("sigma_d") = 0.15, py::arg("sigma_f") = 0.05, py::arg("max_rounds") = 6, py::arg("crossing_penalty") = 5.0,       \
        py::arg("max_elements") = 5000, py::arg("structure") = true, py::arg("material") = "abs", py::arg("thickness_mm") = 1.0,                   \
        py::arg("max_thickness_mm") = 0.0, py::arg("pressure_pa") = 1000.0, py::arg("max_bridge_mm") = 0.0, py::arg("previews") = true,         \
        py::arg("progress") = py::none()

constexpr const char* common_doc =
    "Synthesis: seed, sigma_d (distortion bound, Table 1: 0.13-0.17), sigma_f (boosting fraction, 0.045-0.05), max_rounds,\n"
    "crossing_penalty (mm), max_elements (instances refused above). Structure (§5): structure, material ('abs', 'pla', 'petg',\n"
    "'pa12', '316l', 'ti64'), thickness_mm (initial), max_thickness_mm (0: unbounded), pressure_pa, max_bridge_mm\n"
    "(0: automatic, -1: no bridges). previews: render the pictures. progress(fraction, stage): False cancels; Ctrl-C raises\n"
    "KeyboardInterrupt. Equal to the filigree tool with the same options.";

}  // namespace

void bind_filigree(py::module_& m) {
    py::class_<fg::element>(m, "Element", "An element class: skeleton, strip widths and covering region (mm, reference point at the origin).")
        .def_property_readonly("name", [](const fg::element& e) { return e.name; });
    m.def("element_from_svg", [](const std::filesystem::path& path, double size_mm, double width_mm, double tolerance_mm, const std::string& name) {
        fg::element_options eo;
        eo.size_mm = size_mm, eo.width_mm = width_mm, eo.tolerance_mm = tolerance_mm, eo.name = name.empty() ? path.string() : name;
        // read at a quarter of the skeleton tolerance (at most 0.01 user units), as the filigree tool reads it
        return fg::element_from_svg(io::read_svg(path, std::min(0.01, tolerance_mm / 4)), eo);
    }, py::arg("path"), py::kw_only(), py::arg("size_mm") = 20.0, py::arg("width_mm") = 0.0, py::arg("tolerance_mm") = 0.05, py::arg("name") = "",
          "An element from an SVG drawing: stroked paths are the skeleton, filled shapes their medial axis. size_mm: the\n"
          "skeleton's bounding-box diagonal after scaling; width_mm: strip width (0: the SVG's stroke widths, scaled);\n"
          "tolerance_mm: polygonal approximation.");

    py::class_<fg::planar_filigree, std::shared_ptr<fg::planar_filigree>>(m, "PlanarFiligree", "What make_filigree returns in a planar domain.")
        .def_property_readonly("outline", [](const fg::planar_filigree& f) { return polygons_to(f.outline()); },
                               "The printable piece: [(outer n x 2, [holes])] in mm, the domain's frame (y down, as drawn).")
        .def_property_readonly("mesh", [](const fg::planar_filigree& f) { return mesh_to(f.mesh); }, "(V, F): the watertight extrusion, y flipped (mm).")
        .def_property_readonly("view", [](const fg::planar_filigree& f) { return py::make_tuple(f.view.lo.x, f.view.lo.y, f.view.hi.x, f.view.hi.y); })
        .def_property_readonly("preview", [](const fg::planar_filigree& f) { return picture(f.preview); })
        .def_property_readonly("steps", [](const fg::planar_filigree& f) { return picture(f.steps); })
        .def_property_readonly("stress_map", [](const fg::planar_filigree& f) { return picture(f.stress_map); })
        .def_property_readonly("histogram", [](const fg::planar_filigree& f) { return picture(f.histogram); })
        .def_property_readonly("report", [](const fg::planar_filigree& f) {
            py::dict d;
            d["instances_per_class"] = f.instances_per_class, d["components"] = f.reinforcement.components;
            d["reinforcement"] = record_to(f.reinforcement);
            py::dict a;
            a["instances"] = f.appearance.instances, a["transversal_crossings"] = f.appearance.transversal_crossings;
            a["crossings_per_instance"] = f.appearance.crossings_per_instance, a["overlap_area_fraction"] = f.appearance.overlap_area_fraction;
            a["free_ends"] = f.appearance.free_ends;
            d["appearance"] = a, d["seconds"] = seconds_to(f.seconds);
            return d;
        });
    py::class_<fg::surface_filigree, std::shared_ptr<fg::surface_filigree>>(m, "SurfaceFiligree", "What make_surface_filigree returns.")
        .def_property_readonly("solid", [](const fg::surface_filigree& f) { return mesh_to(f.solid); }, "(V, F): the printable watertight solid (mm).")
        .def_property_readonly("baked", [](const fg::surface_filigree& f) { return mesh_to(f.reinforcement.baked); }, "(V, F): M_b, the strips baked into the base.")
        .def_property_readonly("preview", [](const fg::surface_filigree& f) { return picture(f.preview); })
        .def_property_readonly("stress_map", [](const fg::surface_filigree& f) { return picture(f.stress_map); })
        .def_property_readonly("histogram", [](const fg::surface_filigree& f) { return picture(f.histogram); })
        .def_property_readonly("report", [](const fg::surface_filigree& f) {
            py::dict d;
            d["instances_per_class"] = f.instances_per_class, d["solid_components"] = f.solid_components;
            d["reinforcement"] = record_to(f.reinforcement), d["seconds"] = seconds_to(f.seconds);
            return d;
        });

    m.def("make_filigree", [](const std::vector<fg::element>& classes, const std::optional<std::vector<double>>& weights,
                              const std::optional<std::vector<double>>& rect, const std::optional<std::filesystem::path>& domain_svg, double rotation_deg,
                              std::uint64_t seed, double sigma_d, double sigma_f, int max_rounds, double crossing_penalty, std::size_t max_elements,
                              bool structure, const std::string& material, double thickness_mm, double max_thickness_mm, double pressure_pa,
                              double max_bridge_mm, bool previews, const py::object& progress) {
        if (rect.has_value() == domain_svg.has_value()) throw invalid_input("give the domain as rect=(w, h) (mm) or domain_svg=path, one of them");
        if (rect && rect->size() != 2) throw invalid_input("rect must be (width, height) in mm");
        const fg::planar_domain domain = rect ? fg::planar_domain::rectangle((*rect)[0], (*rect)[1])
                                              : fg::planar_domain::from_svg(io::read_svg(*domain_svg, 0.01), domain_svg->string());
        const fg::filigree_options o = options_from(seed, sigma_d, sigma_f, max_rounds, crossing_penalty, max_elements, structure, material, thickness_mm,
                                                    max_thickness_mm, pressure_pa, max_bridge_mm, previews);
        const std::vector<double> w = weights_of(classes, weights);
        const fg::any_field field = fg::constant_field{rotation_deg * std::numbers::pi / 180.0, 1.0};
        return released(progress, [&](python_progress& p) {
            return std::make_shared<fg::planar_filigree>(fg::make_filigree(std::span<const fg::element>(classes), w, domain, field, o, p));
        });
    }, py::arg("elements"), py::arg("weights") = py::none(), py::kw_only(), py::arg("rect") = py::none(), py::arg("domain_svg") = py::none(),
          py::arg("rotation_deg") = 0.0, FABSYNTH_FILIGREE_COMMON_ARGS,
          (std::string("A filigree (Chen et al. 2016, filigree/pipeline.hpp) of the element classes in proportions `weights`\n"
                       "(default equal) over a rectangle rect = (w, h) mm or the filled shapes of domain_svg (user units = mm), every\n"
                       "element turned by rotation_deg (counter-clockwise, y up).\n") + common_doc).c_str());
    m.def("make_surface_filigree", [](const std::vector<fg::element>& classes, const std::optional<std::vector<double>>& weights, const darray& V,
                                      const py::array& F, std::vector<double> up, const std::optional<std::vector<std::uint32_t>>& region_faces,
                                      const std::optional<std::vector<double>>& vertex_scale, std::uint64_t seed, double sigma_d, double sigma_f,
                                      int max_rounds, double crossing_penalty, std::size_t max_elements, bool structure, const std::string& material,
                                      double thickness_mm, double max_thickness_mm, double pressure_pa, double max_bridge_mm, bool previews,
                                      const py::object& progress) {
        if (up.size() != 3) throw invalid_input("up must be 3 numbers");
        fg::surface_filigree_options o;
        static_cast<fg::filigree_options&>(o) = options_from(seed, sigma_d, sigma_f, max_rounds, crossing_penalty, max_elements, structure, material,
                                                             thickness_mm, max_thickness_mm, pressure_pa, max_bridge_mm, previews);
        o.up = {up[0], up[1], up[2]};
        o.region_faces = region_faces;
        if (vertex_scale) o.vertex_scale = *vertex_scale;
        const triangle_mesh mesh = mesh_from(V, F);
        const std::vector<double> w = weights_of(classes, weights);
        return released(progress, [&](python_progress& p) {
            return std::make_shared<fg::surface_filigree>(fg::make_filigree(std::span<const fg::element>(classes), w, mesh, o, p));
        });
    }, py::arg("elements"), py::arg("weights") = py::none(), py::arg("V"), py::arg("F"), py::kw_only(), py::arg("up") = std::vector<double>{0, 0, 1},
          py::arg("region_faces") = py::none(), py::arg("vertex_scale") = py::none(), FABSYNTH_FILIGREE_COMMON_ARGS,
          (std::string("A filigree on the base surface (V, F) in mm (filigree/surface/pipeline.hpp): the elements' up follows `up`\n"
                       "projected on the surface (gravity along -up), over region_faces (0-based face ids; default all), scaled per\n"
                       "vertex by vertex_scale (default 1).\n") + common_doc).c_str());
}

#undef FABSYNTH_FILIGREE_COMMON_ARGS

}  // namespace fabsynth::python
