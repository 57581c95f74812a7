// foam_slicer: procedural Voronoi foams (Martinez et al. 2016) without ever meshing the foam.
//
//   foam_slicer seeds --box X0 Y0 Z0 X1 Y1 Z1 --out SEEDS.csv [foam options]
//   foam_slicer eval  --points IN.csv --out OUT.csv [foam options]
//   foam_slicer slice MESH --out-dir DIR [foam options] [field options] [--pixel P] [--layer H]
//                     [--slices N] [--supersample S] [--frame T] [--cut PX PY PZ NX NY NZ]...
//                     [--size MM] [--y-up] [--stl-box X0 Y0 Z0 X1 Y1 Z1 --stl-voxel V] [--beams-box X0 Y0 Z0 X1 Y1 Z1]
//
// foam options: --density RHO | --density-x RHO0 RHO1 X0 X1, --radius TAU, --cell L, --seed S.
// slice field options (the field gives seeds/mm^3, or E/Es with --elasticity):
//   --field-axis AXIS V0 V1 C0 C1        linear along axis 0/1/2 between coordinates C0 and C1
//   --field-image PNG --field-rect X0 Y0 X1 Y1 V0 V1
//                                         grayscale image on the rectangle [X0,X1]x[Y0,Y1] of every
//                                         z-plane (row 0 at Y1, i.e. the picture as seen from +z),
//                                         black = V0, white = V1
//   --field-surface V_NEAR V_FAR DEPTH     V_NEAR at the surface, linear to V_FAR at DEPTH mm inside
//   --elasticity                          values are relative Young's moduli E/Es, mapped to density
//                                         at tau = --radius by the shipped homogenization fit
//                                         E = P(rho, tau) (foam/elasticity_fit.hpp, paper §4.2);
//                                         --radius must lie in the fitted radius range, and targets
//                                         outside the reachable range are clamped (with a note).
// Outputs of slice: DIR/slice_NNNNN.png (255 = solid; pixel size in the PNG's pHYs chunk),
// DIR/slices.json (pixel size, layer height, origin, count and file of every slice, written
// last: a stack without it is incomplete), DIR/preview.png, optional DIR/foam.stl (marching cubes
// of the sub-box; also foam.3mf where lib3mf is available) and DIR/beams.vtk (beam network: lines
// + radius per line). Every option is checked, and the stack's memory and pixel evaluations are
// estimated (--max-memory, --max-pixels), before any work; the files move into DIR together at
// the end (examples/common/output_set.hpp).
// Conventions (exit codes, --quiet, --json, --version): docs/tools.md.

#include <fabsynth/foam.hpp>
#include <fabsynth/geometry/distance.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/points.hpp>
#include <fabsynth/io/vtk.hpp>
#include <fabsynth/io/atomic_file.hpp>
#if defined(FABSYNTH_HAS_LIB3MF)
#include <fabsynth/io/mesh_3mf.hpp>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "output_set.hpp"
#include "print_mesh.hpp"
#include "tool.hpp"

namespace fs = std::filesystem;
using namespace fabsynth;
using namespace fabsynth::foam;

namespace {

// The density field chosen on the command line (seeds/mm^3, or E/Es mapped to seeds/mm^3).
using value_field = variant_field<constant_field, linear_field, image_field, surface_distance_field>;
using density_field = variant_field<value_field, elasticity_density_field<value_field>>;

struct foam_args {
    double density = 0.2;
    std::vector<double> density_x;
    double radius = 0.25;
    double cell = 2.0;
    std::uint64_t seed = 1;
};

void add_foam_options(CLI::App* app, foam_args& a) {
    auto* d = app->add_option("--density", a.density, "uniform seed density, seeds/mm^3");
    app->add_option("--density-x", a.density_x, "RHO0 RHO1 X0 X1: density linear in x (constant outside)")
        ->expected(4)
        ->excludes(d);
    app->add_option("--radius", a.radius, "beam radius tau, mm");
    app->add_option("--cell", a.cell, "coarse cell size L, mm");
    app->add_option("--seed", a.seed, "global random seed");
}

// --density or --density-x as a field.
value_field field_from(const foam_args& a) {
    if (a.density_x.size() != 4) return {constant_field{a.density}};
    const linear_field f{.axis = 0, .v0 = a.density_x[0], .v1 = a.density_x[1], .x0 = a.density_x[2], .x1 = a.density_x[3]};
    if (f.x0 == f.x1) throw invalid_input("--density-x: X0 and X1 must differ");
    return {f};
}

// Pixel evaluations per second of one core of the reference machine (benchmarks/README.md, foam
// slicing), only to turn a refused stack into hours in the message; and the bytes a seed costs in
// memory (its vec3 and its CSV line).
constexpr double slice_pixels_per_second = 6e6, bytes_per_seed = 96;

// A box given as X0 Y0 Z0 X1 Y1 Z1 on the command line; refused unless finite with X0 < X1 etc.
box3 box_option(const std::vector<double>& v, const char* option) {
    const box3 b({v[0], v[1], v[2]}, {v[3], v[4], v[5]});
    if (!all_finite(b.lo) || !all_finite(b.hi) || !(b.lo.x < b.hi.x && b.lo.y < b.hi.y && b.lo.z < b.hi.z))
        throw invalid_input(std::string(option) + ": need finite X0 < X1, Y0 < Y1, Z0 < Z1");
    return b;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"foam_slicer: procedural Voronoi foams (seeds, point evaluation, slicing a mesh)", "foam_slicer"};
    tool::common common(app);
    app.require_subcommand(1);
    foam_args fa;

