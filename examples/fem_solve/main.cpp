// fem_solve DECK.inp -o OUTDIR: linear static analysis of an Abaqus/CalculiX .inp deck.
// Writes OUTDIR/displacements.csv (node,ux,uy,uz), OUTDIR/stresses.csv (element centroid stress,
// Abaqus component order sxx,syy,szz,sxy,syz,szx, then von_mises) and OUTDIR/result.vtk, and
// prints a one-line summary (--json: a JSON summary). A direct factorization predicted (by the
// symbolic analysis) to exceed --max-memory or --max-factor-flops is refused before it starts; the
// three files appear together at the end of a successful run. Conventions (exit codes, --quiet, --json,
// --version): docs/tools.md.

#include <charconv>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

#include "fabsynth/fem.hpp"
#include "fabsynth/io/atomic_file.hpp"
#include "fabsynth/io/detail/read_file.hpp"
#include "fabsynth/io/vtk.hpp"
#include "output_set.hpp"
#include "tool.hpp"

namespace fem = fabsynth::fem;

namespace {

// Shortest decimal that round-trips the double.
void put(std::string& s, double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    s.append(buf, r.ptr);
}

// Factorization rates on one core of the reference machine (benchmarks/README.md, "fem_solve
// limits"), only to turn a refused operation count into hours in the message.
constexpr double ldlt_flops_per_second = 1.2e9, cholmod_flops_per_second = 1.6e10;

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Linear static FEM solve of an Abaqus/CalculiX .inp deck (C3D8, C3D6, S3)", "fem_solve"};
    fabsynth::tool::common common(app);
    std::string deck_path, out_dir, solver = "auto";
    app.add_option("deck", deck_path, "input deck (.inp)")->required();
    app.add_option("-o,--output", out_dir, "output directory")->required();
    app.add_option("--solver", solver,
                   "auto (default: ldlt when small; amg for large solid meshes; cholmod, else ldlt, for large shell meshes) | "
                   "ldlt | cholmod | cg | cg-jacobi | amg")
        ->check(CLI::IsMember({"auto", "ldlt", "cholmod", "cg", "cg-jacobi", "amg"}));
    double max_memory_gib = 16, max_factor_flops = 2e12;
    fabsynth::tool::add_memory_limit(app, max_memory_gib);
    app.add_option("--max-factor-flops", max_factor_flops,
                   "refuse a direct factorization (ldlt, cholmod) predicted to need more floating-point operations than this")
        ->check(CLI::PositiveNumber);

