// filigree: synthesis of filigrees in a planar domain (Chen et al. 2016, "Synthesis of Filigrees for
// Digital Fabrication"), from SVG elements to one connected, printable piece.
//
//   filigree --element E.svg [--element E2.svg[:WEIGHT] ...] (--rect W H | --domain D.svg)
//            --scale MM --width MM [--rotation DEG | --field-image F.png --field-scale S0 S1]
//            [--thickness MM] [--material abs|pla] [--no-structure] [--seed S] -o OUT.svg
//   filigree --element E.svg ... --mesh M.obj [--mesh-size MM] [--region FACES.txt | --region-curve C.csv] [--up X Y Z]
//            [--field-scale-file F.txt] --scale MM --width MM [--thickness MM] [--seed S] -o OUT.stl
//            (on a base surface: on_surface.hpp; OUT.stl, OUT.obj, OUT.png, OUT.json)
//
// Pipeline (include/fabsynth/filigree/): elements (element.hpp) -> initialization (§4.1) ->
// rounds of placement optimization with smooth connections and boosting (§4.3, §4.4) -> topology
// cut (§4.5) -> strips (reconstruct.hpp, §6) -> structural optimization by shell FEM (§5) ->
// extrusion. Outputs: OUT.svg (filled shapes only), OUT.stl (watertight extrusion, y flipped so the
// print looks like the drawing), OUT.png (preview), OUT_steps.png (after initialization,
// placement, boosting and topology cut, like the paper's Fig. 8), OUT.json (report). Nothing is
// written unless everything succeeded. Conventions (exit codes, --quiet, --json): docs/tools.md.

#include <fabsynth/filigree/reinforcement.hpp>
#include <fabsynth/filigree/synthesis.hpp>
#include <fabsynth/geometry/coverage_image.hpp>
#include <fabsynth/geometry/extrude.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh_stl.hpp>
#include <fabsynth/io/svg.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "on_surface.hpp"
#include "output_set.hpp"
#include "tool.hpp"

namespace fs = std::filesystem;
using namespace fabsynth;
using namespace fabsynth::filigree;

