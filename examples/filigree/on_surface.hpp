// The --mesh form of the filigree tool (filigree-synthesis.md §8.1, §6): a filigree on a base
// surface. Reads the mesh (optionally scaled to --mesh-size), the region (face ids, or a closed
// curve on the mesh), the up vector
// and a per-vertex scale file; synthesizes on the surface (filigree/surface_synthesis.hpp), bakes
// the strips into the mesh (M_b, filigree/surface_reconstruct.hpp) and thickens M_b into a
// watertight solid (geometry/surface_offset.hpp). Writes OUT.stl (printable solid), OUT.obj (M_b),
// OUT.png (the base mesh with the filigree, from two sides) and OUT.json.
#pragma once

#include <fabsynth/filigree/surface_reconstruct.hpp>
#include <fabsynth/filigree/surface_structure.hpp>
#include <fabsynth/filigree/surface_synthesis.hpp>
#include <fabsynth/geometry/curve_region.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/geometry/render.hpp>
#include <fabsynth/geometry/surface_offset.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/mesh_obj.hpp>
#include <fabsynth/io/mesh_stl.hpp>
#include <fabsynth/io/points.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "output_set.hpp"
#include "tool.hpp"

namespace filigree_tool {

namespace fs = std::filesystem;
using namespace fabsynth;
using namespace fabsynth::filigree;

struct surface_request {
    std::string mesh, region, region_curve, scale_file;
    std::vector<double> up{0, 0, 1};
    double mesh_size = 0;  // 0: the mesh is in mm as it is
};

// The report fields of the synthesis rounds, common to both forms (synthesis_result and
// surface_synthesis_result have them under the same names).
template <class R>
nlohmann::ordered_json layout_fields(const R& syn) {
    return {{"rounds", syn.rounds},
            {"pme", {{"initial", syn.energy_initial}, {"after_first_placement", syn.energy_after_placement}, {"final", syn.energy_final}}},
            {"pme_per_instance_per_round", syn.energy_per_round},
            {"smooth_connections", syn.smooth_connections},
            {"boosted_moves", syn.boosted},
            {"boosting_reconnections", syn.reconnected},
            {"duplicates_removed", syn.duplicates_removed}};
}

// Writes the JSON report to the staged `file` (errors name `shown`, the final path).
inline void write_report(const fs::path& file, const fs::path& shown, const nlohmann::ordered_json& report) {
    std::ofstream j(file);
    j << report.dump(2) << "\n";
    if (!j) throw io_error(shown.string(), 0, "cannot write the report");
}

// Whitespace-separated numbers of a text file ('#' starts a comment line).
inline std::vector<double> read_numbers(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw io_error(path, 0, "cannot open");
    std::vector<double> out;
    std::string line;
    std::size_t no = 0;
    while (std::getline(in, line)) {
        ++no;
        if (!line.empty() && line[0] == '#') continue;
        std::size_t at = 0;
        while (at < line.size()) {
            while (at < line.size() && std::isspace(static_cast<unsigned char>(line[at]))) ++at;
            if (at >= line.size()) break;
            std::size_t used = 0;
            double v = 0;
            try {
                v = std::stod(line.substr(at), &used);
            } catch (const std::exception&) {
                throw io_error(path, no, "not a number: '" + line.substr(at, 20) + "'");
            }
            if (!std::isfinite(v)) throw io_error(path, no, "a value is not finite");
            out.push_back(v);
            at += used;
        }
    }
    return out;
}

// The base mesh with the solid on it, vertex-coloured, for the preview.
inline triangle_mesh with_solid(const triangle_mesh& base, const triangle_mesh& solid, std::vector<std::array<std::uint8_t, 3>>& colours) {
    triangle_mesh both = base;
    colours.assign(base.vertices.size(), {236, 228, 210});
    const auto off = static_cast<std::uint32_t>(base.vertices.size());
    for (const vec3& v : solid.vertices) both.vertices.push_back(v), colours.push_back({140, 62, 28});
    for (auto f : solid.faces) {
        for (auto& k : f) k += off;
        both.faces.push_back(f);
    }
    return both;
}

template <class Progress>
nlohmann::ordered_json run_on_surface(const surface_request& rq, std::span<const element> classes, std::span<const double> weights, synthesis_options so,
                                      reinforcement_options ro, double max_elements, const fs::path& out_any, tool::output_set& outputs, Progress&& progress) {
    const auto t_start = std::chrono::steady_clock::now();
    fs::path stl_out = out_any, obj_out = out_any, png_out = out_any, json_out = out_any;
    stl_out.replace_extension(".stl"), obj_out.replace_extension(".obj"), png_out.replace_extension(".png"), json_out.replace_extension(".json");
    const fs::path stl_file = outputs.add(stl_out), obj_file = outputs.add(obj_out), png_file = outputs.add(png_out), json_file = outputs.add_manifest(json_out);

    progress(0.0, "read mesh");
    triangle_mesh mesh = io::read_mesh(rq.mesh);
    if (mesh.faces.empty()) throw invalid_input(rq.mesh + ": the mesh has no faces");
    size_fit fit;  // the largest side of the bounding box becomes mesh_size mm
    if (rq.mesh_size > 0) fit = fit_to_size(mesh, rq.mesh_size);
    const surface_patcher patcher(mesh);
    surface_region region = surface_region::whole(patcher);
    if (!rq.region.empty()) {
        std::vector<std::uint32_t> ids;
        for (const double x : read_numbers(rq.region)) {
            if (x < 0 || x != std::floor(x) || x >= static_cast<double>(mesh.faces.size()))
                throw invalid_input(rq.region + ": face id " + std::to_string(x) + " is not a face of the mesh (0.." + std::to_string(mesh.faces.size() - 1) + ")");
            ids.push_back(static_cast<std::uint32_t>(x));
        }
        region = surface_region::of_faces(patcher, ids, rq.region);
    }
    if (!rq.region_curve.empty()) {
        std::vector<vec3> curve = io::read_points_csv(rq.region_curve);
        for (vec3& p : curve) p = fit(p);
        const box3 bb = bounding_box(mesh);
        const double reach = 0.02 * glm::length(bb.size());  // points drawn on a coarser copy of the mesh may lie off it
        std::vector<std::uint32_t> inside;
        try {
            inside = faces_inside_curve(mesh, curve, reach);
        } catch (const invalid_input& e) {  // "fabsynth: curve region: ...": name the file instead
            const std::string what = e.what();
            const std::size_t at = what.find("curve region: ");
            throw invalid_input(rq.region_curve + ": " + (at == std::string::npos ? what : what.substr(at + 14)));
        }
        region = surface_region::of_faces(patcher, inside, rq.region_curve);
    }
    const vec3 up(rq.up[0], rq.up[1], rq.up[2]);
    const surface_direction_field direction = surface_direction_field::from_up_vector(patcher, up);
    const surface_scale_field scale =
        rq.scale_file.empty() ? surface_scale_field::constant(mesh, 1.0) : surface_scale_field::per_vertex(mesh, read_numbers(rq.scale_file));
    const surface_control field{&direction, &scale};
    {  // the pattern's size before any work: initialization covers >= 40% new area per element
        double smallest = std::numeric_limits<double>::infinity();
        for (std::size_t c = 0; c < classes.size(); ++c)
            if (weights[c] > 0) smallest = std::min(smallest, classes[c].covering_area);
        tool::require_work(region.area / (0.4 * smallest), max_elements, 25.0, "element instances", "--max-elements",
                           "a region of " + std::to_string(region.area) + " mm^2 with elements of " + std::to_string(smallest) + " mm^2",
                           "or a larger --scale");
    }

    progress(0.05, "synthesis on the surface");
    const surface_synthesis_result syn = synthesize_on_surface(classes, weights, region, field, so);

    progress(0.6, ro.enabled ? "bake and structure" : "bake");
    surface_reinforcement_options sro;
    sro.base = ro, sro.up = vec3(rq.up[0], rq.up[1], rq.up[2]);
    const surface_reinforcement_result rf = reinforce_on_surface(classes, weights, region, field, so, syn, sro);

    progress(0.8, "printable mesh");
    auto t = std::chrono::steady_clock::now();
    surface_offset_options oo;
    oo.cell = rf.thickness / 3;  // the surface_offset guideline (cell <= tau / 4) at a third: the strips are wider than thick
    const triangle_mesh solid = thicken_surface(rf.baked, rf.thickness, oo);
    const auto topo = analyze_topology(solid);
    if (!topo.is_watertight()) throw solver_error("the printable mesh is not watertight");
    const double solid_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();

    progress(0.9, "render");
    std::vector<std::array<std::uint8_t, 3>> colours;
    const triangle_mesh scene = with_solid(mesh, solid, colours);
    render_options look;
    look.width = 800, look.height = 800;
    const vec3 u = glm::normalize(up);
    const vec3 side = std::abs(u.z) < 0.9 ? glm::normalize(glm::cross(u, vec3(0, 0, 1))) : vec3(0, 1, 0);
    const image8 png = render_two_sides(scene, {side, u}, look, colours);

    std::vector<std::size_t> per_class(classes.size(), 0);
    for (const surface_instance& in : syn.instances) ++per_class[in.shape.cls];
    nlohmann::ordered_json report = {
        {"tool", "filigree"},
        {"mode", "surface"},
        {"mesh", {{"file", rq.mesh}, {"vertices", mesh.vertices.size()}, {"faces", mesh.faces.size()}, {"region_faces", region.faces.size()},
                  {"region_area_mm2", region.area}}},
        {"instances", syn.instances.size()},
        {"instances_per_class", per_class},
        {"local_parameterizations", {{"built", syn.maps_built}, {"seconds_summed_over_threads", syn.map_seconds}}},
        {"topology_cut", {{"protrusions_trimmed", syn.cut.cut.protrusions_trimmed}, {"branches_cut", syn.cut.cut.branches_cut},
                          {"cuts_refused_for_connectivity", syn.cut.cut.cuts_refused_for_connectivity},
                          {"split_vertices_off_surface", syn.cut.vertices_off_surface}}},
        {"pieces_dropped", rf.pieces_dropped},
        {"pieces_dropped_area_fraction", rf.dropped_area_fraction},
        {"structure", {{"analysed", rf.analysed}, {"material", ro.material == material_preset::pla ? "pla" : "abs"}, {"pressure_pa", ro.pressure_pa},
                       {"up", rq.up}, {"supports", "lowest 5% along up"}, {"yield_mpa", rf.yield_mpa}, {"fem_nodes", rf.fem_nodes},
                       {"solver", rf.solver}, {"histogram_bin_mpa", rf.histogram_bin_mpa}, {"histogram_before", rf.histogram_before},
                       {"histogram_after", rf.histogram_after}, {"max_von_mises_before_mpa", rf.max_von_mises_before},
                       {"max_von_mises_after_mpa", rf.max_von_mises_after}, {"weak_fraction_phase1", rf.weak_fraction_phase1},
                       {"inserted_per_round", rf.inserted_per_round}, {"thickness_phase2_mm", rf.thickness_phase2},
                       {"weak_fraction_phase2", rf.weak_fraction_phase2}}},
        {"instances_final", rf.instances.size()},
        {"thickness_mm", rf.thickness},
        {"baked_triangles", rf.baked.faces.size()},
        {"stl_triangles", solid.faces.size()},
        {"stl_components", topo.components},
        {"seconds", {{"initialization", syn.seconds.initialization}, {"placement", syn.seconds.placement}, {"boosting", syn.seconds.boosting},
                     {"topology_cut", syn.seconds.topology_cut}, {"bake_and_structure", rf.seconds}, {"printable_mesh", solid_seconds},
                     {"total", std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count()}}},
    };

    report.update(layout_fields(syn));

    progress(0.95, "write");
    io::write_stl(stl_file, solid);
    io::write_obj(obj_file, rf.baked);
    io::write_png(png_file, png);
    write_report(json_file, json_out, report);
    return report;
}

}  // namespace filigree_tool