    auto* seeds_cmd = app.add_subcommand("seeds", "write every seed in a box as x,y,z lines");
    std::vector<double> box;
    std::string out;
    seeds_cmd->add_option("--box", box, "X0 Y0 Z0 X1 Y1 Z1 (mm)")->expected(6)->required();
    seeds_cmd->add_option("--out", out, "output CSV")->required();
    add_foam_options(seeds_cmd, fa);

    auto* eval_cmd = app.add_subcommand("eval", "evaluate F at x,y,z points: one line 1 (solid) or 0 each");
    std::string points;
    eval_cmd->add_option("--points", points, "input CSV of x,y,z lines")->required();
    eval_cmd->add_option("--out", out, "output file")->required();
    add_foam_options(eval_cmd, fa);

    auto* slice_cmd = app.add_subcommand("slice", "slice a mesh filled with graded foam into a PNG stack");
    std::string mesh_path, out_dir;
    double pixel = 0.05, layer = 0, frame = 0.5, size = 0, stl_voxel = 0.05;
    int nslices = 0, supersample = 1;
    std::vector<double> field_axis, field_image_rect, field_surface, stl_box, beams_box, cut_list;
    std::string field_image;
    bool elasticity = false, y_up = false;
    slice_cmd->add_option("mesh", mesh_path, "closed input mesh (.obj/.stl/.ply)")->required()->check(CLI::ExistingFile);
    slice_cmd->add_option("--out-dir", out_dir, "output directory")->required();
    add_foam_options(slice_cmd, fa);
    slice_cmd->add_option("--pixel", pixel, "pixel size, mm");
    slice_cmd->add_option("--layer", layer, "layer height, mm (default: pixel size)");
    slice_cmd->add_option("--slices", nslices, "write only N evenly spaced slices (0 = every layer)");
    slice_cmd->add_option("--supersample", supersample, "S x S samples per pixel (grayscale exposure)");
    slice_cmd->add_option("--frame", frame, "frame thickness, mm (0 = no frame)");
    slice_cmd->add_option("--cut", cut_list, "PX PY PZ NX NY NZ: cut plane without frame (keeps n.(x-p) <= 0)")
        ->expected(6)->take_all()->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    slice_cmd->add_flag("--y-up", y_up, "the mesh is y-up: rotate it so +y becomes +z (build direction)");
    slice_cmd->add_option("--size", size, "scale the mesh so its longest side is this many mm (0 = as is)");
    slice_cmd->add_option("--field-axis", field_axis, "AXIS V0 V1 C0 C1")->expected(5);
    slice_cmd->add_option("--field-image", field_image, "grayscale PNG mapped on a rectangle (see --field-rect)");
    slice_cmd->add_option("--field-rect", field_image_rect, "X0 Y0 X1 Y1 V0 V1 for --field-image")->expected(6);
    slice_cmd->add_option("--field-surface", field_surface, "V_NEAR V_FAR DEPTH")->expected(3);
    slice_cmd->add_flag("--elasticity", elasticity, "field values are E/Es, mapped by the fitted E = P(rho, tau) at tau = --radius");
    slice_cmd->add_option("--stl-box", stl_box, "X0 Y0 Z0 X1 Y1 Z1: export this sub-box as foam.stl")->expected(6);
    slice_cmd->add_option("--stl-voxel", stl_voxel, "marching-cubes sample spacing for --stl-box, mm");
    tool::mesh_simplification simplify(*slice_cmd, 0, "half of --stl-voxel");
    slice_cmd->add_option("--beams-box", beams_box, "X0 Y0 Z0 X1 Y1 Z1: export the beam network as beams.vtk")
        ->expected(6);
    double max_memory_gib = 16, max_pixels = 1e11;
    tool::add_memory_limit(app, max_memory_gib);
    slice_cmd->add_option("--max-pixels", max_pixels, "refuse stacks needing more pixel evaluations than this (slices x pixels x supersample^2)")
        ->check(CLI::PositiveNumber);