namespace {

struct element_arg {
    std::string path;
    double weight = 1.0;
};

// "E.svg" or "E.svg:WEIGHT" (a path may itself contain ':' only if a weight follows).
element_arg parse_element(const std::string& a) {
    element_arg e{a, 1.0};
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

std::vector<polygon_with_holes> strips_of(const std::vector<graph::skeleton_graph<vec2>>& sk, const planar_domain& d) {
    return strip_outline(std::span<const graph::skeleton_graph<vec2>>(sk), d.region);
}

// The skeletons of a set of instances (no topology cut), for the steps picture.
std::vector<graph::skeleton_graph<vec2>> skeletons_of(std::span<const element> classes, const std::vector<instance>& in, const planar_domain& d) {
    pattern_state s(classes, in, constant_field{}, d, 0.0);
    return world_skeletons(s);
}

image8 steps_image(const std::vector<std::vector<polygon_with_holes>>& panels, const box2& view) {
    std::vector<image8> imgs;
    for (const auto& p : panels) imgs.push_back(preview_image(p, view, {.max_side = 700, .supersample = 3}));
    return side_by_side(imgs, 12, std::uint8_t{200}, false);
}

}  // namespace

// The ranges both forms check (scale, width, thickness, tolerance, sigma_d, sigma_f, rounds).
void check_common_ranges(double scale, double width, double thickness, double tolerance, double sigma_d, double sigma_f, int rounds) {
    tool::require_range(scale, 0.1, 1e4, "--scale", "mm");
    tool::require_range(width, 1e-3, scale, "--width", "mm (at most --scale)");
    tool::require_range(thickness, 1e-3, 1e3, "--thickness", "mm");
    tool::require_range(tolerance, 1e-4, scale, "--tolerance", "mm");
    tool::require_range(sigma_d, 1e-3, 1.0, "--sigma-d", "");
    tool::require_range(sigma_f, 1e-4, 1.0, "--sigma-f", "");
    if (rounds < 1 || rounds > 100) throw invalid_input("--rounds must be in [1, 100]");
}

// The element classes of --element arguments (scaled to `scale` mm, strips `width` mm wide).
void load_classes(const std::vector<element_arg>& elements, double scale, double width, double tolerance, std::vector<element>& classes,
                  std::vector<double>& weights) {
    for (const auto& a : elements) {
        element_options eo;
        eo.size_mm = scale, eo.width_mm = width, eo.tolerance_mm = tolerance, eo.name = a.path;
        classes.push_back(element_from_svg(io::read_svg(a.path, std::min(0.01, tolerance / 4)), eo));
        weights.push_back(a.weight);
    }
}

// The --mesh form (on_surface.hpp): elements read as in the 2D form, the rest on the surface.
template <class Progress>
void run_surface_mode(const filigree_tool::surface_request& rq, const std::vector<std::string>& element_args, double scale, double width,
                      reinforcement_options ro, double tolerance, double sigma_d, double sigma_f, int rounds, double max_elements,
                      const std::string& out_path, tool::common& common, Progress& progress) {
    const double thickness = ro.thickness;
    const std::uint64_t seed = ro.seed;
    std::vector<element_arg> elements;
    for (const std::string& a : element_args) elements.push_back(parse_element(a));
    std::vector<fs::path> inputs{rq.mesh};
    for (const auto& e : elements) inputs.emplace_back(e.path);
    if (!rq.region.empty()) inputs.emplace_back(rq.region);
    if (!rq.region_curve.empty()) inputs.emplace_back(rq.region_curve);
    if (!rq.scale_file.empty()) inputs.emplace_back(rq.scale_file);
    const fs::path out(out_path);
    std::vector<fs::path> outs;
    for (const char* ext : {".stl", ".obj", ".png", ".json"}) outs.push_back(fs::path(out).replace_extension(ext));
    tool::check_outputs(inputs, outs);
    for (const auto& e : elements)
        if (!fs::is_regular_file(e.path)) throw io_error(e.path, 0, "no such element file");
    check_common_ranges(scale, width, thickness, tolerance, sigma_d, sigma_f, rounds);
    tool::require_range(max_elements, 1, 1e6, "--max-elements", "");
    if (rq.mesh_size != 0) tool::require_range(rq.mesh_size, 1e-2, 1e5, "--mesh-size", "mm");
    for (const double x : rq.up)
        if (!std::isfinite(x)) throw invalid_input("--up must be finite");
    std::vector<element> classes;
    std::vector<double> weights;
    load_classes(elements, scale, width, tolerance, classes, weights);
    if (std::all_of(weights.begin(), weights.end(), [](double w) { return w <= 0; })) throw invalid_input("--element: every class has weight 0");
    synthesis_options so;
    so.seed = seed, so.sigma_d = sigma_d, so.sigma_f = sigma_f, so.max_rounds = rounds;
    so.init.max_elements = static_cast<std::size_t>(max_elements);
    tool::output_set outputs;
    if (!(std::isfinite(ro.pressure_pa) && ro.pressure_pa >= 0)) throw invalid_input("--pressure must be finite and >= 0 Pa");
    const nlohmann::ordered_json report = filigree_tool::run_on_surface(rq, classes, weights, so, ro, max_elements, out, outputs, progress);
    outputs.commit();
    progress(1.0, "write");
    char line[400];
    std::snprintf(line, sizeof line, "%s: %zu instances on the surface, %d rounds, PME %.1f -> %.1f, thickness %.3g mm, %zu solid triangles",
                  fs::path(out).replace_extension(".stl").string().c_str(), report["instances_final"].template get<std::size_t>(),
                  report["rounds"].template get<int>(), report["pme"]["initial"].template get<double>(), report["pme"]["final"].template get<double>(),
                  report["thickness_mm"].template get<double>(), report["stl_triangles"].template get<std::size_t>());
    common.say(line);
    common.summary(report);
}

int main(int argc, char** argv) {
    CLI::App app{
        "filigree: synthesis of filigrees (Chen et al. 2016) in a rectangle or an SVG domain.\n"
        "Elements (stroked SVG paths = strip skeletons; filled shapes are reduced to their medial axis; shapes with an id\n"
        "starting with 'cover' are convex parts of the covering region) are scaled to --scale mm (bounding-box\n"
        "diagonal), distributed, optimized for matching overlaps and tangential contacts, trimmed, reinforced by shell FEM\n"
        "and extruded. Writes OUT.svg, OUT.stl, OUT.png, OUT_steps.png and OUT.json.",
        "filigree"};
    tool::common common(app);
    std::vector<std::string> element_args;
    std::string domain_path, field_image, material = "abs", out_path;
    std::vector<double> rect, field_scale;
    double scale = 0, width = 0, rotation_deg = 0, thickness = 1.0, sigma_d = 0.15, sigma_f = 0.05, tolerance = 0.05;
    double pressure = 1000.0;
    int rounds = 6;
    double max_elements = 5000;
    bool no_structure = false;
    std::uint64_t seed = 1;
    app.add_option("--element", element_args, "element SVG, optionally E.svg:WEIGHT (class proportion, default 1); repeatable")->required();
    auto* o_rect = app.add_option("--rect", rect, "W H: rectangular domain of W x H mm")->expected(2);
    auto* o_domain = app.add_option("--domain", domain_path, "domain SVG: its filled shapes (with holes), user units = mm")->check(CLI::ExistingFile);
    o_rect->excludes(o_domain);
    app.add_option("--scale", scale, "element size (bounding-box diagonal of its skeleton), mm")->required();
    app.add_option("--width", width, "strip width, mm")->required();
    auto* o_rot = app.add_option("--rotation", rotation_deg, "constant element rotation, degrees (counter-clockwise, y up)");
    auto* o_fimg = app.add_option("--field-image", field_image, "grayscale PNG over the domain's bounding box: element scale from black to white")
                       ->check(CLI::ExistingFile);
    app.add_option("--field-scale", field_scale, "S0 S1: scale factors at black and white of --field-image")->expected(2);
    o_rot->excludes(o_fimg);
    app.add_option("--thickness", thickness, "extrusion and shell thickness, mm (structural optimization may raise it)")->capture_default_str();
    app.add_option("--material", material, "abs | pla (elastic constants and yield stress, filigree/structure.hpp)")->capture_default_str();
    app.add_option("--pressure", pressure, "external pressure on the piece, Pa (§5)")->capture_default_str();
    app.add_flag("--no-structure", no_structure, "skip the structural optimization (§5)");
    app.add_option("--seed", seed, "variety seed (same seed -> identical output)");
    app.add_option("--sigma-d", sigma_d, "distortion bound of smooth connections (Table 1: 0.13-0.17)")->capture_default_str();
    app.add_option("--sigma-f", sigma_f, "fraction of the best pairs boosting learns from (Table 1: 0.045-0.05)")->capture_default_str();
    app.add_option("--rounds", rounds, "most rounds of placement + boosting")->capture_default_str();
    app.add_option("--tolerance", tolerance, "polygonal approximation of the element skeletons, mm")->capture_default_str();
    app.add_option("--max-elements", max_elements, "refuse domains estimated to need more element instances than this")->capture_default_str();
    app.add_option("-o,--output", out_path, "output SVG; OUT.stl, OUT.png, OUT_steps.png and OUT.json are written beside it")->required();
    filigree_tool::surface_request on_mesh;
    auto* o_mesh = app.add_option("--mesh", on_mesh.mesh, "base surface (OBJ, STL, PLY, 3MF): synthesize on it instead of a 2D domain")
                       ->check(CLI::ExistingFile);
    app.add_option("--mesh-size", on_mesh.mesh_size, "scale the base mesh so its bounding box's largest side is this many mm (default: as is, mm)");
    auto* o_region = app.add_option("--region", on_mesh.region, "text file of face ids (0-based) of the base mesh to cover (default: all)")
                         ->check(CLI::ExistingFile);
    app.add_option("--region-curve", on_mesh.region_curve,
                   "CSV of x,y,z points (the mesh's units, before --mesh-size) of a closed curve on the base mesh, each within 2% of the "
                   "mesh's diagonal of it: cover the smaller side it encloses")
        ->check(CLI::ExistingFile)
        ->excludes(o_region);
    app.add_option("--up", on_mesh.up, "X Y Z: the elements' up vector, projected onto the surface (default 0 0 1)")->expected(3);
    app.add_option("--field-scale-file", on_mesh.scale_file, "text file of one element scale factor per mesh vertex")->check(CLI::ExistingFile);
    o_mesh->excludes(o_rect)->excludes(o_domain)->excludes(o_fimg)->excludes(o_rot);

    return tool::run(app, common, argc, argv, [&] {
        auto progress = common.progress();
        if (!on_mesh.mesh.empty()) {
            reinforcement_options ro;
            ro.material = material == "pla" ? material_preset::pla : material == "abs" ? material_preset::abs : throw invalid_input("--material must be abs or pla, got '" + material + "'");
            ro.thickness = thickness, ro.pressure_pa = pressure, ro.enabled = !no_structure, ro.seed = seed;
            return run_surface_mode(on_mesh, element_args, scale, width, ro, tolerance, sigma_d, sigma_f, rounds, max_elements, out_path, common, progress);
        }
        const auto t_start = std::chrono::steady_clock::now();
        const fs::path svg_out(out_path);
        fs::path stl_out = svg_out, png_out = svg_out, json_out = svg_out;
        stl_out.replace_extension(".stl");
        png_out.replace_extension(".png");
        json_out.replace_extension(".json");
        const fs::path steps_out = svg_out.parent_path() / (svg_out.stem().string() + "_steps.png");
        std::vector<element_arg> elements;
        for (const std::string& a : element_args) elements.push_back(parse_element(a));
        std::vector<fs::path> inputs;
        for (const auto& e : elements) inputs.emplace_back(e.path);
        if (!domain_path.empty()) inputs.emplace_back(domain_path);
        if (!field_image.empty()) inputs.emplace_back(field_image);
        tool::check_outputs(inputs, {svg_out, stl_out, png_out, steps_out, json_out});
        for (const auto& e : elements)
            if (!fs::is_regular_file(e.path)) throw io_error(e.path, 0, "no such element file");
        if (rect.empty() == domain_path.empty()) throw invalid_input("give exactly one of --rect and --domain");
        check_common_ranges(scale, width, thickness, tolerance, sigma_d, sigma_f, rounds);
        if (!(std::isfinite(pressure) && pressure >= 0)) throw invalid_input("--pressure must be finite and >= 0 Pa");
        if (!std::isfinite(rotation_deg)) throw invalid_input("--rotation must be finite");
        if (!field_image.empty() && field_scale.size() != 2) throw invalid_input("--field-image needs --field-scale S0 S1");
        if (field_image.empty() && !field_scale.empty()) throw invalid_input("--field-scale needs --field-image");
        for (double s : field_scale) tool::require_range(s, 1e-2, 1e2, "--field-scale", "");
        const material_preset mat = material == "pla" ? material_preset::pla : material == "abs" ? material_preset::abs : throw invalid_input("--material must be abs or pla, got '" + material + "'");
        tool::output_set outputs;
        const fs::path svg_file = outputs.add(svg_out), stl_file = outputs.add(stl_out), png_file = outputs.add(png_out),
                       steps_file = outputs.add(steps_out), json_file = outputs.add_manifest(json_out);

        progress(0.0, "read elements");
        const planar_domain domain = rect.empty() ? planar_domain::from_svg(io::read_svg(domain_path, 0.01), domain_path)
                                                  : planar_domain::rectangle(tool::require_range(rect[0], 1e-2, 1e5, "--rect width", "mm"),
                                                                             tool::require_range(rect[1], 1e-2, 1e5, "--rect height", "mm"));
        std::vector<element> classes;
        std::vector<double> weights;
        load_classes(elements, scale, width, tolerance, classes, weights);
        {  // the pattern's size before any work: initialization covers >= 40% new area per element
            double smallest = std::numeric_limits<double>::infinity();
            const double s_min = field_scale.empty() ? 1.0 : std::min(field_scale[0], field_scale[1]);
            for (std::size_t c = 0; c < classes.size(); ++c)
                if (weights[c] > 0) smallest = std::min(smallest, classes[c].covering_area * s_min * s_min);
            if (!std::isfinite(smallest)) throw invalid_input("--element: every class has weight 0");
            tool::require_range(max_elements, 1, 1e6, "--max-elements", "");
            tool::require_work(domain.area / (0.4 * smallest), max_elements, 25.0, "element instances", "--max-elements",
                               "a domain of " + std::to_string(domain.area) + " mm^2 with elements of " + std::to_string(smallest) + " mm^2",
                               "or a larger --scale");
        }
        any_field field = constant_field{rotation_deg * std::numbers::pi / 180.0, 1.0};
        std::string field_kind = "constant";
        if (!field_image.empty()) {
            image8 img = io::read_png(field_image);
            if (img.channels != 1) {  // luminance of colour pictures
                image8 g(img.width, img.height, 1);
                for (int y = 0; y < img.height; ++y)
                    for (int x = 0; x < img.width; ++x) {
                        int s = 0;
                        for (int c = 0; c < std::min(3, img.channels); ++c) s += img.at(x, y, c);
                        g.at(x, y) = static_cast<std::uint8_t>(s / std::min(3, img.channels));
                    }
                img = std::move(g);
            }
            field = image_field(std::move(img), domain.bounds, field_scale[0], field_scale[1], rotation_deg * std::numbers::pi / 180.0);
            field_kind = "image";
        }

        progress(0.05, "synthesis");
        synthesis_options so;
        so.seed = seed, so.sigma_d = sigma_d, so.sigma_f = sigma_f, so.max_rounds = rounds;
        so.init.max_elements = static_cast<std::size_t>(max_elements);
        synthesis_result syn = synthesize_pattern(std::span<const element>(classes), weights, domain, field, so);

        progress(0.6, "strips");
        reinforcement_options ro;
        ro.material = mat, ro.thickness = thickness, ro.pressure_pa = pressure, ro.enabled = !no_structure, ro.seed = seed;
        const reinforcement_result rf = reinforce(std::span<const element>(classes), weights, domain, field, so, syn, ro);
        const std::vector<polygon_with_holes>& drawn = rf.outline;
        if (drawn.empty()) throw solver_error("the synthesized pattern is empty");

        progress(0.85, "mesh");
        triangle_mesh mesh = printable_extrusion(drawn, rf.thickness);
        mirror_y(mesh);
        weld_to_float(mesh);
        require_watertight(mesh, "the extruded filigree, rounded to single precision,");

        const box2 view = framed_view(domain.bounds, 0.02);
        const io::svg_document doc = io::document_of(drawn, view);
        const image8 png = preview_image(drawn, view, {.max_side = 1600, .supersample = 4});
        const image8 steps = steps_image({strips_of(skeletons_of(classes, syn.initial, domain), domain),
                                          strips_of(skeletons_of(classes, syn.placed_once, domain), domain),
                                          strips_of(skeletons_of(classes, syn.instances, domain), domain), strips_of(syn.skeletons, domain)},
                                         view);

        std::vector<std::size_t> per_class(classes.size(), 0);
        for (const instance& in : rf.instances) ++per_class[in.cls];
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
            {"pieces_dropped_area_fraction", rf.dropped_area_fraction},
            {"structure", {{"analysed", rf.analysed}, {"material", material}, {"pressure_pa", pressure}, {"yield_mpa", rf.yield_mpa},
                           {"fem_nodes", rf.fem_nodes}, {"solver", rf.solver}, {"histogram_bin_mpa", rf.histogram_bin_mpa},
                           {"histogram_before", rf.histogram_before}, {"histogram_after", rf.histogram_after},
                           {"max_von_mises_before_mpa", rf.max_von_mises_before}, {"max_von_mises_after_mpa", rf.max_von_mises_after},
                           {"weak_fraction_phase1", rf.weak_fraction_phase1}, {"inserted_per_round", rf.inserted_per_round},
                           {"thickness_phase2_mm", rf.thickness_phase2}, {"weak_fraction_phase2", rf.weak_fraction_phase2}}},
            {"thickness_mm", rf.thickness},
            {"stl_triangles", mesh.faces.size()},
            {"seconds", {{"initialization", syn.seconds.initialization}, {"placement", syn.seconds.placement}, {"boosting", syn.seconds.boosting},
                         {"topology_cut", syn.seconds.topology_cut}, {"structure", rf.seconds},
                         {"total", std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count()}}},
        };
        report.update(filigree_tool::layout_fields(syn));
        for (std::size_t c = 0; c < classes.size(); ++c)
            report["elements"].push_back({{"file", elements[c].path}, {"weight", weights[c]}, {"instances", per_class[c]},
                                          {"skeleton_vertices", classes[c].vertices.size()}, {"size_mm", classes[c].size}});

        progress(0.95, "write");
        io::write_svg(svg_file, doc);
        io::write_stl(stl_file, mesh);
        io::write_png(png_file, png);
        io::write_png(steps_file, steps);
        filigree_tool::write_report(json_file, json_out, report);
        outputs.commit();
        progress(1.0, "write");
        char line[400];
        std::snprintf(line, sizeof line, "%s: %zu instances of %zu element classes, %d rounds, PME %.1f -> %.1f, %zu component(s), thickness %.3g mm",
                      svg_out.string().c_str(), rf.instances.size(), classes.size(), syn.rounds, syn.energy_initial, syn.energy_final, rf.components,
                      rf.thickness);
        common.say(line);
        common.summary(report);
    });
}
