// SPDX-License-Identifier: MIT
#pragma once
// What every binding file of the Python package shares: NumPy <-> library conversions (meshes as
// (V, F), pictures as uint8 arrays, point sets as n x 3) and `released`, which runs a library call
// with the GIL released and a progress callback that forwards to Python and turns Ctrl-C into a
// cancellation. The bindings stay thin: each file wraps one namespace's entry points and nothing
// else (the library is the single place of every algorithm).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <fabsynth/core/error.hpp>
#include <fabsynth/core/image.hpp>
#include <fabsynth/core/progress.hpp>
#include <fabsynth/core/types.hpp>
#include <fabsynth/geometry/mesh.hpp>
#include <fabsynth/geometry/polygon.hpp>

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fabsynth::python {

namespace py = pybind11;
using darray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using u8array = py::array_t<std::uint8_t, py::array::c_style>;

/// An n x k float64 array (k = 2 or 3) as points; `what` names the argument in errors.
template <class V>
[[nodiscard]] std::vector<V> points_from(const darray& a, const char* what) {
    constexpr py::ssize_t k = V::length();
    if (a.ndim() != 2 || a.shape(1) != k)
        throw invalid_input(std::string(what) + " must be an n x " + std::to_string(k) + " array, got shape " + std::string(py::str(py::tuple(py::cast(std::vector<py::ssize_t>(a.shape(), a.shape() + a.ndim()))))));
    std::vector<V> out(static_cast<std::size_t>(a.shape(0)));
    const double* p = a.data();
    for (std::size_t i = 0; i < out.size(); ++i)
        for (int c = 0; c < k; ++c) out[i][c] = p[i * k + static_cast<std::size_t>(c)];
    return out;
}

/// An n x k float64 array of points (a copy).
template <class V>
[[nodiscard]] darray points_to(const std::vector<V>& pts) {
    constexpr py::ssize_t k = V::length();
    darray a({static_cast<py::ssize_t>(pts.size()), k});
    double* p = a.mutable_data();
    for (std::size_t i = 0; i < pts.size(); ++i)
        for (int c = 0; c < k; ++c) p[i * k + static_cast<std::size_t>(c)] = pts[i][c];
    return a;
}

/// A mesh from (V, F): V n x 3 float64 (mm), F m x 3 integer indices into V.
[[nodiscard]] inline triangle_mesh mesh_from(const darray& V, const py::array& F) {
    triangle_mesh m;
    m.vertices = points_from<vec3>(V, "V");
    const auto f = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(F);
    if (!f || f.ndim() != 2 || f.shape(1) != 3) throw invalid_input("F must be an m x 3 integer array");
    if (F.dtype().kind() != 'i' && F.dtype().kind() != 'u') throw invalid_input("F must hold integers (int32 or int64), got dtype " + std::string(py::str(F.dtype())));
    m.faces.resize(static_cast<std::size_t>(f.shape(0)));
    const std::int64_t* p = f.data();
    for (std::size_t i = 0; i < m.faces.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const std::int64_t v = p[3 * i + static_cast<std::size_t>(c)];
            if (v < 0 || static_cast<std::size_t>(v) >= m.vertices.size())
                throw invalid_input("F[" + std::to_string(i) + "] refers to vertex " + std::to_string(v) + ", V has " + std::to_string(m.vertices.size()));
            m.faces[i][static_cast<std::size_t>(c)] = static_cast<std::uint32_t>(v);
        }
    return m;
}

/// (V, F) of a mesh: float64 n x 3 and int64 m x 3.
[[nodiscard]] inline py::tuple mesh_to(const triangle_mesh& m) {
    py::array_t<std::int64_t> F({static_cast<py::ssize_t>(m.faces.size()), py::ssize_t{3}});
    std::int64_t* p = F.mutable_data();
    for (std::size_t i = 0; i < m.faces.size(); ++i)
        for (std::size_t c = 0; c < 3; ++c) p[3 * i + c] = m.faces[i][c];
    return py::make_tuple(points_to(m.vertices), F);
}

/// A picture as a uint8 array, (h, w) for one channel, (h, w, c) otherwise; the pixels are moved,
/// not copied (the array owns them).
[[nodiscard]] inline u8array image_to(image8&& img) {
    auto* data = new std::vector<std::uint8_t>(std::move(img.data));
    py::capsule owner(data, [](void* d) { delete static_cast<std::vector<std::uint8_t>*>(d); });
    std::vector<py::ssize_t> shape{img.height, img.width};
    if (img.channels > 1) shape.push_back(img.channels);
    return u8array(shape, data->data(), owner);
}

/// A uint8 array (h, w) or (h, w, c), c in 1..4, as a picture (a copy).
[[nodiscard]] inline image8 image_from(const py::array& a, const char* what) {
    if (a.dtype().kind() != 'u' || a.itemsize() != 1) throw invalid_input(std::string(what) + " must be a uint8 array, got dtype " + std::string(py::str(a.dtype())));
    const auto c = u8array::ensure(a);
    if (c.ndim() != 2 && c.ndim() != 3) throw invalid_input(std::string(what) + " must have shape (h, w) or (h, w, c)");
    const int h = static_cast<int>(c.shape(0)), w = static_cast<int>(c.shape(1)), ch = c.ndim() == 3 ? static_cast<int>(c.shape(2)) : 1;
    image8 img(w, h, ch);  // checks the sizes and 1 <= c <= 4
    std::copy_n(c.data(), img.data.size(), img.data.begin());
    return img;
}

/// Polygons with holes as [(outer n x 2, [holes n x 2])] (mm), for outlines and drawings.
[[nodiscard]] inline py::list polygons_to(const std::vector<polygon_with_holes>& polys) {
    py::list out;
    for (const polygon_with_holes& p : polys) {
        py::list holes;
        for (const ring2& h : p.holes) holes.append(points_to(h));
        out.append(py::make_tuple(points_to(p.outer), holes));
    }
    return out;
}

[[nodiscard]] inline box2 box2_from(const std::vector<double>& v, const char* what) {
    if (v.size() != 4) throw invalid_input(std::string(what) + " must be (x0, y0, x1, y1) in mm");
    return box2({v[0], v[1]}, {v[2], v[3]});
}
[[nodiscard]] inline box3 box3_from(const std::vector<double>& v, const char* what) {
    if (v.size() != 6) throw invalid_input(std::string(what) + " must be (x0, y0, z0, x1, y1, z1) in mm");
    const box3 b({v[0], v[1], v[2]}, {v[3], v[4], v[5]});
    if (!all_finite(b.lo) || !all_finite(b.hi) || !(b.lo.x < b.hi.x && b.lo.y < b.hi.y && b.lo.z < b.hi.z))
        throw invalid_input(std::string(what) + ": need finite x0 < x1, y0 < y1, z0 < z1");
    return b;
}

/// The progress callback a library call gets from Python. Called by the library on the calling
/// thread (which has released the GIL): at most every 20 ms (and at every fraction 1) it takes the
/// GIL, lets Python run its signal handlers (Ctrl-C raises KeyboardInterrupt there) and calls the
/// user's `progress(fraction, stage)`; a pending exception or a False return cancels the call.
class python_progress {
public:
    explicit python_progress(py::object user) : user_(std::move(user)), state_(std::make_shared<state>()) {}

    bool operator()(double fraction, std::string_view stage) const {
        const auto now = std::chrono::steady_clock::now();
        if (fraction < 1 && now - state_->last < std::chrono::milliseconds(20)) return true;
        state_->last = now;
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) {
            state_->pending = std::make_unique<py::error_already_set>();
            return false;
        }
        if (user_.is_none()) return true;
        try {
            const py::object r = user_(fraction, std::string(stage));
            if (!r.is_none() && !py::bool_(r)) return false;
        } catch (py::error_already_set& e) {
            state_->pending = std::make_unique<py::error_already_set>(std::move(e));
            return false;
        }
        return true;
    }
    /// Re-raises what Python raised inside the callback (KeyboardInterrupt, the callback's own
    /// error), if anything; call with the GIL held.
    void rethrow_pending() const {
        if (state_->pending) {
            py::error_already_set e = std::move(*state_->pending);
            state_->pending.reset();
            throw e;
        }
    }

private:
    struct state {
        std::chrono::steady_clock::time_point last{};
        std::unique_ptr<py::error_already_set> pending;
    };
    py::object user_;
    std::shared_ptr<state> state_;
};

/// Runs f(progress) with the GIL released; a cancellation caused by Python (Ctrl-C, an exception
/// in the callback) is re-raised as that Python exception, one asked for by the callback returning
/// False stays fabsynth.Cancelled.
template <class F>
auto released(const py::object& progress, F&& f) {
    python_progress p(progress);
    try {
        py::gil_scoped_release nogil;
        return f(p);
    } catch (const cancelled&) {
        p.rethrow_pending();
        throw;
    }
}

void bind_geometry(py::module_& m);
void bind_io(py::module_& m);
void bind_foam(py::module_& m);
void bind_fem(py::module_& m);
void bind_surface_pattern(py::module_& m);
void bind_filigree(py::module_& m);
void bind_vector_pattern(py::module_& m);

}  // namespace fabsynth::python
