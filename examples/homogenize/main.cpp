// homogenize GRID.vtk [--E 1] [--nu 0.3] [--solver multigrid|jacobi|direct] [--preview out.png]
//
// Periodic homogenization of a voxel grid of densities in [0, 1] read from a legacy VTK
// STRUCTURED_POINTS file: either POINT_DATA with DIMENSIONS = voxel counts, or CELL_DATA with
// DIMENSIONS = voxel counts + 1. The unit cell is the grid's bounding box; voxels of density 0 are
// void. Prints JSON on stdout:
//   C                6x6 effective tensor [MPa], Voigt order 11,22,33,23,13,12, engineering shear
//                    strains (C44 = mu for an isotropic solid)
//   E, nu            isotropic fit of procedural-voronoi-foams.md eq. (1), 0 <= E <= --E, -1 <= nu <= 0.5
//   xi               relative residual of that fit, ||C^I - C||_F / ||C||_F (0 = isotropic)
//   xi_abs           the residual of eq. (1) itself, ||C^I - C||_F^2 [MPa^2]
//   volume_fraction  mean density; removed_fraction: floating islands removed before solving
// Progress goes to stderr. Exit code 1 on any error (message on stderr).
#include <CLI/CLI.hpp>

#include <fabsynth/core.hpp>
#include <fabsynth/fem/homogenization.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/vtk.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

namespace {

std::string num(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", x);
    return buf;
}

// Three orthogonal mid-plane slices (xy | xz | yz) of the densities, 0 = black, 1 = white.
fabsynth::image8 slices(const fabsynth::fem::density_view& g) {
    const fabsynth::ivec3 n = g.dims();
    const int w = n.x + 1 + n.x + 1 + n.y, h = std::max(n.y, n.z);
    fabsynth::image8 img(w, h, 1, 64);
    auto put = [&](int x, int y, double v) { img.at(x, h - 1 - y) = static_cast<std::uint8_t>(std::lround(255 * std::clamp(v, 0.0, 1.0))); };
    for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) put(i, j, g.get({i, j, n.z / 2}));
    for (int k = 0; k < n.z; ++k)
        for (int i = 0; i < n.x; ++i) put(n.x + 1 + i, k, g.get({i, n.y / 2, k}));
    for (int k = 0; k < n.z; ++k)
        for (int j = 0; j < n.y; ++j) put(2 * n.x + 2 + j, k, g.get({n.x / 2, j, k}));
    return img;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Periodic homogenization of a voxel density grid (legacy VTK STRUCTURED_POINTS); prints JSON"};
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
    CLI11_PARSE(app, argc, argv);

    try {
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
        std::cerr << "homogenize: " << input << ": " << dims.x << "x" << dims.y << "x" << dims.z << " voxels ("
                  << (sp.cell_data ? "CELL_DATA" : "POINT_DATA") << " '" << f->name << "'), E = " << E << " MPa, nu = " << nu << "\n";
        if (!preview.empty()) fabsynth::io::write_png(preview, slices(grid));

        fabsynth::fem::homogenization_options opt;
        opt.solver.solver = fabsynth::fem::parse_voxel_solver(solver);
        opt.solver.tolerance = tol;
        opt.law = {.penalty = penalty, .min_density = min_density};
        int last = -1;
        const auto r = fabsynth::fem::homogenize(grid, {E, nu}, opt, [&](double frac, std::string_view stage) {
            const int pct = static_cast<int>(frac * 100);
            if (pct != last) {
                last = pct;
                std::cerr << "\r" << stage << " " << pct << "%   " << std::flush;
            }
        });
        std::cerr << "\n";
        const auto fit = fabsynth::fem::fit_isotropic(r.C, E);
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

        std::ostringstream js;
        js << "{\n  \"C\": [";
        for (int i = 0; i < 6; ++i) {
            js << (i ? ",\n        [" : "[");
            for (int j = 0; j < 6; ++j) js << (j ? ", " : "") << num(r.C(i, j));
            js << "]";
        }
        js << "],\n  \"E\": " << num(fit.E) << ",\n  \"nu\": " << num(fit.nu) << ",\n  \"xi\": " << num(fit.relative_residual)
           << ",\n  \"xi_abs\": " << num(fit.residual) << ",\n  \"volume_fraction\": " << num(r.volume_fraction)
           << ",\n  \"removed_fraction\": " << num(r.removed_fraction) << ",\n  \"dims\": [" << dims.x << ", " << dims.y << ", "
           << dims.z << "],\n  \"solver\": \"" << solver << "\",\n  \"levels\": " << r.stats[0].levels << ",\n  \"dofs\": " << r.stats[0].dofs
           << ",\n  \"iterations\": [";
        for (int i = 0; i < 6; ++i) js << (i ? ", " : "") << r.stats[static_cast<std::size_t>(i)].iterations;
        js << "],\n  \"seconds\": " << num(secs) << "\n}\n";
        std::cout << js.str();
        std::cerr << "homogenize: done in " << num(secs) << " s\n";
    } catch (const std::exception& e) {
        std::cerr << "homogenize: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
