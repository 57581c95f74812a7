// filigree: synthesis of filigrees in a planar domain (Chen et al. 2016, "Synthesis of Filigrees for
// Digital Fabrication"), from SVG elements to one connected, printable piece.
//
//   filigree --element E.svg[:WEIGHT][@G1,G2] [--element ...] [--labels L.png] (--rect W H | --domain D.svg)
//            --scale MM [--width MM] [--rotation DEG | --field-image F.png --field-scale S0 S1]
//            [--rotation-image R.png --rotation-range A0 A1] [--thickness MM] [--max-thickness MM]
//            [--material abs|pla|petg|pa12|316l|ti64] [--support-edge SIDE | --support-box X0 Y0 X1 Y1 | --hang X Y]
//            [--upright] [--no-structure] [--seed S] -o OUT.svg
//   filigree --element E.svg[:WEIGHT][@L1,L2] ... --mesh M.obj [--mesh-size MM] [--region FACES.txt | --region-curve C.csv]
//            [--face-labels LABELS.txt] [--up X Y Z] [--field-scale-file F.txt] --scale MM [--width MM] [--thickness MM] [--seed S] -o OUT.stl
//            (on a base surface: OUT.stl printable solid, OUT.obj baked M_b, OUT.png, OUT.json)
//
// The tool reads the inputs, makes one library call (make_filigree in
// include/fabsynth/filigree/pipeline.hpp, or filigree/surface/pipeline.hpp on a base surface:
// elements (element.hpp) -> initialization (§4.1) -> rounds of placement optimization with smooth
// connections and boosting (§4.3, §4.4) -> topology cut (§4.5) -> strips (reconstruct.hpp, §6) ->
// structural optimization by shell FEM (§5) -> extrusion or thickening, previews) and writes the
// files. Outputs of the planar form: OUT.svg (filled shapes only), OUT.stl (watertight extrusion, y
// flipped so the print looks like the drawing), OUT.3mf (the same mesh, mm; where lib3mf is
// available), OUT.png (preview), OUT_steps.png (after initialization, placement, boosting and
// topology cut, like the paper's Fig. 8), OUT_stress.png and OUT_histogram.png (Fig. 10 and 21,
// with the structural optimization), OUT.json (report). The surface form writes OUT.stl, OUT.3mf,
// OUT.obj, OUT.png, OUT_stress.png, OUT_histogram.png and OUT.json. Nothing is written unless everything succeeded. Conventions (exit codes, --quiet,
// --json): docs/tools.md.


#include <fabsynth/filigree/pipeline.hpp>
#include <fabsynth/filigree/surface/pipeline.hpp>
#include <fabsynth/io/image.hpp>
#if defined(FABSYNTH_HAS_LIB3MF)
#include <fabsynth/io/mesh_3mf.hpp>
#endif
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/mesh_obj.hpp>
#include <fabsynth/io/mesh_stl.hpp>
#include <fabsynth/io/numbers.hpp>
#include <fabsynth/io/points.hpp>
#include <fabsynth/io/svg.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "output_set.hpp"
#include "print_mesh.hpp"
#include "tool.hpp"

namespace fs = std::filesystem;
using namespace fabsynth;
using namespace fabsynth::filigree;

namespace {

struct element_arg {
    std::string path;
    double weight = 1.0;
    std::vector<int> labels;  // grey levels of --labels where the class may lie; empty: everywhere
};

// "E.svg", "E.svg:WEIGHT", "E.svg@G1,G2" or "E.svg:WEIGHT@G1,G2" (a path may itself contain ':' only
// if a weight follows, '@' only if labels follow).
element_arg parse_element(std::string a) {
    element_arg e{a, 1.0, {}};
    if (const std::size_t at = a.rfind('@'); at != std::string::npos) {
        std::vector<int> labels;
        std::string list = a.substr(at + 1);
        bool ok = !list.empty();
        for (std::size_t from = 0; ok && from <= list.size();) {
            const std::size_t comma = std::min(list.find(',', from), list.size());
            const std::string item = list.substr(from, comma - from);
            char* end = nullptr;
            const long v = std::strtol(item.c_str(), &end, 10);
            ok = !item.empty() && end && *end == '\0' && v >= 0 && v <= 255;
            if (ok) labels.push_back(static_cast<int>(v));
            from = comma + 1;
        }
        if (ok) {  // else the '@' is part of the file name
            e.labels = std::move(labels);
            a = a.substr(0, at);
            e.path = a;
        }
    }
    const std::size_t colon = a.rfind(':');
    if (colon != std::string::npos && colon + 1 < a.size()) {
        const std::string w = a.substr(colon + 1);
        char* end = nullptr;
        const double v = std::strtod(w.c_str(), &end);
        if (end && *end == '\0') {
            if (!(std::isfinite(v) && v >= 0)) throw invalid_input("--element " + a + ": the weight must be finite and >= 0");
            e.path = a.substr(0, colon), e.weight = v;
        }
    }
    return e;
}

// The --mesh form's inputs.
struct surface_request {
    std::string mesh, region, region_curve, scale_file, directions, face_labels;
    std::vector<double> up{0, 0, 1};
    double mesh_size = 0;  // 0: the mesh is in mm as it is
};

// Points as [[x, y], ...] (mm).
nlohmann::ordered_json points_json(const std::vector<vec2>& points) {
    auto a = nlohmann::ordered_json::array();
    for (const vec2& p : points) a.push_back({p.x, p.y});
    return a;
}

// One object per round of placement and boosting (Fig. 22 and the counts behind it).
nlohmann::ordered_json rounds_json(const std::vector<round_record>& rounds) {
    auto a = nlohmann::ordered_json::array();
    for (const round_record& r : rounds)
        a.push_back({{"instances", r.instances}, {"pme_per_instance", r.pme_per_instance}, {"translation_mm", r.translation_mm},
                     {"smooth_connections", r.smooth_connections}, {"boosted_moves", r.boosted}, {"boosting_reconnections", r.reconnected},
                     {"duplicates_removed", r.duplicates_removed}});
    return a;
}

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
            {"duplicates_removed", syn.duplicates_removed},
            {"per_round", rounds_json(syn.per_round)}};
}

