// SPDX-License-Identifier: MIT
// The extension module `fabsynth._fabsynth`: the exception classes, the thread count and one
// submodule per library namespace (io.cpp, foam.cpp, fem.cpp, surface_pattern.cpp,
// filigree.cpp, vector_pattern.cpp). python/fabsynth/*.py re-export them
// as the package `fabsynth`.
#include "common.hpp"

#include <fabsynth/core/parallel.hpp>
#include <fabsynth/version.hpp>

namespace fabsynth::python {
namespace {

PyObject* new_exception(const char* name, const char* doc, PyObject* bases) {
    PyObject* e = PyErr_NewExceptionWithDoc(name, doc, bases, nullptr);
    if (!e) throw py::error_already_set();
    return e;
}

}  // namespace
}  // namespace fabsynth::python

PYBIND11_MODULE(_fabsynth, m) {
    using namespace fabsynth::python;
    m.doc() = "fabsynth: synthesis of 3D-printable structures (C++ core; use the package `fabsynth`).";
    m.attr("__version__") = FABSYNTH_VERSION_STRING;

    // Error hierarchy: fabsynth::error and its subclasses, with the matching built-in bases so that
    // `except ValueError` and `except OSError` catch invalid input and file errors.
    static PyObject* const base = new_exception("fabsynth.Error", "Base of every error the library raises.", PyExc_Exception);
    const auto with = [](PyObject* builtin) { return py::make_tuple(py::handle(base), py::handle(builtin)).release().ptr(); };
    static PyObject* const invalid =
        new_exception("fabsynth.InvalidInput", "An argument or input value is outside its documented domain (also a ValueError).", with(PyExc_ValueError));
    static PyObject* const io = new_exception("fabsynth.IoError", "A file could not be read or written, or is malformed (also an OSError).", with(PyExc_OSError));
    static PyObject* const no_solution = new_exception("fabsynth.NoSolution", "The request is well formed but cannot be met.", base);
    static PyObject* const solver = new_exception("fabsynth.SolverError", "A numerical solve failed.", base);
    static PyObject* const cancelled = new_exception("fabsynth.Cancelled", "The progress callback returned False.", base);
    m.attr("Error") = py::handle(base);
    m.attr("InvalidInput") = py::handle(invalid);
    m.attr("IoError") = py::handle(io);
    m.attr("NoSolution") = py::handle(no_solution);
    m.attr("SolverError") = py::handle(solver);
    m.attr("Cancelled") = py::handle(cancelled);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const fabsynth::invalid_input& e) {
            PyErr_SetString(invalid, e.what());
        } catch (const fabsynth::io_error& e) {
            PyErr_SetString(io, e.what());
        } catch (const fabsynth::no_solution& e) {
            PyErr_SetString(no_solution, e.what());
        } catch (const fabsynth::solver_error& e) {
            PyErr_SetString(solver, e.what());
        } catch (const fabsynth::cancelled& e) {
            PyErr_SetString(cancelled, e.what());
        } catch (const fabsynth::error& e) {
            PyErr_SetString(base, e.what());
        }
    });

    m.def("set_num_threads", [](unsigned n) { fabsynth::set_num_threads(n); }, py::arg("n"),
          "Sets the number of threads of later calls (0 = automatic: FABSYNTH_NUM_THREADS, else the core count).\n"
          "Results are byte-identical for any thread count.");
    m.def("num_threads", [] { return fabsynth::num_threads(); }, "Number of threads library calls use (>= 1).");

    auto geometry_m = m.def_submodule("geometry", "Meshes: simplification with guarantees, Hausdorff distance.");
    bind_geometry(geometry_m);
    auto io_m = m.def_submodule("io", "Files: meshes as (V, F), PNG pictures as uint8 arrays with their pixel size, SVG drawings.");
    bind_io(io_m);
    auto foam_m = m.def_submodule("foam", "Procedural Voronoi foams (Martinez, Dumas & Lefebvre 2016): evaluation, slices, seeds, beams.");
    bind_foam(foam_m);
    auto fem_m = m.def_submodule("fem", "Finite elements: voxel models, homogenization.");
    bind_fem(fem_m);
    auto sp_m = m.def_submodule("surface_pattern", "Structurally sound surface patterns by example (Lu et al. 2015).");
    bind_surface_pattern(sp_m);
    auto fg_m = m.def_submodule("filigree", "Filigrees (Chen et al. 2016): planar and on a base surface.");
    bind_filigree(fg_m);
    auto vp_m = m.def_submodule("vector_pattern", "Topology-constrained vector patterns along curves (Zhou et al. 2014).");
    bind_vector_pattern(vp_m);
}
