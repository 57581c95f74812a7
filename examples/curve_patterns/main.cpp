// curve_patterns: topology-constrained vector patterns along curves and in rectangles
// (Zhou, Jiang & Lefebvre 2014, "Topology-constrained synthesis of vector patterns").
//
//   curve_patterns --exemplar E.svg (--curve C.svg | --line LENGTH | --circle RADIUS | --rect W H |
//                  --curve3d C.csv [--twist DEG] | --mesh M.obj --points P.csv (--emboss H [--shell T] | --carve T) [--cell C])
//                  --height H [--components N] [--holes M] [--closed] [--closed-loop] [--seed S]
//                  [--thickness T] [--tolerance TOL] [--slicing reeb|uniform] [--beta B] -o OUT.svg
//
// The exemplar (filled shapes of an SVG band lying along x) is scaled uniformly so that its height
// equals H; pieces slide across the band by less than H/2 (§3.5), so the pattern stays within H of
// the curve. The pattern is synthesized in the curve's (u, v) parameter domain
// (vector_pattern/synthesis.hpp), mapped onto the curve (vector_pattern/band_map.hpp) and extruded to a
// watertight slab tessellated in the parameter domain (geometry/extrude.hpp, §6.3).
// --curve3d: a polyline in space (x,y,z rows, mm; geometry/space_curve.hpp: rotation-minimising
// frames, --twist degrees of extra turn about the tangent over the whole curve, a multiple of 360
// when --closed); the band lies along the frame's normal and the STL's thickness along its
// binormal; OUT.svg is then the developed band (u along the curve, v across) and OUT.png a shaded
// render of the solid from two opposite sides.
// --mesh/--points: a curve drawn on a disk-topology surface, or a closed genus-0 one which is cut open
// at the vertex farthest from the points (§6.3): the points (x,y,z rows, mm,
// snapped to the mesh) are joined by a spline in the mesh's harmonic parameterization
// (surface/disk_parameterization.hpp, surface/curve.hpp), with smoothed surface normals;
// the pattern is then embossed H mm above a shell of --shell mm around the surface, or carved out of
// a shell of T mm (surface/decoration.hpp), and OUT.stl is that one watertight solid;
// OUT.svg is the developed band and OUT.png a shaded render from two sides.
// Outputs: OUT.svg (filled shapes only), OUT.stl and OUT.3mf (where lib3mf is available; T mm thick, the SVG's y axis flipped so the print
// looks like the drawing), OUT.png (preview, pattern dark on white: geometry/coverage_image.hpp). Nothing is written unless
// everything succeeded; an impossible request exits with status 3 and the reason on stderr.
// Conventions (exit codes, --quiet, --json, --version): docs/tools.md.
// The pipeline is one library call, vector_pattern::make_pattern (vector_pattern/pipeline.hpp); this
// tool parses the arguments, reads the inputs, writes the outputs and prints the report.

#include <fabsynth/geometry/curve.hpp>
#include <fabsynth/geometry/space_curve.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/mesh_stl.hpp>
#include <fabsynth/io/points.hpp>
#include <fabsynth/io/svg.hpp>
#if defined(FABSYNTH_HAS_LIB3MF)
#include <fabsynth/io/mesh_3mf.hpp>
#endif
#include <fabsynth/vector_pattern/exemplar.hpp>
#include <fabsynth/vector_pattern/pipeline.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "output_set.hpp"
#include "print_mesh.hpp"
#include "tool.hpp"

namespace fs = std::filesystem;
using namespace fabsynth;
using fabsynth::tool::short_number;