// How the flat piece is held (reinforcement_options::support), for the report.
nlohmann::ordered_json support_json(const planar_support& ps) {
    static const char* sides[] = {"top", "bottom", "left", "right"};
    nlohmann::ordered_json j;
    if (ps.box) j = {{"box_mm", {ps.box->lo.x, ps.box->lo.y, ps.box->hi.x, ps.box->hi.y}}};
    else if (ps.hang) j = {{"hang_mm", {ps.hang->x, ps.hang->y}}, {"hang_radius_mm", ps.hang_radius}};
    else j = {{"side", sides[static_cast<int>(ps.side)]}, {"fraction", ps.fraction}};
    j["gravity"] = ps.upright ? "in the plane, toward the drawing's bottom" : "out of the plane";
    return j;
}

// The §5 record of both forms (reinforcement_result and surface_reinforcement_result share these
// names); `up`: the surface form's up vector, between pressure and supports.
template <class R>
nlohmann::ordered_json structure_fields(const R& rf, const reinforcement_options& opt, const std::vector<double>* up) {
    nlohmann::ordered_json s = {{"analysed", rf.analysed}, {"material", material_name(opt.material)}, {"pressure_pa", opt.pressure_pa}};
    if (up) s["up"] = *up, s["supports"] = "lowest 5% along up";
    else s["supports"] = support_json(opt.support);
    s.update(nlohmann::ordered_json{{"yield_mpa", rf.yield_mpa}, {"fem_nodes", rf.fem_nodes}, {"solver", rf.solver},
                                    {"histogram_bin_mpa", rf.histogram_bin_mpa}, {"histogram_before", rf.histogram_before},
                                    {"histogram_after", rf.histogram_after}, {"max_von_mises_before_mpa", rf.max_von_mises_before},
                                    {"max_von_mises_after_mpa", rf.max_von_mises_after}, {"weak_fraction_phase1", rf.weak_fraction_phase1},
                                    {"inserted_per_round", rf.inserted_per_round}, {"thickness_phase2_mm", rf.thickness_phase2},
                                    {"weak_fraction_phase2", rf.weak_fraction_phase2}, {"max_thickness_mm", opt.max_thickness},
                                    {"strong", rf.strong}, {"weak_nodes_final", rf.weak_nodes_final}});
    return s;
}

// Writes the JSON report to the staged `file` (errors name `shown`, the final path).
void write_report(const fs::path& file, const fs::path& shown, const nlohmann::ordered_json& report) {
    std::ofstream j(file);
    j << report.dump(2) << "\n";
    if (!j) throw io_error(shown.string(), 0, "cannot write the report");
}

double seconds_since(std::chrono::steady_clock::time_point t) { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); }

// The ranges both forms check (scale, width, thickness, tolerance, sigma_d, sigma_f, rounds).
void check_common_ranges(double scale, double width, double thickness, double tolerance, double sigma_d, double sigma_f, int rounds) {
    tool::require_range(scale, 0.1, 1e4, "--scale", "mm");
    if (width != 0) tool::require_range(width, 1e-3, scale, "--width", "mm (at most --scale; or 0: the SVG's own stroke widths)");
    tool::require_range(thickness, 1e-3, 1e3, "--thickness", "mm");
    tool::require_range(tolerance, 1e-4, scale, "--tolerance", "mm");
    tool::require_range(sigma_d, 1e-3, 1.0, "--sigma-d", "");
    tool::require_range(sigma_f, 1e-4, 1.0, "--sigma-f", "");
    if (rounds < 1 || rounds > 100) throw invalid_input("--rounds must be in [1, 100]");
}

// The element classes of --element arguments (scaled to `scale` mm, strips `width` mm wide; 0: the
// SVG's stroke widths, or a filled shape's local width, scaled with the element).
void load_classes(const std::vector<element_arg>& elements, double scale, double width, double tolerance, std::vector<element>& classes,
                  std::vector<double>& weights) {
    for (const auto& a : elements) {
        element_options eo;
        eo.size_mm = scale, eo.width_mm = width, eo.tolerance_mm = tolerance, eo.name = a.path;
        classes.push_back(element_from_svg(io::read_svg(a.path, std::min(0.01, tolerance / 4)), eo));
        weights.push_back(a.weight);
    }
}

// The pattern's size before any work (initialization.hpp's estimate).
void check_work(double area, double smallest, const filigree_options& opt, double max_elements, const char* where) {
    tool::require_work(estimated_instances(area, smallest, opt.synthesis.init), max_elements, 25.0, "element instances", "--max-elements",
                       std::string(where) + std::to_string(area) + " mm^2 with elements of " + std::to_string(smallest) + " mm^2",
                       "or a larger --scale");
}

