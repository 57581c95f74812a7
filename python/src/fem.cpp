// SPDX-License-Identifier: MIT
// fabsynth.fem: a linear static solve of an Abaqus/CalculiX deck (fem/inp.hpp + fem/solve_context,
// what fem_solve does) and the periodic homogenization of a density grid (fem/homogenization.hpp,
// what homogenize does).
#include "common.hpp"

#include <fabsynth/fem.hpp>
#include <fabsynth/io/detail/read_file.hpp>

#include <filesystem>

namespace fabsynth::python {
namespace {

py::dict solve(const fem::inp_deck& d, const std::string& solver) {
    fem::solve_options options;
    options.method = fem::parse_solver_method(solver);
    if (!fem::method_available(options.method)) throw invalid_input("solver " + solver + ": this build has no CHOLMOD (SuiteSparse not found)");
    const fem::mesh& m = d.model;
    fem::static_result r;
    std::vector<fem::voigt6> stress;
    {
        py::gil_scoped_release nogil;
        fem::solve_context context(m, d.loads, options);
        r = context.solve(d.loads);
        stress = fem::centroid_stresses(m, r);
    }
    const auto n = static_cast<py::ssize_t>(m.nodes.size()), ne = static_cast<py::ssize_t>(m.elements.size());
    darray u({n, py::ssize_t{3}}), rot({n, py::ssize_t{3}}), s({ne, py::ssize_t{6}});
    py::array_t<double> vm(ne);
    py::array_t<std::int64_t> node_labels(n), element_labels(ne);
    for (py::ssize_t i = 0; i < n; ++i) {
        const vec3 a = r.displacement(static_cast<std::size_t>(i)), q = r.rotation(static_cast<std::size_t>(i));
        for (int k = 0; k < 3; ++k) u.mutable_data()[3 * i + k] = a[k], rot.mutable_data()[3 * i + k] = q[k];
        node_labels.mutable_data()[i] = m.node_label(static_cast<std::size_t>(i));
    }
    for (py::ssize_t e = 0; e < ne; ++e) {
        const fem::voigt6& v = stress[static_cast<std::size_t>(e)];  // Voigt (xx,yy,zz,yz,xz,xy) -> Abaqus (xx,yy,zz,xy,yz,zx)
        const double ab[6] = {v(0), v(1), v(2), v(5), v(3), v(4)};
        for (int k = 0; k < 6; ++k) s.mutable_data()[6 * e + k] = ab[k];
        vm.mutable_data()[e] = fem::von_mises(v);
        element_labels.mutable_data()[e] = m.element_label(static_cast<std::size_t>(e));
    }
    py::dict out;
    out["nodes"] = points_to(m.nodes), out["node_labels"] = node_labels, out["element_labels"] = element_labels;
    out["displacements"] = u, out["rotations"] = rot, out["stresses"] = s, out["von_mises"] = vm;
    out["solver"] = r.solver, out["iterations"] = r.iterations, out["relative_residual"] = r.relative_residual;
    return out;
}

constexpr const char* solve_doc =
    "Linear static solve (C3D8, C3D6, S3 elements; mm, N, MPa), as fem_solve does it. solver: auto | ldlt |\n"
    "cholmod | cg | cg-jacobi | amg.\n\n"
    "Returns dict(nodes=n x 3 mm, node_labels=n, displacements=n x 3 mm, rotations=n x 3 rad (0 without\n"
    "rotational DOFs), element_labels=m, stresses=m x 6 MPa at element centroids in Abaqus order (xx, yy,\n"
    "zz, xy, yz, zx), von_mises=m MPa, solver=the method used, iterations, relative_residual).";

}  // namespace

void bind_fem(py::module_& m) {
    m.def("solve_inp", [](const std::filesystem::path& path, const std::string& solver) {
        const std::string text = io::detail::read_file(path);
        return solve(fem::parse_inp(text, path.string()), solver);
    }, py::arg("path"), py::arg("solver") = "auto", solve_doc);
    m.def("solve_inp_text", [](const std::string& text, const std::string& solver) { return solve(fem::parse_inp(text, "<text>"), solver); },
          py::arg("text"), py::arg("solver") = "auto", solve_doc);
    m.def("homogenize", [](const darray& density, const py::object& voxel, double E, double nu, double tol, const py::object& progress) {
        if (density.ndim() != 3) throw invalid_input("density must be a 3D array indexed [x, y, z]");
        std::vector<double> voxel_mm;
        if (py::isinstance<py::float_>(voxel) || py::isinstance<py::int_>(voxel)) voxel_mm.assign(3, voxel.cast<double>());
        else voxel_mm = voxel.cast<std::vector<double>>();
        if (voxel_mm.size() != 3) throw invalid_input("voxel_mm must be one size or (x, y, z), mm");
        if (!(nu > -1 && nu < 0.5)) throw invalid_input("nu must lie in (-1, 0.5)");
        const ivec3 dims(static_cast<int>(density.shape(0)), static_cast<int>(density.shape(1)), static_cast<int>(density.shape(2)));
        std::vector<double> values(static_cast<std::size_t>(density.size()));  // x fastest, as fem::density_view reads them
        const auto d = density.unchecked<3>();
        for (int z = 0; z < dims.z; ++z)
            for (int y = 0; y < dims.y; ++y)
                for (int x = 0; x < dims.x; ++x)
                    values[static_cast<std::size_t>(x) + static_cast<std::size_t>(dims.x) * (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims.y) * z)] = d(x, y, z);
        const fem::density_view grid(dims, {voxel_mm[0], voxel_mm[1], voxel_mm[2]}, values);
        fem::homogenization_options opt;
        opt.solver.tolerance = tol;
        const auto [r, fit] = released(progress, [&](python_progress& p) {
            auto h = fem::homogenize(grid, {E, nu}, opt, p);
            return std::pair{h, fem::fit_isotropic(h.C, E)};
        });
        py::array_t<double> C({6, 6});
        for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 6; ++j) C.mutable_data()[6 * i + j] = r.C(i, j);
        py::dict out;
        out["C"] = C, out["volume_fraction"] = r.volume_fraction, out["removed_fraction"] = r.removed_fraction;
        out["E"] = fit.E, out["nu"] = fit.nu, out["relative_residual"] = fit.relative_residual;
        return out;
    }, py::arg("density"), py::arg("voxel_mm") = 1.0, py::kw_only(), py::arg("E") = 1.0, py::arg("nu") = 0.3, py::arg("tol") = 1e-8,
          py::arg("progress") = py::none(),
          "Periodic homogenization of one unit cell (fem/homogenization.hpp), as the homogenize tool does it.\n\n"
          "density: float64 array (nx, ny, nz) indexed [x, y, z], values in [0, 1] scaling the stiffness (0 = void);\n"
          "voxel_mm: voxel size (one number or x, y, z; mm); E (MPa), nu: the base material; tol: CG tolerance.\n"
          "Returns dict(C=6 x 6 effective elasticity in MPa, Voigt (xx, yy, zz, yz, xz, xy) with engineering shear,\n"
          "volume_fraction, removed_fraction (floating islands), E, nu, relative_residual: the isotropic fit of\n"
          "procedural-voronoi-foams eq. 1).");
}

}  // namespace fabsynth::python