namespace {
// Band heights synthesized, stitched, merged and extruded per second along a line (Greek key, 2
// threads, the 2-core VM; benchmarks/README.md "Tool limits"), rounded down: the rate of the
// --max-heights estimate.
constexpr double band_heights_per_second = 100.0;
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "curve_patterns: topology-constrained vector patterns along curves and in rectangles (Zhou et al. 2014).\n"
        "The exemplar is scaled uniformly so that its height equals --height; pieces slide across the band by\n"
        "less than --height/2, so the pattern stays within --height of the curve. Writes OUT.svg (filled shapes),\n"
        "OUT.stl (extruded, watertight) and OUT.png (preview) side by side. Holes count holes of the pattern\n"
        "glued along the band; on a closed curve a loop around the curve (--closed-loop) also encloses the\n"
        "curve's inside, which the drawing shows as one more enclosed region.",
        "curve_patterns"};
    tool::common common(app);
    std::string exemplar_path, curve_path, curve3d_path, mesh_path, points_path, out_path, slicing = "reeb";
    std::optional<double> line_length, circle_radius;
    std::vector<double> rect;
    double height = 0, thickness = 1.0, tolerance = 0.0, beta = 0.0;
    std::optional<double> twist, emboss, carve, shell, cell;
    std::optional<std::uint32_t> components, holes;
    bool closed = false, closed_loop = false;
    std::uint64_t seed = 0;
    app.add_option("--exemplar", exemplar_path, "exemplar SVG (filled shapes, a band along x)")->required()->check(CLI::ExistingFile);
    auto* o_curve = app.add_option("--curve", curve_path, "curve SVG: the first path/polyline/line/circle... is the curve")->check(CLI::ExistingFile);
    auto* o_line = app.add_option("--line", line_length, "straight line of this length (mm)");
    auto* o_circle = app.add_option("--circle", circle_radius, "circle of this radius (mm), closed");
    auto* o_rect = app.add_option("--rect", rect, "W H: rectangle of W x H mm, synthesized twice (§6.2)")->expected(2);
    auto* o_curve3d = app.add_option("--curve3d", curve3d_path, "curve in space: CSV of x,y,z rows (mm), a polyline")->check(CLI::ExistingFile);
    app.add_option("--twist", twist, "--curve3d: extra turn of the band about the curve over its length (degrees)")->needs(o_curve3d);
    o_curve3d->excludes(o_curve, o_line, o_circle, o_rect);
    auto* o_mesh = app.add_option("--mesh", mesh_path, "surface to decorate: a disk-topology mesh (OBJ, STL, PLY, mm)")->check(CLI::ExistingFile);
    auto* o_points = app.add_option("--points", points_path, "--mesh: CSV of x,y,z rows (mm), points on the surface the band's curve passes through")
                         ->check(CLI::ExistingFile)
                         ->needs(o_mesh);
    o_mesh->needs(o_points)->excludes(o_curve, o_line, o_circle, o_rect, o_curve3d);
    auto* o_emboss = app.add_option("--emboss", emboss, "--mesh: relief height above the shell (mm)")->needs(o_mesh);
    app.add_option("--carve", carve, "--mesh: cut the pattern out of a shell this thick (mm)")->needs(o_mesh)->excludes(o_emboss);
    app.add_option("--shell", shell, "--emboss: thickness of the shell around the surface (mm, default 2)")->needs(o_emboss);
    app.add_option("--cell", cell, "--mesh: grid spacing of the solid (mm; default a quarter of the relief or shell, at most --height/40)")->needs(o_mesh);
    double max_gib = 16.0, max_heights = 2000.0;
    tool::add_memory_limit(app, max_gib);
    app.add_option("--max-heights", max_heights,
                   "refuse bands longer than this many band heights before the work (it grows with the length; docs/tools.md, \"Limits\")")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    o_curve->excludes(o_line, o_circle, o_rect);
    o_line->excludes(o_circle, o_rect);
    o_circle->excludes(o_rect);
    app.add_option("--height", height, "band height H (mm): the exemplar is scaled to this height")->required();
    app.add_option("--components", components, "exact number of connected components");
    app.add_option("--holes", holes, "exact number of holes");
    app.add_flag("--closed", closed, "close the --curve path (last point joined to the first); a --circle is always closed");
    app.add_flag("--closed-loop", closed_loop, "closed curves: some component must wind around the loop (paper Fig. 6)");
    app.add_option("--seed", seed, "variety seed (same seed -> identical output)");
    app.add_option("--thickness", thickness, "STL thickness (mm)")->capture_default_str();
    app.add_option("--tolerance", tolerance, "max chord error of the mapped outlines (mm); default H/1000");
    app.add_option("--slicing", slicing, "exemplar slicing: reeb (topology-driven, §5.2) or uniform (§5.1)")->capture_default_str();
    app.add_option("--beta", beta, "autocorrelation penalty weight (§3.7), 0 = off")->capture_default_str();
    app.add_option("-o,--output", out_path, "output SVG; OUT.stl and OUT.png are written beside it")->required();
    tool::mesh_simplification simplify(app, 0.05, "0.05 mm");

    return tool::run(app, common, argc, argv, [&] {
        auto progress = common.progress();
        const fs::path svg_out(out_path);
        fs::path stl_out = svg_out, png_out = svg_out, threemf_out = svg_out;
        stl_out.replace_extension(".stl");
        png_out.replace_extension(".png");
        threemf_out.replace_extension(".3mf");
        tool::check_outputs({exemplar_path, curve_path, curve3d_path, mesh_path, points_path}, {svg_out, stl_out, png_out, threemf_out});
        const int shapes_given =
            !curve_path.empty() + line_length.has_value() + circle_radius.has_value() + !rect.empty() + !curve3d_path.empty() + !mesh_path.empty();
        if (shapes_given != 1) throw invalid_input("give exactly one of --curve, --line, --circle, --rect, --curve3d, --mesh");
        const bool on_surface = !mesh_path.empty();
        if (on_surface && !emboss && !carve) throw invalid_input("--mesh needs --emboss H or --carve T");
        if (twist && !std::isfinite(*twist)) throw invalid_input("--twist must be finite");
        // Lengths between 1 um and 100 m, and bands at most 1e5 heights long: beyond, the geometry's
        // tolerances (relative to the band height) underflow or overflow.
        constexpr double min_mm = 1e-3, max_mm = 1e5, max_band_heights = 1e5;
        tool::require_range(height, min_mm, max_mm, "--height", "mm");
        tool::require_range(thickness, min_mm, max_mm, "--thickness", "mm");
        if (tolerance == 0.0) tolerance = height / 1000.0;
        tool::require_range(tolerance, 1e-3 * min_mm, height, "--tolerance", "mm (at most --height)");
        auto require_band_length = [&](double length, const char* option) {
            tool::require_range(length, min_mm, max_band_heights * height, option, "mm (at most 1e5 x --height)");
            // The work grows with the band's length in heights (pieces to place, stitch and merge):
            // measured rate in benchmarks/README.md, "Tool limits".
            tool::require_work(length / height, max_heights, band_heights_per_second, "band heights", "--max-heights",
                               std::string(option) + " " + short_number(length) + " mm at --height " + short_number(height));
        };
        if (line_length) require_band_length(*line_length, "--line length");
        if (circle_radius) require_band_length(2 * 3.14159265358979 * tool::require_range(*circle_radius, min_mm, max_mm, "--circle", "mm"), "--circle length");
        if (rect.size() == 2) require_band_length(rect[0], "--rect width"), tool::require_range(rect[1], min_mm, max_mm, "--rect height", "mm");
        if (!(beta >= 0.0) || !std::isfinite(beta)) throw invalid_input("--beta must be finite and >= 0");
        if (closed && (line_length || !rect.empty())) throw invalid_input("--closed applies to --curve, --curve3d and --mesh (a --circle is always closed)");
        if (emboss) tool::require_range(*emboss, min_mm, max_mm, "--emboss", "mm");
        if (carve) tool::require_range(*carve, min_mm, max_mm, "--carve", "mm");
        if (shell) tool::require_range(*shell, min_mm, max_mm, "--shell", "mm");
        if (cell) tool::require_range(*cell, min_mm, max_mm, "--cell", "mm");
        if (slicing != "reeb" && slicing != "uniform") throw invalid_input("--slicing must be reeb or uniform, got '" + slicing + "'");
        tool::output_set outputs;  // the files appear together at the end of a successful run
        const fs::path svg_file = outputs.add(svg_out), stl_file = outputs.add(stl_out), png_file = outputs.add(png_out);
#if defined(FABSYNTH_HAS_LIB3MF)
        const fs::path threemf_file = outputs.add(threemf_out);
#endif

        // The exemplar as read (make_pattern scales it to the band height).
        progress(0.0, "read exemplar");
        const vector_pattern::exemplar raw = vector_pattern::exemplar_from_svg(io::read_svg(exemplar_path));
        if (!(raw.height() > 0.0)) throw invalid_input(exemplar_path + ": the exemplar has no height");
        // an extruded band of touching shapes is no closed solid: refused here, naming the file
        if (!on_surface) vector_pattern::require_separate_shapes(raw, exemplar_path);

        vector_pattern::pattern_options po;
        po.band_height = height;
        po.thickness = thickness;
        po.chord_tolerance = tolerance;
        po.synthesis.components = components;
        po.synthesis.holes = holes;
        po.synthesis.closed_loop = closed_loop;
        po.synthesis.seed = seed;
        po.synthesis.beta = beta;
        po.synthesis.slicing = slicing == "uniform" ? vector_pattern::slicing_method::uniform : vector_pattern::slicing_method::reeb;

        // The inputs, read and checked against the options that name them; what the run is, for the report.
        std::optional<vector_pattern::pattern_where> where;
        std::string what;
        const auto check_closed_loop = [&](bool closed_curve, const char* forms) {
            if (closed_loop && !closed_curve) throw invalid_input(std::string("--closed-loop needs a closed curve (") + forms + ")");
        };
        if (on_surface) {
            triangle_mesh surface = io::read_mesh(mesh_path);
            validate(surface, mesh_path.c_str());
            std::vector<vec3> picked = io::read_points_csv(points_path);
            po.decoration.mode = emboss ? decoration_mode::emboss : decoration_mode::carve;
            po.decoration.shell = emboss ? shell.value_or(2.0) : *carve;
            po.decoration.height = emboss.value_or(1.0);
            po.decoration.cell = cell.value_or(0.0);  // 0: make_pattern's default
            po.decoration.cell = vector_pattern::decoration_cell(po);
            tool::require_memory(vector_pattern::estimated_decoration_bytes(surface, po.decoration.cell), max_gib,
                                 "decorating " + mesh_path + " at a " + std::to_string(po.decoration.cell) + " mm cell");
            check_closed_loop(closed, "--mesh with --closed");
            where = vector_pattern::on_surface{.surface = std::move(surface), .points = std::move(picked), .closed = closed};
        } else if (!curve3d_path.empty()) {
            space_curve curve = space_curve::polyline(io::read_points_csv(curve3d_path), closed, {.twist_degrees = twist.value_or(0.0)});
            require_band_length(curve.length(), "--curve3d length");
            check_closed_loop(curve.closed(), "--curve3d with --closed");
            what = std::string(curve.closed() ? "closed" : "open") + " curve in space of length " + std::to_string(curve.length());
            where = vector_pattern::along_space_curve{std::move(curve)};
        } else if (!rect.empty()) {
            require_positive(rect[0], "--rect width");
            require_positive(rect[1], "--rect height");
            if (closed_loop) throw invalid_input("--closed-loop needs a closed curve");
            what = "rectangle " + std::to_string(rect[0]) + " x " + std::to_string(rect[1]);
            where = vector_pattern::in_rectangle{rect[0], rect[1]};
        } else {
            std::optional<planar_curve> curve;
            if (line_length) {
                curve = planar_curve::line(require_positive(*line_length, "--line length"));
                what = "line";
            } else if (circle_radius) {
                const double r = require_positive(*circle_radius, "--circle radius");
                curve = planar_curve::circle(r, {r + height, r + height});
                what = "circle";
            } else {
                // Flatten the curve finely: 1e-4 of its drawing's size (the band map needs smooth normals).
                const io::svg_document coarse = io::read_svg(curve_path);
                const box2 b = coarse.bounds();
                if (b.empty()) throw invalid_input(curve_path + ": the curve SVG has no shape");
                const double diag = glm::length(b.size());
                const io::svg_document doc = io::read_svg(curve_path, diag > 0.0 ? 1e-4 * diag : 0.01);
                curve = curve_from_svg(doc, closed);
                what = curve->closed() ? "closed curve" : "open curve";
            }
            if (!curve_path.empty()) require_band_length(curve->length(), "--curve length");
            check_closed_loop(curve->closed(), "--circle, or --curve with --closed");
            what += " of length " + std::to_string(curve->length());
            where = vector_pattern::along_planar_curve{std::move(*curve)};
        }

        // The pipeline: synthesis, mapping, the printable solid, the preview (progress within 5%-85%).
        const vector_pattern::pattern_result res = vector_pattern::make_pattern(
            raw, *where, po, [&](double fraction, std::string_view stage) { progress(0.05 + 0.8 * fraction, stage); });
        const triangle_mesh mesh = simplify(res.mesh, common, stl_out.filename().string());
        if (on_surface)
            what = std::string(emboss ? "embossed" : "carved") + (res.closed ? " closed" : " open") + " band of length " + std::to_string(res.band_length) +
                   " on " + mesh_path + (res.cut_open ? " (closed: cut open for the map, far from the points)" : "");
        const io::svg_document doc = io::document_of(res.drawn, res.view);

        progress(0.9, "write");
        io::write_svg(svg_file, doc);
        io::write_stl(stl_file, mesh);
#if defined(FABSYNTH_HAS_LIB3MF)
        io::write_3mf(threemf_file, mesh, {.name = svg_out.stem().string()});
#endif
        io::write_png(png_file, res.preview);
        outputs.commit();

        const std::size_t rings = res.rings, crossings = res.edge_crossings;
        const mesh_topology_info& solid = res.solid;
        progress(1.0, "write");
        // the distortion: every piece is stretched along the curve by L / (its pieces' natural length)
        const double stretch = res.stretch;
        const vector_pattern::synthesis_result& syn = res.synthesis;
        const std::string thick = on_surface ? "" : ", " + std::to_string(thickness) + " mm thick";
        char line[640];
        std::snprintf(line, sizeof line,
                      "%s: %s, exemplar %s scaled to height %g\npieces: %zu input, %zu in result, natural length %.2f mm "
                      "stretched by %.3f; DP %.3f s (%zu entries, %.1f MB)\n"
                      "topology: %u components, %u holes; %zu rings drawn; STL %zu triangles%s",
                      svg_out.string().c_str(), what.c_str(), exemplar_path.c_str(), height, syn.input_pieces, syn.sequence.size(),
                      syn.achieved_length, stretch, syn.dp_seconds, syn.dp_entries, static_cast<double>(syn.dp_peak_bytes) / (1024.0 * 1024.0), syn.components,
                      syn.holes, rings, mesh.faces.size(), thick.c_str());
        common.say(line);
        if (on_surface) {
            std::snprintf(line, sizeof line, "surface: %zu edge crossings in the curve; solid: %zu components, genus %lld", crossings, solid.components,
                          solid.genus);
            common.say(line);
        }
        common.summary({{"shape", what},
                        {"edge_crossings", crossings},
                        {"solid_components", solid.components},
                        {"solid_genus", solid.genus},
                        {"components", syn.components},
                        {"holes", syn.holes},
                        {"input_pieces", syn.input_pieces},
                        {"result_pieces", syn.sequence.size()},
                        {"natural_length_mm", syn.achieved_length},
                        {"stretch", stretch},
                        {"rings", rings},
                        {"dp_seconds", syn.dp_seconds},
                        {"stl_triangles", mesh.faces.size()},
                        {"outputs", {svg_out.string(), stl_out.string(), png_out.string()}}});
    });
}