    return fabsynth::tool::run(app, common, argc, argv, [&] {
        auto progress = common.progress();
        const std::filesystem::path out_files(out_dir);
        fabsynth::tool::check_outputs({deck_path}, {out_files / "displacements.csv", out_files / "stresses.csv", out_files / "result.vtk"});
        fabsynth::tool::output_set outputs;  // nothing reaches OUTDIR before commit()
        const std::filesystem::path disp_csv = outputs.add(out_files / "displacements.csv"), stress_csv = outputs.add(out_files / "stresses.csv"),
                                    result_vtk = outputs.add(out_files / "result.vtk");
        progress(0.0, "read deck");
        const auto t0 = std::chrono::steady_clock::now();
        const fem::inp_deck d = fem::parse_inp(fabsynth::io::detail::read_file(deck_path), deck_path);
        progress(0.1, "solve");
        fem::solve_options options;
        options.method = fem::parse_solver_method(solver);
        if (!fem::method_available(options.method))
            throw fabsynth::invalid_input("--solver " + solver + ": this build has no CHOLMOD (SuiteSparse not found)");
        fem::solve_context context(d.model, d.loads, options);
        {  // a direct factor is sized by the symbolic analysis: refuse before factorizing what cannot finish
            const fem::solve_statistics& pre = context.statistics();
            const std::string what = pre.method + " factorization of " + std::to_string(pre.free_dofs) + " free DOFs";
            fabsynth::tool::require_memory(pre.predicted_factor_bytes, max_memory_gib, what);
            fabsynth::tool::require_work(pre.predicted_factor_flops, max_factor_flops, pre.method == "ldlt" ? ldlt_flops_per_second : cholmod_flops_per_second,
                                         "floating-point operations", "--max-factor-flops", what,
                                         "or --solver amg, whose cost grows about linearly");
        }
        const fem::static_result r = context.solve(d.loads);
        const fem::solve_statistics& st = context.statistics();
        const fem::mesh& m = d.model;
        progress(0.7, "stresses");
        const auto stress = fem::centroid_stresses(m, r);
        progress(0.8, "write");

        const std::filesystem::path out(out_dir);
        std::string csv = "node,ux,uy,uz\n";
        std::size_t umax_node = 0;
        double umax = -1;
        std::vector<double> disp, rot, vm_field, s_field;
        bool any_rot = false;
        for (std::size_t i = 0; i < m.nodes.size(); ++i) {
            const fabsynth::vec3 u = r.displacement(i), q = r.rotation(i);
            csv += std::to_string(m.node_label(i));
            for (int k = 0; k < 3; ++k) csv += ',', put(csv, u[k]);
            csv += '\n';
            if (glm::length(u) > umax) umax = glm::length(u), umax_node = i;
            for (int k = 0; k < 3; ++k) disp.push_back(u[k]), rot.push_back(q[k]);
            any_rot = any_rot || r.dofs.count[i] == 6;
        }
        fabsynth::io::atomic_write(disp_csv, csv);

        csv = "element,sxx,syy,szz,sxy,syz,szx,von_mises\n";
        std::size_t vm_el = 0;
        double vm_max = -1;
        for (std::size_t e = 0; e < m.elements.size(); ++e) {
            const fem::voigt6& s = stress[e];  // Voigt (xx,yy,zz,yz,xz,xy) -> Abaqus (xx,yy,zz,xy,yz,zx)
            const double ab[6] = {s(0), s(1), s(2), s(5), s(3), s(4)};
            const double vm = fem::von_mises(s);
            csv += std::to_string(m.element_label(e));
            for (double v : ab) csv += ',', put(csv, v);
            csv += ',', put(csv, vm), csv += '\n';
            s_field.insert(s_field.end(), ab, ab + 6);
            vm_field.push_back(vm);
            if (vm > vm_max) vm_max = vm, vm_el = e;
        }
        fabsynth::io::atomic_write(stress_csv, csv);

        std::vector<fabsynth::io::vtk_cell> cells;
        for (const fem::element& e : m.elements)
            fem::visit_kind(e.kind, [&]<class E>(std::type_identity<E>) {
                fabsynth::io::vtk_cell c{static_cast<std::uint8_t>(E::vtk_type), {}};
                for (int a = 0; a < E::num_nodes; ++a) c.nodes.push_back(e.nodes[static_cast<std::size_t>(E::vtk_order[a])]);
                cells.push_back(std::move(c));
            });
        std::vector<fabsynth::io::vtk_field> pf = {{"displacement", 3, disp}};
        if (any_rot) pf.push_back({"rotation", 3, rot});
        std::vector<double> ids;
        for (std::size_t e = 0; e < m.elements.size(); ++e) ids.push_back(static_cast<double>(m.element_label(e)));
        fabsynth::io::write_vtk_unstructured(result_vtk, m.nodes, cells, pf,
                                             {{"stress_xx_yy_zz_xy_yz_zx", 6, s_field}, {"von_mises", 1, vm_field}, {"element_id", 1, ids}});
        outputs.commit();
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        progress(1.0, "write");
        std::ostringstream line;
        line << "fem_solve: " << m.nodes.size() << " nodes, " << m.elements.size() << " elements, " << r.dofs.total
             << " dofs; max |u| = " << umax << " mm at node " << m.node_label(umax_node) << "; max von Mises = " << vm_max
             << " MPa in element " << m.element_label(vm_el) << "; solver " << st.method << " (" << st.reason << ")"
             << (st.last_iterations ? ", " + std::to_string(st.last_iterations) + " CG iterations" : std::string()) << ", residual "
             << r.relative_residual << ", " << secs << " s";
        common.say(line.str());
        common.summary({{"nodes", m.nodes.size()},
                        {"elements", m.elements.size()},
                        {"dofs", r.dofs.total},
                        {"max_displacement_mm", umax},
                        {"max_displacement_node", m.node_label(umax_node)},
                        {"max_von_mises_mpa", vm_max},
                        {"max_von_mises_element", m.element_label(vm_el)},
                        {"solver", st.method},
                        {"solver_requested", solver},
                        {"solver_reason", st.reason},
                        {"cg_iterations", st.last_iterations},
                        {"predicted_factor_bytes", st.predicted_factor_bytes},
                        {"predicted_factor_flops", st.predicted_factor_flops},
                        {"assemble_seconds", st.assemble_seconds},
                        {"analyze_seconds", st.analyze_seconds},
                        {"factorize_seconds", st.factorize_seconds},
                        {"solve_seconds", st.solve_seconds},
                        {"relative_residual", r.relative_residual},
                        {"outputs", {(out / "displacements.csv").string(), (out / "stresses.csv").string(), (out / "result.vtk").string()}},
                        {"seconds", secs}});
    });
}
