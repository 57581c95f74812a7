// homogenize GRID.vtk [--E 1] [--nu 0.3] [--solver multigrid|jacobi|direct] [--preview out.png]
//
// Periodic homogenization of a voxel grid of densities in [0, 1] read from a legacy VTK
// STRUCTURED_POINTS file: either POINT_DATA with DIMENSIONS = voxel counts, or CELL_DATA with
// DIMENSIONS = voxel counts + 1. The unit cell is the grid's bounding box; voxels of density 0 are
// void. Prints a summary line; with --json, a JSON object on stdout with these fields:
//   C                6x6 effective tensor [MPa], Voigt order 11,22,33,23,13,12, engineering shear
//                    strains (C44 = mu for an isotropic solid)
//   E, nu            isotropic fit of procedural-voronoi-foams.md eq. (1), 0 <= E <= --E, -1 <= nu <= 0.5
//   xi               relative residual of that fit, ||C^I - C||_F / ||C||_F (0 = isotropic)
//   xi_abs           the residual of eq. (1) itself, ||C^I - C||_F^2 [MPa^2]
//   volume_fraction  mean density; removed_fraction: floating islands removed before solving
// Conventions (exit codes, progress on stderr, --quiet, --json, --version): docs/tools.md.

#include <fabsynth/core.hpp>
#include <fabsynth/fem/homogenization.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/vtk.hpp>
#include <fabsynth/voxel/preview.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

#include "output_set.hpp"
#include "tool.hpp"

namespace {
// Peak bytes per voxel of the six periodic solves, measured with /usr/bin/time on 48^3 and 96^3
// lattices (benchmarks/README.md, "Tool limits"), rounded up: matrix-free multigrid (every level's
// vectors and element data) and Jacobi-CG (the fine level only).
constexpr double multigrid_bytes_per_voxel = 1000, jacobi_bytes_per_voxel = 360;
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Periodic homogenization of a voxel density grid (legacy VTK STRUCTURED_POINTS)", "homogenize"};
    fabsynth::tool::common common(app);
    std::string input, field, solver = "multigrid", preview;
    double E = 1.0, nu = 0.3, tol = 1e-8, penalty = 1.0, min_density = 0.0;
    unsigned threads = 0;
    app.add_option("grid", input, "VTK STRUCTURED_POINTS file with one density in [0,1] per voxel")->required();
    app.add_option("--E", E, "Young's modulus of the solid [MPa] (also the upper bound of the fitted E)")->capture_default_str();
    app.add_option("--nu", nu, "Poisson's ratio of the solid")->capture_default_str();
    app.add_option("--solver", solver, "multigrid (matrix-free, large grids), jacobi (CG) or direct (small grids)")->capture_default_str();
    app.add_option("--field", field, "name of the density array (default: the first one-component array)");
    app.add_option("--tol", tol, "relative residual tolerance of each of the six solves")->capture_default_str();
    app.add_option("--penalty", penalty, "stiffness = E * density^penalty (SIMP exponent)")->capture_default_str();
    app.add_option("--min-density", min_density, "stiffness floor for solid voxels (density > 0)")->capture_default_str();
    app.add_option("--threads", threads, "worker threads (0 = all cores)")->capture_default_str();
    app.add_option("--preview", preview, "write a PNG of the three mid-plane slices of the densities");
    double max_memory_gib = 16;
    fabsynth::tool::add_memory_limit(app, max_memory_gib);

