// voxelize MESH --resolution N -o OUTDIR
//
// Writes OUTDIR/shell.vtk (voxel cells with fields shell 0/1 and solid 0/1 as bytes, normal as
// floats), OUTDIR/solid.stl (marching cubes of the solid voxels, simplified within
// --mesh-tolerance, default half a voxel: watertight; also solid.3mf where lib3mf is available) and OUTDIR/slices.png (z-slices: shell coloured by normal | solid), and
// prints a one-line summary (--json: a JSON summary). The memory the run needs is estimated
// before anything is allocated and refused above --max-memory; the four files appear together at
// the end of a successful run (examples/common/output_set.hpp). Conventions (exit codes, --quiet,
// --json, --version): docs/tools.md.
#include <fabsynth/core.hpp>
#include <fabsynth/geometry/marching_cubes.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/vtk.hpp>
#include <fabsynth/voxel.hpp>
#if defined(FABSYNTH_HAS_LIB3MF)
#include <fabsynth/io/mesh_3mf.hpp>
#endif

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "output_set.hpp"
#include "print_mesh.hpp"
#include "tool.hpp"

namespace fs = std::filesystem;
using namespace fabsynth;

namespace {

io::structured_points to_vtk(const shell_grid& shell, const voxel_grid<std::uint8_t>& solid) {
    const grid_geometry& g = shell.geometry();
    io::structured_points out{.dims = g.dims + 1, .origin = g.origin, .spacing = g.spacing, .cell_data = true, .fields = {}};
    const auto n = static_cast<std::size_t>(g.count());
    io::vtk_field is_shell{"shell", 1, std::vector<double>(n, 0.0), io::vtk_type::uint8};
    io::vtk_field is_solid{"solid", 1, std::vector<double>(n, 0.0), io::vtk_type::uint8};
    io::vtk_field normal{"normal", 3, std::vector<double>(3 * n, 0.0), io::vtk_type::float32};
    shell.for_each([&](ivec3 p, const shell_voxel& v) {
        const auto i = static_cast<std::size_t>(g.index(p));
        is_shell.values[i] = 1.0;
        for (int a = 0; a < 3; ++a) normal.values[3 * i + static_cast<std::size_t>(a)] = v.normal[a];
    });
    for (std::size_t i = 0; i < n; ++i) is_solid.values[i] = solid.storage().data()[i];
    out.fields = {std::move(is_shell), std::move(is_solid), std::move(normal)};
    return out;
}

// Peak bytes per voxel: the solid grid (1), the VTK fields held as doubles (5 x 8) and the file
// image (1 + 1 + 12), rounded up.
constexpr double bytes_per_voxel = 56;

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Voxelize a triangle mesh: surface shell with normals, solid interior, watertight remesh", "voxelize"};
    tool::common common(app);
    std::string mesh_path, out_dir;
    int resolution = 128, padding = 1, slices = 4;
    app.add_option("mesh", mesh_path, "input mesh (.obj, .stl, .ply), closed for a meaningful solid")->required();
    app.add_option("-r,--resolution", resolution, "voxels along the longest side of the bounding box")->check(CLI::Range(1, 2048));
    app.add_option("--padding", padding, "empty voxels added on every side")->check(CLI::Range(0, 64));
    app.add_option("--slices", slices, "z-slices shown in slices.png")->check(CLI::Range(1, 16));
    app.add_option("-o,--output", out_dir, "output directory")->required();
    double max_memory_gib = 16;
    tool::add_memory_limit(app, max_memory_gib);
    tool::mesh_simplification simplify(app, 0, "half a voxel");

    return tool::run(app, common, argc, argv, [&] {
        auto progress = common.progress();
        const fs::path out(out_dir);
        tool::check_outputs({mesh_path}, {out / "shell.vtk", out / "solid.stl", out / "solid.3mf", out / "slices.png"});
        const auto t0 = std::chrono::steady_clock::now();
        progress(0.0, "read mesh");
        const triangle_mesh mesh = io::read_mesh(mesh_path);
        if (mesh.empty()) throw invalid_input(mesh_path + ": mesh has no faces");
        const grid_geometry g = fit_grid(bounding_box(mesh), resolution, padding);
        char what[96];
        std::snprintf(what, sizeof what, "--resolution %d: a %dx%dx%d grid", resolution, g.dims.x, g.dims.y, g.dims.z);
        tool::require_memory(static_cast<double>(g.count()) * bytes_per_voxel, max_memory_gib, what);
        tool::output_set outputs;  // nothing reaches OUTDIR before commit()
        const fs::path shell_vtk = outputs.add(out / "shell.vtk"), solid_stl = outputs.add(out / "solid.stl"),
                       slices_png = outputs.add(out / "slices.png");
#if defined(FABSYNTH_HAS_LIB3MF)
        const fs::path solid_3mf = outputs.add(out / "solid.3mf");
#endif
        progress(0.1, "surface voxels");
        const shell_grid shell = voxelize_surface(mesh, g);
        progress(0.4, "solid voxels");
        const voxel_grid<std::uint8_t> solid = voxelize_solid(mesh, g);
        progress(0.6, "marching cubes");
        simplify.default_tolerance(0.5 * g.spacing.x);
        const triangle_mesh remesh = simplify(marching_cubes(solid), common, "solid.stl");
        const auto shell_cc = label_components<connectivity::c26>(shell, [](const shell_voxel& v) { return v.normal != vec3(0); });
        const auto topo = analyze_topology(remesh);

        progress(0.8, "write");
        io::write_vtk(shell_vtk, to_vtk(shell, solid));
        io::write_mesh(solid_stl, remesh);
#if defined(FABSYNTH_HAS_LIB3MF)
        io::write_3mf(solid_3mf, remesh, {.name = fs::path(mesh_path).stem().string()});
#endif
        io::write_png(slices_png, shell_solid_slices(shell, solid, slices));
        outputs.commit();
        progress(1.0, "write");
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

        const std::uint64_t nsolid = solid.count_if([](std::uint8_t v) { return v != 0; });
        char line[512];
        std::snprintf(line, sizeof line,
                      "%s: %zu triangles, grid %dx%dx%d (voxel %.4g mm): shell %llu voxels (%d 26-components), solid %llu voxels, "
                      "solid.stl %zu faces %s genus %lld, %.2f s",
                      fs::path(mesh_path).filename().string().c_str(), mesh.num_faces(), g.dims.x, g.dims.y, g.dims.z, g.spacing.x,
                      static_cast<unsigned long long>(shell.storage().stored()), shell_cc.count, static_cast<unsigned long long>(nsolid),
                      remesh.num_faces(), topo.is_watertight() ? "watertight" : "NOT watertight", static_cast<long long>(topo.genus), secs);
        common.say(line);
        common.summary({{"input_triangles", mesh.num_faces()},
                        {"grid", {g.dims.x, g.dims.y, g.dims.z}},
                        {"voxel_mm", g.spacing.x},
                        {"shell_voxels", shell.storage().stored()},
                        {"shell_components_26", shell_cc.count},
                        {"solid_voxels", nsolid},
                        {"solid_faces", remesh.num_faces()},
                        {"watertight", topo.is_watertight()},
                        {"genus", topo.genus},
                        {"outputs", {(fs::path(out_dir) / "shell.vtk").string(), (fs::path(out_dir) / "solid.stl").string(),
                                     (fs::path(out_dir) / "slices.png").string()}},
                        {"seconds", secs}});
    });
}