// Progress of the library call inside the tool's: fractions [0, 1] of the call -> [from, to].
template <class Progress>
auto progress_between(Progress& progress, double from, double to) {
    return [&progress, from, to](double f, std::string_view stage) { progress(from + (to - from) * f, stage); };
}

// The --mesh form: elements read as in the 2D form, the rest on the surface.
template <class Progress>
void run_surface_mode(const surface_request& rq, const std::vector<std::string>& element_args, double scale, double width, surface_filigree_options opt, double tolerance, double max_elements, const std::string& out_path, tool::common& common, tool::mesh_simplification& simplify,
                      Progress& progress) {
    const auto t_start = std::chrono::steady_clock::now();
    std::vector<element_arg> elements;
    for (const std::string& a : element_args) elements.push_back(parse_element(a));
    const bool any_labels = std::any_of(elements.begin(), elements.end(), [](const element_arg& e) { return !e.labels.empty(); });
    if (any_labels != !rq.face_labels.empty())
        throw invalid_input(any_labels ? "--element E.svg@L with --mesh needs --face-labels LABELS.txt" : "--face-labels needs an element given as E.svg@L1,L2");
    std::vector<fs::path> inputs{rq.mesh};
    for (const auto& e : elements) inputs.emplace_back(e.path);
    if (!rq.region.empty()) inputs.emplace_back(rq.region);
    if (!rq.region_curve.empty()) inputs.emplace_back(rq.region_curve);
    if (!rq.scale_file.empty()) inputs.emplace_back(rq.scale_file);
    if (!rq.directions.empty()) inputs.emplace_back(rq.directions);
    if (!rq.face_labels.empty()) inputs.emplace_back(rq.face_labels);
    const fs::path out(out_path);
    fs::path stl_out = out, obj_out = out, png_out = out, json_out = out, threemf_out = out;
    stl_out.replace_extension(".stl"), obj_out.replace_extension(".obj"), png_out.replace_extension(".png"), json_out.replace_extension(".json");
    threemf_out.replace_extension(".3mf");
    const fs::path hist_out = out.parent_path() / (out.stem().string() + "_histogram.png");
    const fs::path stress_out = out.parent_path() / (out.stem().string() + "_stress.png");
    tool::check_outputs(inputs, {stl_out, obj_out, png_out, json_out, threemf_out, hist_out, stress_out});
    for (const auto& e : elements)
        if (!fs::is_regular_file(e.path)) throw io_error(e.path, 0, "no such element file");
    check_common_ranges(scale, width, opt.reinforcement.thickness, tolerance, opt.synthesis.sigma_d, opt.synthesis.sigma_f, opt.synthesis.max_rounds);
    tool::require_range(max_elements, 1, 1e6, "--max-elements", "");
    opt.synthesis.init.max_elements = static_cast<std::size_t>(max_elements);
    if (rq.mesh_size != 0) tool::require_range(rq.mesh_size, 1e-2, 1e5, "--mesh-size", "mm");
    for (const double x : rq.up)
        if (!std::isfinite(x)) throw invalid_input("--up must be finite");
    std::vector<element> classes;
    std::vector<double> weights;
    load_classes(elements, scale, width, tolerance, classes, weights);
    if (std::all_of(weights.begin(), weights.end(), [](double w) { return w <= 0; })) throw invalid_input("--element: every class has weight 0");
    tool::output_set outputs;
    if (!(std::isfinite(opt.reinforcement.pressure_pa) && opt.reinforcement.pressure_pa >= 0))
        throw invalid_input("--pressure must be finite and >= 0 Pa");
    const fs::path stl_file = outputs.add(stl_out), obj_file = outputs.add(obj_out), png_file = outputs.add(png_out), json_file = outputs.add_manifest(json_out);
#if defined(FABSYNTH_HAS_LIB3MF)
    const fs::path threemf_file = outputs.add(threemf_out);
#endif
    const fs::path hist_file = opt.reinforcement.enabled ? outputs.add(hist_out) : fs::path();
    const fs::path stress_file = opt.reinforcement.enabled ? outputs.add(stress_out) : fs::path();

    progress(0.0, "read mesh");
    triangle_mesh mesh = io::read_mesh(rq.mesh);
    if (mesh.faces.empty()) throw invalid_input(rq.mesh + ": the mesh has no faces");
    size_fit fit;  // the largest side of the bounding box becomes mesh_size mm
    if (rq.mesh_size > 0) fit = fit_to_size(mesh, rq.mesh_size);
    if (!rq.region.empty()) {
        std::vector<std::uint32_t> ids;
        for (const double x : io::read_numbers(rq.region)) {
            if (x < 0 || x != std::floor(x) || x >= static_cast<double>(mesh.faces.size()))
                throw invalid_input(rq.region + ": face id " + std::to_string(x) + " is not a face of the mesh (0.." + std::to_string(mesh.faces.size() - 1) + ")");
            ids.push_back(static_cast<std::uint32_t>(x));
        }
        opt.region_faces = std::move(ids), opt.region_name = rq.region;
    }
    if (!rq.region_curve.empty()) {
        std::vector<vec3> curve = io::read_points_csv(rq.region_curve);
        for (vec3& p : curve) p = fit(p);
        opt.region_curve = std::move(curve), opt.region_name = rq.region_curve;
    }
    if (!rq.scale_file.empty()) opt.vertex_scale = io::read_numbers(rq.scale_file);
    if (!rq.directions.empty()) {  // rows "vertex dx dy dz"
        const std::vector<double> v = io::read_numbers(rq.directions);
        if (v.empty() || v.size() % 4 != 0)
            throw invalid_input(rq.directions + ": expected rows of 4 numbers (vertex id, direction x y z), got " + std::to_string(v.size()) + " numbers");
        for (std::size_t k = 0; k < v.size(); k += 4) {
            if (v[k] < 0 || v[k] != std::floor(v[k]) || v[k] >= static_cast<double>(mesh.vertices.size()))
                throw invalid_input(rq.directions + ": row " + std::to_string(k / 4 + 1) + ": vertex " + std::to_string(v[k]) +
                                    " is not a vertex of the mesh (0.." + std::to_string(mesh.vertices.size() - 1) + ")");
            opt.directions.push_back({static_cast<std::uint32_t>(v[k]), vec3(v[k + 1], v[k + 2], v[k + 3])});
        }
    }
    if (any_labels) {  // one label per face, in the mesh's face order (polygons as read: fan triangles)
        std::vector<int> labels;
        for (const double x : io::read_numbers(rq.face_labels)) {
            if (x < 0 || x > 255 || x != std::floor(x)) throw invalid_input(rq.face_labels + ": label " + std::to_string(x) + " is not an integer in 0-255");
            labels.push_back(static_cast<int>(x));
        }
        std::vector<std::vector<int>> class_labels;
        for (const element_arg& e : elements) class_labels.push_back(e.labels);
        opt.class_allowed = face_label_regions(labels, mesh.faces.size(), class_labels, "--face-labels " + rq.face_labels);
    }
    const surface_filigree_base base(std::move(mesh), opt);
    check_work(base.region().area, smallest_covering_area(classes, weights), opt, max_elements, "a region of ");

    const surface_filigree f = make_filigree(classes, weights, base, opt, progress_between(progress, 0.0, 0.95));
    const surface_synthesis_result& syn = f.synthesis;
    const surface_reinforcement_result& rf = f.reinforcement;
    simplify.default_tolerance(0.5 * f.solid_cell);
    const triangle_mesh solid = simplify(f.solid, common, stl_out.filename().string());

    nlohmann::ordered_json report = {
        {"tool", "filigree"},
        {"mode", "surface"},
        {"mesh", {{"file", rq.mesh}, {"vertices", base.mesh().vertices.size()}, {"faces", base.mesh().faces.size()},
                  {"region_faces", base.region().faces.size()}, {"region_area_mm2", base.region().area}}},
        {"direction_constraints", opt.directions.size()},
        {"face_labels", rq.face_labels},
        {"instances", syn.instances.size()},
        {"instances_per_class", f.instances_per_class},
        {"local_parameterizations", {{"built", syn.maps_built}, {"seconds_summed_over_threads", syn.map_seconds}}},
        {"topology_cut", {{"protrusions_trimmed", syn.cut.cut.protrusions_trimmed}, {"branches_cut", syn.cut.cut.branches_cut},
                          {"cuts_refused_for_connectivity", syn.cut.cut.cuts_refused_for_connectivity},
                          {"split_vertices_off_surface", syn.cut.vertices_off_surface}}},
        {"pieces_dropped", rf.pieces_dropped},
        {"pieces_trimmed", rf.pieces_trimmed},
        {"pieces_bridged", rf.pieces_bridged},
        {"pieces_dropped_area_fraction", rf.dropped_area_fraction},
        {"structure", structure_fields(rf, opt.reinforcement, &rq.up)},
        {"instances_final", rf.instances.size()},
        {"thickness_mm", rf.thickness},
        {"baked_triangles", rf.baked.faces.size()},
        {"stl_triangles", solid.faces.size()},
        {"stl_components", f.solid_components},
        {"seconds", {{"initialization", f.seconds.synthesis.initialization}, {"placement", f.seconds.synthesis.placement},
                     {"boosting", f.seconds.synthesis.boosting}, {"topology_cut", f.seconds.synthesis.topology_cut},
                     {"bake_and_structure", f.seconds.structure}, {"printable_mesh", f.seconds.mesh}, {"total", seconds_since(t_start)}}},
    };
    report.update(layout_fields(syn));
    for (std::size_t c = 0; c < classes.size(); ++c)
        report["elements"].push_back({{"file", elements[c].path}, {"weight", weights[c]}, {"labels", elements[c].labels}, {"instances", f.instances_per_class[c]}});
    report["meshes"] = simplify.report();

    progress(0.95, "write");
    io::write_stl(stl_file, solid);
    io::write_obj(obj_file, rf.baked);
#if defined(FABSYNTH_HAS_LIB3MF)
    io::write_3mf(threemf_file, solid, {.name = out.stem().string()});
#endif
    io::write_png(png_file, f.preview);
    if (!f.histogram.empty()) io::write_png(hist_file, f.histogram);
    if (!f.stress_map.empty()) io::write_png(stress_file, f.stress_map);
    write_report(json_file, json_out, report);
    outputs.commit();
    progress(1.0, "write");
    char line[400];
    std::snprintf(line, sizeof line, "%s: %zu instances on the surface, %d rounds, PME %.1f -> %.1f, thickness %.3g mm, %zu solid triangles",
                  stl_out.string().c_str(), rf.instances.size(), syn.rounds, syn.energy_initial, syn.energy_final, rf.thickness, solid.faces.size());
    common.say(line);
    common.summary(report);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "filigree: synthesis of filigrees (Chen et al. 2016) in a rectangle or an SVG domain.\n"
        "Elements (stroked SVG paths = strip skeletons; filled shapes are reduced to their medial axis; shapes with an id\n"
        "starting with 'cover' are convex parts of the covering region) are scaled to --scale mm (bounding-box\n"
        "diagonal), distributed, optimized for matching overlaps and tangential contacts, trimmed, reinforced by shell FEM\n"
        "and extruded. Writes OUT.svg, OUT.stl, OUT.3mf, OUT.png, OUT_steps.png, OUT_stress.png, OUT_histogram.png and OUT.json.",
        "filigree"};
    tool::common common(app);
    std::vector<std::string> element_args;
    std::string domain_path, field_image, rotation_image, labels_image, material = "abs", support_edge, out_path;
    std::vector<double> rect, field_scale, rotation_range, support_box, hang;
    double scale = 0, width = 0, rotation_deg = 0, thickness = 1.0, sigma_d = 0.15, sigma_f = 0.05, tolerance = 0.05;
    double pressure = 1000.0, max_thickness = 0, hang_radius = 0;
    bool upright = false;
    filigree_options defaults;
    double crossing_penalty = defaults.synthesis.crossing_penalty, max_bridge = defaults.reinforcement.max_bridge_mm;
    int rounds = 6;
    double max_elements = 5000;
    bool no_structure = false;
    std::uint64_t seed = 1;
    app.add_option("--element", element_args, "element SVG, optionally E.svg:WEIGHT (class proportion, default 1) and @G1,G2 (only where --labels has these grey levels); repeatable")->required();
    auto* o_rect = app.add_option("--rect", rect, "W H: rectangular domain of W x H mm")->expected(2);
    auto* o_domain = app.add_option("--domain", domain_path, "domain SVG: its filled shapes (with holes), user units = mm")->check(CLI::ExistingFile);
    o_rect->excludes(o_domain);
    app.add_option("--scale", scale, "element size (bounding-box diagonal of its skeleton), mm")->required();
    app.add_option("--width", width, "strip width, mm; default: each stroke's own width in the SVG, scaled with the element as --scale scales it");
    auto* o_rot = app.add_option("--rotation", rotation_deg, "constant element rotation, degrees (counter-clockwise, y up)");
    auto* o_fimg = app.add_option("--field-image", field_image, "grayscale PNG over the domain's bounding box: element scale from black to white")
                       ->check(CLI::ExistingFile);
    app.add_option("--field-scale", field_scale, "S0 S1: scale factors at black and white of --field-image")->expected(2);
    auto* o_labels = app.add_option("--labels", labels_image,
                                    "grayscale PNG over the domain's bounding box: regions by grey level; an element given as E.svg@G1,G2 "
                                    "is placed only where the picture is G1 or G2")
                         ->check(CLI::ExistingFile);
    o_rot->excludes(o_fimg);
    auto* o_rimg = app.add_option("--rotation-image", rotation_image,
                                  "grayscale PNG over the domain's bounding box: element rotation from black to white (--rotation-range)")
                       ->check(CLI::ExistingFile)
                       ->excludes(o_rot);
    app.add_option("--rotation-range", rotation_range, "A0 A1: rotations at black and white of --rotation-image, degrees")->expected(2);
    app.add_option("--thickness", thickness, "extrusion and shell thickness, mm (structural optimization may raise it)")->capture_default_str();
    app.add_option("--material", material, "abs | pla | petg | pa12 | 316l | ti64 (elastic constants and yield stress, filigree/structure.hpp)")
        ->capture_default_str();
    app.add_option("--max-thickness", max_thickness,
                   "thickest the structural optimization may make the piece, mm; it stops there and reports the nodes still weak (default: no bound)");
    auto* o_edge = app.add_option("--support-edge", support_edge, "top | bottom | left | right: the piece is clamped along 5% of this side (default top, as drawn)");
    auto* o_sbox = app.add_option("--support-box", support_box, "X0 Y0 X1 Y1: clamp the piece where it lies in this box (mm, as drawn, y down)")->expected(4);
    auto* o_hang = app.add_option("--hang", hang, "X Y: the piece hangs upright from an eyelet at this point (mm, as drawn); its weight pulls down the drawing")
                       ->expected(2);
    app.add_option("--hang-radius", hang_radius, "radius of the --hang eyelet, mm (default: the median strip width)");
    app.add_flag("--upright", upright, "the piece stands upright: gravity in its plane toward the drawing's bottom (default: lying flat)");
    o_edge->excludes(o_sbox)->excludes(o_hang);
    o_sbox->excludes(o_hang);
    app.add_option("--pressure", pressure, "external pressure on the piece, Pa (§5)")->capture_default_str();
    app.add_flag("--no-structure", no_structure, "skip the structural optimization (§5)");
    app.add_option("--seed", seed, "variety seed (same seed -> identical output)");
    app.add_option("--sigma-d", sigma_d, "distortion bound of smooth connections (Table 1: 0.13-0.17)")->capture_default_str();
    app.add_option("--sigma-f", sigma_f, "fraction of the best pairs boosting learns from (Table 1: 0.045-0.05)")->capture_default_str();
    app.add_option("--rounds", rounds, "most rounds of placement + boosting")->capture_default_str();
    app.add_option("--crossing-penalty", crossing_penalty,
                   "mm added to a pair's matching energy per strip crossing of its two elements (0: the paper's eq. 2 alone)")
        ->capture_default_str();
    app.add_option("--max-bridge", max_bridge,
                   "longest bridge strip joining a cut-off piece to the rest, mm (0: 4 x the strip width, 8 x on a --mesh; -1: none)")
        ->capture_default_str();
    app.add_option("--tolerance", tolerance, "polygonal approximation of the element skeletons, mm")->capture_default_str();
    app.add_option("--max-elements", max_elements, "refuse domains estimated to need more element instances than this")->capture_default_str();
    app.add_option("-o,--output", out_path, "output SVG; OUT.stl, OUT.png, OUT_steps.png and OUT.json are written beside it")->required();
    tool::mesh_simplification simplify(app, 0.05, "0.05 mm; with --mesh, half the grid spacing of the thickening");
    surface_request on_mesh;
    auto* o_mesh = app.add_option("--mesh", on_mesh.mesh, "base surface (OBJ, STL, PLY, 3MF): synthesize on it instead of a 2D domain")
                       ->check(CLI::ExistingFile);
    // the surface form's options need --mesh (the planar form would otherwise ignore them)
    app.add_option("--mesh-size", on_mesh.mesh_size, "scale the base mesh so its bounding box's largest side is this many mm (default: as is, mm)")
        ->needs(o_mesh);
    auto* o_region = app.add_option("--region", on_mesh.region, "text file of face ids (0-based) of the base mesh to cover (default: all)")
                         ->check(CLI::ExistingFile)
                         ->needs(o_mesh);
    app.add_option("--region-curve", on_mesh.region_curve,
                   "CSV of x,y,z points (the mesh's units, before --mesh-size) of a closed curve on the base mesh, each within 2% of the "
                   "mesh's diagonal of it: cover the smaller side it encloses")
        ->check(CLI::ExistingFile)
        ->excludes(o_region)
        ->needs(o_mesh);
    app.add_option("--up", on_mesh.up, "X Y Z: the elements' up vector, projected onto the surface (default 0 0 1)")->expected(3)->needs(o_mesh);
    app.add_option("--field-scale-file", on_mesh.scale_file, "text file of one element scale factor per mesh vertex")
        ->check(CLI::ExistingFile)
        ->needs(o_mesh);
    app.add_option("--face-labels", on_mesh.face_labels,
                   "text file of one label (0-255) per face of the base mesh, in its face order: regions; an element given as "
                   "E.svg@L1,L2 is placed only on faces labelled L1 or L2")
        ->check(CLI::ExistingFile)
        ->needs(o_mesh);
    app.add_option("--directions", on_mesh.directions,
                   "text file of rows 'vertex dx dy dz': element directions at mesh vertices, interpolated over the surface (default: --up)")
        ->check(CLI::ExistingFile)
        ->needs(o_mesh);
    o_mesh->excludes(o_labels)->excludes(o_rect)->excludes(o_domain)->excludes(o_fimg)->excludes(o_rot)->excludes(o_rimg)->excludes(o_edge)->excludes(o_sbox)->excludes(o_hang);

    return tool::run(app, common, argc, argv, [&] {
        auto progress = common.progress();
        const auto t_start = std::chrono::steady_clock::now();
        filigree_options opt;  // as the library's defaults, set from the options above
        tool::require_range(crossing_penalty, 0.0, 1e3, "--crossing-penalty", "mm");
        if (max_bridge != -1) tool::require_range(max_bridge, 0.0, 1e3, "--max-bridge", "mm (or -1: no bridges)");
        opt.synthesis.seed = seed, opt.synthesis.sigma_d = sigma_d, opt.synthesis.sigma_f = sigma_f, opt.synthesis.max_rounds = rounds;
        opt.synthesis.crossing_penalty = crossing_penalty;
        opt.reinforcement.max_bridge_mm = max_bridge;
        opt.reinforcement.thickness = thickness, opt.reinforcement.pressure_pa = pressure, opt.reinforcement.enabled = !no_structure;
        try {
            opt.reinforcement.material = parse_material(material);
        } catch (const invalid_input& e) {
            throw invalid_input(std::string("--material: ") + e.what());
        }
        if (max_thickness != 0) tool::require_range(max_thickness, thickness, 1e3, "--max-thickness", "mm (at least --thickness)");
        opt.reinforcement.max_thickness = max_thickness;
        if (no_structure && (max_thickness != 0 || !support_edge.empty() || !support_box.empty() || !hang.empty() || upright || hang_radius != 0))
            throw invalid_input("--max-thickness, --support-edge, --support-box, --hang, --hang-radius and --upright need the structural optimization (drop --no-structure)");
        if (!on_mesh.mesh.empty()) {
            if (upright || hang_radius != 0) throw invalid_input("--upright and --hang-radius are for a planar piece; on a surface the supports follow --up");
            surface_filigree_options so;
            static_cast<filigree_options&>(so) = opt;
            so.up = vec3(on_mesh.up[0], on_mesh.up[1], on_mesh.up[2]);
            return run_surface_mode(on_mesh, element_args, scale, width, std::move(so), tolerance, max_elements, out_path, common, simplify, progress);
        }
        const fs::path svg_out(out_path);
        fs::path stl_out = svg_out, png_out = svg_out, json_out = svg_out, threemf_out = svg_out;
        stl_out.replace_extension(".stl");
        threemf_out.replace_extension(".3mf");
        png_out.replace_extension(".png");
        json_out.replace_extension(".json");
        const fs::path steps_out = svg_out.parent_path() / (svg_out.stem().string() + "_steps.png");
        const fs::path stress_out = svg_out.parent_path() / (svg_out.stem().string() + "_stress.png");
        const fs::path hist_out = svg_out.parent_path() / (svg_out.stem().string() + "_histogram.png");
        std::vector<element_arg> elements;
        for (const std::string& a : element_args) elements.push_back(parse_element(a));
        std::vector<fs::path> inputs;
        for (const auto& e : elements) inputs.emplace_back(e.path);
        if (!domain_path.empty()) inputs.emplace_back(domain_path);
        if (!field_image.empty()) inputs.emplace_back(field_image);
        if (!labels_image.empty()) inputs.emplace_back(labels_image);
        if (!rotation_image.empty()) inputs.emplace_back(rotation_image);
        tool::check_outputs(inputs, {svg_out, stl_out, png_out, steps_out, json_out, threemf_out, stress_out, hist_out});
        for (const auto& e : elements)
            if (!fs::is_regular_file(e.path)) throw io_error(e.path, 0, "no such element file");
        if (rect.empty() == domain_path.empty()) throw invalid_input("give exactly one of --rect and --domain");
        check_common_ranges(scale, width, thickness, tolerance, sigma_d, sigma_f, rounds);
        if (!(std::isfinite(pressure) && pressure >= 0)) throw invalid_input("--pressure must be finite and >= 0 Pa");
        if (!std::isfinite(rotation_deg)) throw invalid_input("--rotation must be finite");
        if (!field_image.empty() && field_scale.size() != 2) throw invalid_input("--field-image needs --field-scale S0 S1");
        if (field_image.empty() && !field_scale.empty()) throw invalid_input("--field-scale needs --field-image");
        for (double s : field_scale) tool::require_range(s, 1e-2, 1e2, "--field-scale", "");
        if (!rotation_image.empty() && rotation_range.size() != 2) throw invalid_input("--rotation-image needs --rotation-range A0 A1");
        if (rotation_image.empty() && !rotation_range.empty()) throw invalid_input("--rotation-range needs --rotation-image");
        for (double a : rotation_range) tool::require_range(a, -3600.0, 3600.0, "--rotation-range", "degrees");
        planar_support& sup = opt.reinforcement.support;
        if (!support_edge.empty()) {
            const std::vector<std::string> sides{"top", "bottom", "left", "right"};
            const auto it = std::find(sides.begin(), sides.end(), support_edge);
            if (it == sides.end()) throw invalid_input("--support-edge must be top, bottom, left or right, got '" + support_edge + "'");
            sup.side = static_cast<support_side>(it - sides.begin());
        }
        for (double v : support_box) tool::require_range(v, -1e5, 1e5, "--support-box", "mm");
        if (!support_box.empty()) {
            if (!(support_box[0] < support_box[2] && support_box[1] < support_box[3])) throw invalid_input("--support-box needs X0 < X1 and Y0 < Y1");
            sup.box = box2(vec2(support_box[0], support_box[1]), vec2(support_box[2], support_box[3]));
        }
        for (double v : hang) tool::require_range(v, -1e5, 1e5, "--hang", "mm");
        if (hang_radius != 0) {
            if (hang.empty()) throw invalid_input("--hang-radius needs --hang X Y");
            tool::require_range(hang_radius, 1e-3, 1e3, "--hang-radius", "mm");
        }
        if (!hang.empty()) sup.hang = vec2(hang[0], hang[1]), sup.hang_radius = hang_radius, sup.upright = true;
        if (upright) sup.upright = true;
        tool::output_set outputs;
        const fs::path svg_file = outputs.add(svg_out), stl_file = outputs.add(stl_out), png_file = outputs.add(png_out),
                       steps_file = outputs.add(steps_out), json_file = outputs.add_manifest(json_out);
#if defined(FABSYNTH_HAS_LIB3MF)
        const fs::path threemf_file = outputs.add(threemf_out);
#endif
        const fs::path stress_file = no_structure ? fs::path() : outputs.add(stress_out), hist_file = no_structure ? fs::path() : outputs.add(hist_out);

        progress(0.0, "read elements");
        planar_domain domain = rect.empty() ? planar_domain::from_svg(io::read_svg(domain_path, 0.01), domain_path)
                                                  : planar_domain::rectangle(tool::require_range(rect[0], 1e-2, 1e5, "--rect width", "mm"),
                                                                             tool::require_range(rect[1], 1e-2, 1e5, "--rect height", "mm"));
        std::vector<element> classes;
        std::vector<double> weights;
        load_classes(elements, scale, width, tolerance, classes, weights);
        const bool any_labels = std::any_of(elements.begin(), elements.end(), [](const element_arg& e) { return !e.labels.empty(); });
        if (any_labels != !labels_image.empty())
            throw invalid_input(any_labels ? "--element E.svg@G needs --labels L.png" : "--labels needs an element given as E.svg@G1,G2");
        if (any_labels) {
            std::vector<std::vector<int>> class_labels;
            for (const element_arg& e : elements) class_labels.push_back(e.labels);
            domain.class_allowed = label_regions(grey_levels(io::read_png(labels_image)), domain.bounds, class_labels, "--labels " + labels_image);
        }
        {
            const double smallest = smallest_covering_area(classes, weights, field_scale.empty() ? 1.0 : std::min(field_scale[0], field_scale[1]));
            if (!std::isfinite(smallest)) throw invalid_input("--element: every class has weight 0");
            tool::require_range(max_elements, 1, 1e6, "--max-elements", "");
            check_work(domain.area, smallest, opt, max_elements, "a domain of ");
            opt.synthesis.init.max_elements = static_cast<std::size_t>(max_elements);
        }
        constexpr double deg = std::numbers::pi / 180.0;
        any_field field = constant_field{rotation_deg * deg, 1.0};
        std::string field_kind = "constant";
        if (!field_image.empty()) {
            field = image_field(grey_levels(io::read_png(field_image)), domain.bounds, field_scale[0], field_scale[1], rotation_deg * deg);
            field_kind = "image";
        }
        if (!rotation_image.empty()) {
            image_rotation_field rot(grey_levels(io::read_png(rotation_image)), domain.bounds, rotation_range[0] * deg, rotation_range[1] * deg);
            field = combined_field<image_rotation_field, any_field>{std::move(rot), field};
            field_kind = field_image.empty() ? "rotation image" : "rotation image, scale image";
        }

        const planar_filigree f = make_filigree(std::span<const element>(classes), weights, domain, field, opt, progress_between(progress, 0.05, 0.95));
        const synthesis_result& syn = f.synthesis;
        const reinforcement_result& rf = f.reinforcement;
        const triangle_mesh mesh = simplify(f.mesh, common, stl_out.filename().string());

        nlohmann::ordered_json report = {
            {"tool", "filigree"},
            {"elements", nlohmann::ordered_json::array()},
            {"instances", rf.instances.size()},
            {"domain_area_mm2", domain.area},
            {"covered_fraction_initial", syn.covered_fraction},
            {"field", field_kind},
            {"connection_database", syn.database_size},
            {"topology_cut", {{"protrusions_trimmed", syn.cut.protrusions_trimmed}, {"branches_cut", syn.cut.branches_cut},
                              {"cuts_refused_for_connectivity", syn.cut.cuts_refused_for_connectivity}}},
            {"connected_components", rf.components},
            {"pieces_dropped", rf.pieces_dropped},
            {"pieces_trimmed", rf.pieces_trimmed},
            {"pieces_bridged", rf.pieces_bridged},
            {"pieces_dropped_area_fraction", rf.dropped_area_fraction},
            {"appearance", {{"transversal_crossings", f.appearance.transversal_crossings},
                            {"crossings_per_instance", f.appearance.crossings_per_instance},
                            {"overlap_area_fraction", f.appearance.overlap_area_fraction},
                            {"free_ends", f.appearance.free_ends},
                            {"crossing_points_mm", points_json(f.appearance.crossing_points)}}},
            {"structure", structure_fields(rf, opt.reinforcement, nullptr)},
            {"weak_points_mm", points_json(rf.weak_points)},
            {"thickness_mm", rf.thickness},
            {"stl_triangles", mesh.faces.size()},
            {"seconds", {{"initialization", f.seconds.synthesis.initialization}, {"placement", f.seconds.synthesis.placement},
                         {"boosting", f.seconds.synthesis.boosting}, {"topology_cut", f.seconds.synthesis.topology_cut},
                         {"structure", f.seconds.structure}, {"total", seconds_since(t_start)}}},
        };
        report.update(layout_fields(syn));
        for (std::size_t c = 0; c < classes.size(); ++c)
            report["elements"].push_back({{"file", elements[c].path}, {"weight", weights[c]}, {"labels", elements[c].labels}, {"instances", f.instances_per_class[c]},
                                          {"skeleton_vertices", classes[c].vertices.size()}, {"size_mm", classes[c].size},
                                          {"median_strip_width_mm", classes[c].median_width()}});
        report["meshes"] = simplify.report();

        progress(0.95, "write");
        io::write_svg(svg_file, io::document_of(f.outline(), f.view));
        io::write_stl(stl_file, mesh);
#if defined(FABSYNTH_HAS_LIB3MF)
        io::write_3mf(threemf_file, mesh, {.name = svg_out.stem().string()});
#endif
        io::write_png(png_file, f.preview);
        io::write_png(steps_file, f.steps);
        if (!f.stress_map.empty()) io::write_png(stress_file, f.stress_map), io::write_png(hist_file, f.histogram);
        write_report(json_file, json_out, report);
        outputs.commit();
        progress(1.0, "write");
        char line[400];
        std::snprintf(line, sizeof line, "%s: %zu instances of %zu element classes, %d rounds, PME %.1f -> %.1f, %.2f crossings per instance, %zu component(s), thickness %.3g mm",
                      svg_out.string().c_str(), rf.instances.size(), classes.size(), syn.rounds, syn.energy_initial, syn.energy_final,
                      f.appearance.crossings_per_instance, rf.components, rf.thickness);
        common.say(line);
        common.summary(report);
    });
}