    return fabsynth::tool::run(app, common, argc, argv, [&] {
        fabsynth::tool::check_outputs({input}, {preview});
        // 1e-9..1e9 MPa spans every printable solid (steel ~2e5) with room; beyond, the six solves'
        // energies overflow or underflow far from the option that caused it.
        fabsynth::tool::require_range(E, 1e-9, 1e9, "--E", "MPa");
        if (!(nu > -1 && nu < 0.5)) throw fabsynth::invalid_input("--nu must lie in (-1, 0.5)");
        if (!(tol > 0 && tol < 1)) throw fabsynth::invalid_input("--tol must lie in (0, 1)");
        if (!(std::isfinite(penalty) && penalty > 0)) throw fabsynth::invalid_input("--penalty must be finite and > 0");
        if (!(min_density >= 0 && min_density < 1)) throw fabsynth::invalid_input("--min-density must lie in [0, 1)");
        const auto voxel_solver = fabsynth::fem::parse_voxel_solver(solver);
        fabsynth::tool::output_set outputs;  // the preview appears only after a successful solve
        const std::filesystem::path preview_staged = preview.empty() ? std::filesystem::path() : outputs.add(preview);
        fabsynth::set_num_threads(threads);
        const auto t0 = std::chrono::steady_clock::now();
        const fabsynth::io::structured_points sp = fabsynth::io::read_vtk_structured_points(input);
        const fabsynth::io::vtk_field* f = nullptr;
        for (const auto& fld : sp.fields)
            if (field.empty() ? fld.components == 1 : fld.name == field) {
                f = &fld;
                break;
            }
        if (!f) throw fabsynth::invalid_input(input + ": no " + (field.empty() ? std::string("one-component") : "'" + field + "'") + " data array");
        if (f->components != 1) throw fabsynth::invalid_input(input + ": array '" + f->name + "' has " + std::to_string(f->components) + " components, expected 1");
        fabsynth::ivec3 dims = sp.dims;
        if (sp.cell_data)
            for (int a = 0; a < 3; ++a) dims[a] = std::max(sp.dims[a] - 1, 1);
        const fabsynth::fem::density_view grid(dims, sp.spacing, f->values);
        const double voxels = static_cast<double>(dims.x) * dims.y * dims.z;
        fabsynth::tool::require_memory(voxels * (voxel_solver == fabsynth::fem::voxel_solver::jacobi ? jacobi_bytes_per_voxel : multigrid_bytes_per_voxel),
                                       max_memory_gib, "homogenizing " + std::to_string(dims.x) + "x" + std::to_string(dims.y) + "x" + std::to_string(dims.z) +
                                                           " voxels with --solver " + solver);
        std::ostringstream head;
        head << "homogenize: " << input << ": " << dims.x << "x" << dims.y << "x" << dims.z << " voxels ("
                  << (sp.cell_data ? "CELL_DATA" : "POINT_DATA") << " '" << f->name << "'), E = " << E << " MPa, nu = " << nu;
        if (!common.quiet()) std::cerr << head.str() << "\n";

        fabsynth::fem::homogenization_options opt;
        opt.solver.solver = voxel_solver;
        opt.solver.tolerance = tol;
        opt.law = {.penalty = penalty, .min_density = min_density};
        const auto r = fabsynth::fem::homogenize(grid, {E, nu}, opt, common.progress());
        const auto fit = fabsynth::fem::fit_isotropic(r.C, E);
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

        if (!preview.empty()) {
            fabsynth::io::write_png(preview_staged, fabsynth::mid_plane_slices(dims, [&](fabsynth::ivec3 p) { return grid.get(p); }));
            outputs.commit();
        }
        nlohmann::ordered_json C = nlohmann::ordered_json::array();
        for (int i = 0; i < 6; ++i) {
            nlohmann::ordered_json row = nlohmann::ordered_json::array();
            for (int j = 0; j < 6; ++j) row.push_back(r.C(i, j));
            C.push_back(row);
        }
        nlohmann::ordered_json iterations = nlohmann::ordered_json::array();
        for (int i = 0; i < 6; ++i) iterations.push_back(r.stats[static_cast<std::size_t>(i)].iterations);
        common.summary({{"C", C},
                        {"E", fit.E},
                        {"nu", fit.nu},
                        {"xi", fit.relative_residual},
                        {"xi_abs", fit.residual},
                        {"volume_fraction", r.volume_fraction},
                        {"removed_fraction", r.removed_fraction},
                        {"dims", {dims.x, dims.y, dims.z}},
                        {"solver", solver},
                        {"levels", r.stats[0].levels},
                        {"dofs", r.stats[0].dofs},
                        {"iterations", iterations},
                        {"seconds", secs}});
        char line[256];
        std::snprintf(line, sizeof line, "homogenize: E = %.10g MPa, nu = %.10g, xi = %.3g, volume fraction %.6g, %.3g s", fit.E, fit.nu,
                      fit.relative_residual, r.volume_fraction, secs);
        common.say(line);
    });
}
