// SPDX-License-Identifier: MIT
// fabsynth.surface_pattern: make_exemplar (surface_pattern/exemplar.hpp) and make_pattern, the whole
// pipeline in one call (surface_pattern/pipeline.hpp). The options are make_pattern's, flattened into
// keyword arguments with the library's defaults (synthesis_options and structure_options fields by
// their names; `seed` seeds both, as the surface_patterns tool does).
#include "common.hpp"

#include <fabsynth/surface_pattern.hpp>

namespace fabsynth::python {
namespace {

namespace sp = fabsynth::surface_pattern;

py::array_t<std::int32_t> voxels_to(const std::vector<ivec3>& v) {
    py::array_t<std::int32_t> a({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
    for (std::size_t i = 0; i < v.size(); ++i)
        for (int k = 0; k < 3; ++k) a.mutable_data()[3 * i + static_cast<std::size_t>(k)] = v[i][k];
    return a;
}

py::dict grid_to(const grid_geometry& g) {
    py::dict d;
    d["dims"] = py::make_tuple(g.dims.x, g.dims.y, g.dims.z);
    d["origin"] = py::make_tuple(g.origin.x, g.origin.y, g.origin.z);
    d["spacing"] = py::make_tuple(g.spacing.x, g.spacing.y, g.spacing.z);
    return d;
}

py::dict stats_to(const sp::stress_statistics& s) {
    py::dict d;
    d["average_pa"] = s.average, d["median_pa"] = s.median, d["p99_pa"] = s.p99, d["max_pa"] = s.max;
    d["elements"] = s.elements, d["fixed_elements"] = s.fixed_elements, d["unsupported_pieces"] = s.unsupported_pieces;
    d["unsupported_voxels"] = s.unsupported_voxels, d["cg_iterations"] = s.iterations, d["seconds"] = s.seconds;
    return d;
}

/// The figures of a result, under the key names of the surface_patterns tool's report.json.
py::dict report_of(const sp::pattern_result& r) {
    py::dict d;
    py::list levels;
    for (const sp::level_report& l : r.levels) {
        py::dict x;
        x["level"] = l.level, x["voxels"] = l.voxels, x["spacing_mm"] = l.spacing_mm, x["sigma_px"] = l.sigma_px;
        x["energy_initial"] = l.energy_initial, x["energy_passes"] = l.energy_passes, x["candidates"] = l.candidates, x["seconds"] = l.seconds;
        levels.append(x);
    }
    d["mesh_closed"] = r.mesh_closed, d["voxel_mm"] = r.voxel_mm, d["exemplar_mm_per_px"] = r.mm_per_px, d["r_pattern_mm"] = r.r_pattern_mm;
    d["bridge_radius_mm"] = r.bridge_radius_mm, d["min_feature_mm"] = r.min_feature_mm, d["shell_voxels"] = r.shell_voxels.size();
    d["levels"] = levels;
    d["solid_fraction"] = r.solid_fraction, d["solid_fraction_synthesized"] = r.solid_fraction_synthesized;
    d["exemplar_solid_fraction"] = r.exemplar_solid_fraction, d["synthesized_voxels"] = r.synthesized_voxels, d["final_voxels"] = r.final_voxels;
    d["reinforcement_voxels"] = r.reinforcement_voxels, d["thin_feature_voxels_state4"] = r.thin_feature_voxels;
    d["reinforcement_ratio"] = r.reinforcement_ratio();
    d["specks_removed"] = r.specks.removed_components, d["speck_voxels_removed"] = r.specks.removed_voxels;
    py::list its;
    for (const sp::structural_step_report& it : r.structure.iterations) {
        py::dict x;
        x["samples"] = it.samples, x["solid_edges"] = it.solid_edges, x["empty_edges"] = it.empty_edges;
        x["components_before"] = it.components_before, x["components_after"] = it.components_after;
        x["added_connect"] = it.added_connect, x["added_force"] = it.added_force, x["added_geodesic"] = it.added_geodesic;
        x["max_stress_mpa"] = it.max_stress_mpa, x["max_stress_after_mpa"] = it.max_stress_after_mpa, x["load_n"] = it.load_n;
        x["solves"] = it.solves, x["reinforced_voxels"] = it.reinforced_voxels, x["seconds"] = it.seconds;
        its.append(x);
    }
    py::dict st;
    st["converged"] = r.structure.converged, st["iterations"] = its, st["forced_voxels"] = r.structure.forced_voxels;
    d["structural"] = st, d["overloaded"] = r.structure.overloaded, d["thin_feature_voxels"] = r.thin_features.added_voxels;
    d["solid_voxels"] = r.thickened.voxels.size(), d["components_26"] = r.components_26;
    d["pattern_faces"] = r.mesh.num_faces(), d["pattern_watertight"] = r.watertight;
    if (!r.validation.empty()) {
        py::dict v;
        for (const sp::stage_validation& s : r.validation) {
            py::dict x;
            x["expected"] = stats_to(s.expected), x["unexpected"] = stats_to(s.unexpected);
            v[py::str(s.name)] = x;
        }
        d["validation"] = v;
    }
    const sp::pattern_timings& t = r.seconds;
    py::dict tm;
    tm["voxelize"] = t.voxelize, tm["synthesis"] = t.synthesis, tm["structural_analysis"] = t.structural_analysis, tm["resynthesis"] = t.resynthesis;
    tm["fabrication"] = t.fabrication, tm["validation"] = t.validation, tm["preview"] = t.preview, tm["total"] = t.total;
    d["timings"] = tm;
    return d;
}

vec3 vec3_from(const std::vector<double>& v, const char* what) {
    if (v.size() != 3) throw invalid_input(std::string(what) + " must be 3 numbers");
    return {v[0], v[1], v[2]};
}

}  // namespace

void bind_surface_pattern(py::module_& m) {
    py::class_<sp::exemplar>(m, "Exemplar", "A raster exemplar: the binary pattern map, its feature-distance channel and optional colours.")
        .def_property_readonly("width", &sp::exemplar::width)
        .def_property_readonly("height", &sp::exemplar::height)
        .def_property_readonly("channels", &sp::exemplar::channels, "2 without colour, 5 with")
        .def_property_readonly("tileable", &sp::exemplar::tileable)
        .def_property_readonly("solid_fraction", &sp::exemplar::solid_fraction);
    m.def("make_exemplar", [](const py::array& mask, const py::object& colour, double feature_px, bool tileable, double feature_weight, double colour_weight) {
        const image8 mk = image_from(mask, "mask");
        std::optional<image8> c;
        if (!colour.is_none()) c = image_from(colour.cast<py::array>(), "colour");
        return sp::make_exemplar(mk, c ? &*c : nullptr,
                                 {.feature_px = feature_px, .tileable = tileable, .feature_weight = feature_weight, .colour_weight = colour_weight});
    }, py::arg("mask"), py::arg("colour") = py::none(), py::kw_only(), py::arg("feature_px"), py::arg("tileable") = true,
          py::arg("feature_weight") = 1.0, py::arg("colour_weight") = 1.0,
          "An exemplar from a mask picture (uint8 (h, w) or (h, w, c): white = solid) and an optional colour picture of\n"
          "the same size; feature_px: r_pattern, the pattern's feature radius in exemplar pixels (> 0).");

    py::class_<sp::pattern_result, std::shared_ptr<sp::pattern_result>>(m, "PatternResult",
        "What make_pattern returns: the printable mesh, the voxels behind it, the preview and the report.")
        .def_property_readonly("mesh", [](const sp::pattern_result& r) { return mesh_to(r.mesh); }, "(V, F) of the watertight, smoothed solid, mm.")
        .def_property_readonly("vertex_colours", [](const sp::pattern_result& r) {
            u8array c({static_cast<py::ssize_t>(r.vertex_colours.size()), py::ssize_t{3}});
            for (std::size_t i = 0; i < r.vertex_colours.size(); ++i)
                for (std::size_t k = 0; k < 3; ++k) c.mutable_data()[3 * i + k] = r.vertex_colours[i][k];
            return c;
        }, "sRGB uint8 (n, 3) per vertex of mesh: the exemplar's colour, blue reinforcement, green enlarged thin features\n"
           "(0 rows when the exemplar has no colour and structure is off).")
        .def_property_readonly("preview", [](const sp::pattern_result& r) {
            image8 copy = r.preview;
            return image_to(std::move(copy));
        }, "RGB uint8 (h, w, 3): two views side by side (empty without preview).")
        .def_property_readonly("grid", [](const sp::pattern_result& r) { return grid_to(r.grid); }, "The finest voxel grid: dict(dims, origin mm, spacing mm).")
        .def_property_readonly("shell_voxels", [](const sp::pattern_result& r) { return voxels_to(r.shell_voxels); }, "n x 3 int32 voxel indices of the shell.")
        .def_property_readonly("state", [](const sp::pattern_result& r) {
            return py::array_t<std::uint8_t>(static_cast<py::ssize_t>(r.state.size()), r.state.data());
        }, "uint8 per shell voxel: 1 empty, 2 exemplar, 3 reinforcement, 4 enlarged thin feature.")
        .def_property_readonly("solid_voxels", [](const sp::pattern_result& r) { return voxels_to(r.thickened.voxels); },
                               "m x 3 int32 voxel indices of the printable solid (the pattern thickened inward).")
        .def_property_readonly("report", &report_of, "The figures (dict; the keys of the surface_patterns tool's report.json).");

    m.def("make_pattern", [](const darray& V, const py::array& F, const sp::exemplar& ex, double size_mm, double thickness_mm, int resolution, int levels,
                             double min_feature_mm, int smoothing, double mm_per_px, int candidates, double jitter, std::vector<double> up, int passes,
                             std::uint64_t seed, bool structure, int max_iterations, bool stages, bool validate, bool preview, int preview_size,
                             double max_memory_gb, const std::string& material, std::vector<double> gravity, std::size_t samples, double safety_factor,
                             double load_factor, double design_load_n, double geodesic_factor, double bridge_radius_mm, double bridge_band,
                             const std::optional<std::vector<double>>& support_plane, double support_band_mm,
                             const std::vector<std::vector<double>>& loads, const py::object& progress) {
        const triangle_mesh mesh = mesh_from(V, F);
        sp::pattern_options po;
        po.size_mm = size_mm, po.resolution = resolution, po.levels = levels, po.thickness_mm = thickness_mm, po.min_feature_mm = min_feature_mm;
        po.smoothing = smoothing, po.preview = preview, po.preview_size = preview_size, po.max_memory_bytes = max_memory_gb * double(1ull << 30);
        po.synthesis = {.mm_per_px = mm_per_px, .candidates = candidates, .jitter = jitter, .up = vec3_from(up, "up"), .passes = passes, .seed = seed};
        po.structure = structure, po.max_iterations = max_iterations, po.stages = stages, po.validate = validate;
        po.structural.target_samples = samples, po.structural.seed = seed, po.structural.material = sp::print_material::named(material);
        po.structural.safety_factor = safety_factor, po.structural.design_load_n = design_load_n, po.structural.load_factor = load_factor;
        po.structural.gravity = vec3_from(gravity, "gravity"), po.structural.geodesic_factor = geodesic_factor;
        po.structural.bridge_radius_mm = bridge_radius_mm, po.structural.bridge_band = bridge_band;
        if (support_plane) {
            if (support_plane->size() != 6) throw invalid_input("support_plane must be (px, py, pz, nx, ny, nz)");
            const auto& s = *support_plane;
            po.structural.fixed = sp::plane_support({s[0], s[1], s[2]}, {s[3], s[4], s[5]}, support_band_mm < 0 ? size_mm / resolution : support_band_mm);
        }
        for (const auto& L : loads) {
            if (L.size() != 6 && L.size() != 7) throw invalid_input("a load is (x, y, z, fx, fy, fz[, radius]) in mm and N");
            po.structural.loads.push_back({vec3(L[0], L[1], L[2]), vec3(L[3], L[4], L[5]), L.size() == 7 ? L[6] : 0.0});
        }
        auto r = released(progress, [&](python_progress& p) { return std::make_shared<sp::pattern_result>(sp::make_pattern(mesh, ex, po, p)); });
        return r;
    }, py::arg("V"), py::arg("F"), py::arg("exemplar"), py::kw_only(), py::arg("size_mm"), py::arg("thickness_mm"), py::arg("resolution") = 256,
          py::arg("levels") = 0, py::arg("min_feature_mm") = -1.0, py::arg("smoothing") = 50, py::arg("mm_per_px") = 0.0, py::arg("candidates") = 128,
          py::arg("jitter") = 0.1, py::arg("up") = std::vector<double>{0, 0, 1}, py::arg("passes") = 2, py::arg("seed") = 1, py::arg("structure") = true,
          py::arg("max_iterations") = 30, py::arg("stages") = false, py::arg("validate") = false, py::arg("preview") = true, py::arg("preview_size") = 768,
          py::arg("max_memory_gb") = 16.0, py::arg("material") = "abs", py::arg("gravity") = std::vector<double>{0, 0, -1}, py::arg("samples") = 1000,
          py::arg("safety_factor") = 2.0, py::arg("load_factor") = 20.0, py::arg("design_load_n") = 0.0, py::arg("geodesic_factor") = 1.5,
          py::arg("bridge_radius_mm") = 0.0, py::arg("bridge_band") = 0.25, py::arg("support_plane") = py::none(), py::arg("support_band_mm") = -1.0,
          py::arg("loads") = std::vector<std::vector<double>>{}, py::arg("progress") = py::none(),
          "Structurally sound surface pattern (Lu et al. 2015, surface_pattern/pipeline.hpp) on the mesh (V, F), scaled so its\n"
          "longest side is size_mm, carved by the exemplar and thickened inward by thickness_mm (mm, >= one voxel).\n"
          "resolution: voxels along the longest side (paper: 256); synthesis: mm_per_px (0 = a finest voxel per pixel),\n"
          "candidates, jitter, up (the pattern's up on the surface; (0, 0, 0): free), passes, seed; structure: the loop of §5\n"
          "with material ('abs', 'pla'), gravity (direction; the lowest 10% are the supports, or support_plane =\n"
          "(px, py, pz, nx, ny, nz) with support_band_mm), samples, safety_factor, load_factor, design_load_n (N), loads\n"
          "[(x, y, z, fx, fy, fz[, radius])] (mm, N), geodesic_factor, bridge_radius_mm, bridge_band; stages, validate (the\n"
          "Table 3 FEM, report['validation']); preview, preview_size (px). Equal to the surface_patterns tool with the same\n"
          "options. progress(fraction, stage): False cancels; Ctrl-C raises KeyboardInterrupt.");
}

}  // namespace fabsynth::python