    return tool::run(app, common, argc, argv, [&] {
        auto progress = common.progress();
        if (seeds_cmd->parsed() || eval_cmd->parsed()) {
            tool::check_outputs({points}, {out});
            const density_field rho{field_from(fa)};
            const voronoi_foam f(rho, constant_field{fa.radius}, {.cell = fa.cell, .seed = fa.seed});
            tool::output_set outputs;
            const fs::path out_file = outputs.add(out);
            if (seeds_cmd->parsed()) {
                const box3 b = box_option(box, "--box");
                const double rho_max = fa.density_x.size() == 4 ? std::max(fa.density_x[0], fa.density_x[1]) : fa.density;
                const vec3 e = b.size();
                tool::require_memory(rho_max * e.x * e.y * e.z * bytes_per_seed, max_memory_gib,
                                     "--box with up to " + std::to_string(rho_max * e.x * e.y * e.z) + " seeds");
                const std::vector<vec3> seeds = f.seeds().seeds_in_box(b);
                io::write_points_csv(out_file, seeds);
                outputs.commit();
                common.say("foam_slicer seeds: " + std::to_string(seeds.size()) + " seeds -> " + out);
                common.summary({{"command", "seeds"}, {"seeds", seeds.size()}, {"outputs", {out}}});
            } else {
                const auto pts = io::read_points_csv(points);
                std::vector<std::uint8_t> r(pts.size());
                f.contains(pts, r);  // the batch query: visited block by block, in parallel
                std::string text;
                text.reserve(2 * pts.size());
                std::size_t inside = 0;
                for (const std::uint8_t c : r) text += c ? '1' : '0', text += '\n', inside += c;
                io::atomic_write(out_file, text);
                outputs.commit();
                common.say("foam_slicer eval: " + std::to_string(inside) + " of " + std::to_string(pts.size()) + " points solid -> " + out);
                common.summary({{"command", "eval"}, {"points", pts.size()}, {"solid", inside}, {"outputs", {out}}});
            }
            return;
        }

        // ---- slice ---- every option is checked before the first file is written
        require_positive(pixel, "--pixel");
        if (!(layer >= 0) || !std::isfinite(layer)) throw invalid_input("--layer must be finite and >= 0 mm (0 = the pixel size)");
        if (nslices < 0) throw invalid_input("--slices must be >= 0 (0 = every layer)");
        if (supersample < 1 || supersample > 16) throw invalid_input("--supersample must be in [1, 16]");
        if (!(size >= 0) || !std::isfinite(size)) throw invalid_input("--size must be finite and >= 0 mm (0 = as is)");
        if (field_axis.size() == 5 && field_axis[0] != std::floor(field_axis[0]))
            throw invalid_input("--field-axis: AXIS must be 0, 1 or 2");
        std::optional<box3> stl_region, beams_region;
        if (stl_box.size() == 6) stl_region = box_option(stl_box, "--stl-box"), require_positive(stl_voxel, "--stl-voxel");
        if (beams_box.size() == 6) beams_region = box_option(beams_box, "--beams-box");
        const fs::path dir(out_dir);
        tool::check_outputs({mesh_path, field_image},
                            {dir / "preview.png", dir / "slices.json", dir / "foam.stl", dir / "foam.3mf", dir / "beams.vtk"});
        if (stl_region) {  // marching-cubes samples of the sub-box (a float per sample and the mesh)
            const vec3 e = stl_region->size() / stl_voxel;
            tool::require_memory((e.x + 2) * (e.y + 2) * (e.z + 2) * 16.0, max_memory_gib, "--stl-box at --stl-voxel " + std::to_string(stl_voxel));
        }
        progress(0.0, "read mesh");
        triangle_mesh mesh = io::read_mesh(mesh_path);
        validate(mesh, mesh_path.c_str());
        if (y_up) rotate_y_up_to_z_up(mesh);
        if (size > 0) fit_to_size(mesh, size);
        const mesh_distance md(mesh);
        md.require_watertight();
        value_field values = field_from(fa);
        double v_lo = 0, v_hi = 0;  // range of the field's values (for --elasticity)
        if (field_axis.size() == 5) {
            const linear_field f{.axis = static_cast<int>(field_axis[0]), .v0 = field_axis[1], .v1 = field_axis[2],
                                 .x0 = field_axis[3], .x1 = field_axis[4]};
            if (f.axis < 0 || f.axis > 2) throw invalid_input("--field-axis: AXIS must be 0, 1 or 2");
            if (f.x0 == f.x1) throw invalid_input("--field-axis: C0 and C1 must differ");
            values.field = f, v_lo = f.v0, v_hi = f.v1;
        } else if (!field_image.empty()) {
            if (field_image_rect.size() != 6) throw invalid_input("--field-image needs --field-rect X0 Y0 X1 Y1 V0 V1");
            const auto& r = field_image_rect;
            if (r[0] >= r[2] || r[1] >= r[3]) throw invalid_input("--field-rect: need X0 < X1 and Y0 < Y1");
            values.field = image_field(io::read_png(field_image), box2({r[0], r[1]}, {r[2], r[3]}), r[4], r[5]);
            v_lo = r[4], v_hi = r[5];
        } else if (field_surface.size() == 3) {
            require_positive(field_surface[2], "--field-surface DEPTH");
            values.field = surface_distance_field(md, field_surface[0], field_surface[1], field_surface[2]);
            v_lo = field_surface[0], v_hi = field_surface[1];
        } else if (fa.density_x.size() == 4) {
            v_lo = fa.density_x[0], v_hi = fa.density_x[1];
        } else {
            v_lo = v_hi = fa.density;
        }
        density_field field{values};
        if (elasticity) {
            const elasticity_density_field<value_field> e(values, fa.radius, std::min(v_lo, v_hi), std::max(v_lo, v_hi));
            const auto [reach_lo, reach_hi] = e.reachable();
            if (e.e_lo() < reach_lo || e.e_hi() > reach_hi)
                std::cerr << "note: --elasticity targets outside [" << reach_lo << ", " << reach_hi
                          << "] (reachable with the fitted model at tau = " << fa.radius << " mm) are clamped\n";
            field.field = e;
        }
        const voronoi_foam foam(field, constant_field{fa.radius}, {.cell = fa.cell, .seed = fa.seed});
        frame_options fo{.thickness = frame, .cuts = {}};
        for (std::size_t i = 0; i + 5 < cut_list.size(); i += 6)
            fo.cuts.push_back({{cut_list[i], cut_list[i + 1], cut_list[i + 2]}, {cut_list[i + 3], cut_list[i + 4], cut_list[i + 5]}});
        const framed_foam obj(foam, md, fo);

        const box3 bb = bounding_box(mesh);
        {  // the cost of the stack, before it is planned
            const slice_stack_cost cost = estimate_slice_stack(bb, pixel, layer, nslices, supersample, static_cast<double>(slice_options{}.slab_bytes));
            const double px = cost.pixels_per_slice;
            char what[160];
            std::snprintf(what, sizeof what, "a stack of %.0f slices of %.3g pixels (%.3g mm) at supersample %d", cost.slices, px, pixel, supersample);
            // the slab, the four preview copies, the PNG encoder's buffer and the side-by-side preview
            tool::require_memory(cost.slab_bytes + px * (4 + 2 + 4), max_memory_gib, what);
            tool::require_work(cost.evaluations, max_pixels, slice_pixels_per_second, "pixel evaluations", "--max-pixels", what);
        }
        const slice_stack stack = plan_slice_stack(bb, pixel, layer, nslices);
        const box2& region = stack.region;
        const std::vector<int>& which = stack.selected;
        std::vector<fs::path> slice_files;
        for (int k : which) {
            char name[64];
            std::snprintf(name, sizeof name, "slice_%05d.png", k);
            slice_files.push_back(dir / name);
        }
        tool::check_outputs({mesh_path, field_image}, slice_files);
        // Every file is staged and moves into DIR only when the whole set is written; slices.json,
        // the manifest of a complete stack, goes last (and the previous one first).
        tool::output_set outputs;
        std::vector<fs::path> staged_slices;
        for (const fs::path& p : slice_files) staged_slices.push_back(outputs.add(p));
        const fs::path preview_png = outputs.add(dir / "preview.png"), foam_stl = outputs.add(dir / "foam.stl"),
                       beams_vtk = outputs.add(dir / "beams.vtk"), manifest_json = outputs.add_manifest(dir / "slices.json");
#if defined(FABSYNTH_HAS_LIB3MF)
        const fs::path foam_3mf = outputs.add(dir / "foam.3mf");
#endif
        const slice_options so{.supersample = supersample};
        std::uint64_t pixels = 0, solid = 0;
        double total_ms = 0;
        std::vector<image8> preview;
        nlohmann::ordered_json files = nlohmann::ordered_json::array();
        // the stack is rendered a slab at a time (the edges of each tile column once per slab);
        // each slice is written as it is handed over, in order
        std::vector<double> heights;
        for (int k : which) heights.push_back(stack.z(k));
        double emit_ms = 0;
        const auto t0 = std::chrono::steady_clock::now();
        obj.for_each_slice(heights, region, pixel, [&](std::size_t s, image8& img) {
            const auto e0 = std::chrono::steady_clock::now();
            pixels += img.data.size();
            for (auto v : img.data) solid += v;
            char name[64];
            std::snprintf(name, sizeof name, "slice_%05d.png", which[s]);
            io::write_png(staged_slices[s], img, {.pixel_mm = pixel});
            files.push_back({{"layer", which[s]}, {"z_mm", heights[s]}, {"file", name}});
            // preview: 4 slices spread over the stack
            if (preview.size() < 4 && s == (preview.size() * which.size()) / 4) preview.push_back(img);
            progress(static_cast<double>(s + 1) / static_cast<double>(which.size()), "slices");
            emit_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - e0).count();
        }, so);
        total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() - emit_ms;
        // preview: up to 4 slices side by side, +y up
        if (!preview.empty())
            io::write_png(preview_png, side_by_side(preview, 4, std::uint8_t{128}, true), {.pixel_mm = pixel});
        std::size_t stl_triangles = 0, beam_count = 0;
        if (stl_region) {
            progress(0.0, "foam.stl");
            simplify.default_tolerance(0.5 * stl_voxel);
            const triangle_mesh m = simplify(framed_foam_mesh(obj, *stl_region, stl_voxel), common, "foam.stl");
            io::write_mesh(foam_stl, m);
#if defined(FABSYNTH_HAS_LIB3MF)
            io::write_3mf(foam_3mf, m, {.name = "foam"});
#endif
            stl_triangles = m.faces.size();
            if (!common.quiet()) std::cerr << "foam.stl: " << m.faces.size() << " triangles\n";
        }
        if (beams_region) {
            const beam_network net = extract_beams(foam, *beams_region);
            std::vector<io::vtk_cell> cells;
            for (const auto& e : net.edges) cells.push_back({io::vtk_cell_type::line, {e[0], e[1]}});
            io::write_vtk_unstructured(beams_vtk, net.nodes, cells, {},
                                       {io::vtk_field{"radius", 1, net.radii}}, io::encoding::ascii);
            beam_count = net.edges.size();
            if (!common.quiet()) std::cerr << "beams.vtk: " << net.nodes.size() << " nodes, " << net.edges.size() << " beams\n";
        }
        const nlohmann::ordered_json manifest = {{"pixel_mm", pixel},
                                                 {"layer_mm", stack.layer},
                                                 {"origin_mm", {region.lo.x, region.lo.y}},
                                                 {"width_px", files.empty() ? 0 : preview[0].width},
                                                 {"height_px", files.empty() ? 0 : preview[0].height},
                                                 {"value", "255 = solid, 0 = empty (grey levels with --supersample)"},
                                                 {"count", files.size()},
                                                 {"slices", files}};
        io::atomic_write(manifest_json, manifest.dump(2) + "\n");
        outputs.commit();
        const double ms = total_ms / static_cast<double>(which.size());
        const double solid_percent = 100.0 * double(solid) / 255.0 / double(std::max<std::uint64_t>(1, pixels));
        char line[256];
        std::snprintf(line, sizeof line, "foam_slicer: %zu slices of %dx%d px (%.3f mm), %llu voxels, solid volume %.2f%%, %.1f ms/slice, %.2f Mpixel/s",
                      which.size(), static_cast<int>(std::ceil((region.hi.x - region.lo.x) / pixel - 1e-9)),
                      static_cast<int>(std::ceil((region.hi.y - region.lo.y) / pixel - 1e-9)), pixel,
                      static_cast<unsigned long long>(pixels), solid_percent, ms, double(pixels) / (total_ms * 1e3));
        common.say(line);
        common.summary({{"command", "slice"},
                        {"slices", which.size()},
                        {"pixel_mm", pixel},
                        {"solid_percent", solid_percent},
                        {"ms_per_slice", ms},
                        {"stl_triangles", stl_triangles},
                        {"beams", beam_count},
                        {"manifest", (fs::path(out_dir) / "slices.json").string()}});
    });
}
