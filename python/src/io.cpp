// SPDX-License-Identifier: MIT
// fabsynth.io: io/mesh.hpp, io/image.hpp, io/svg.hpp (and io/mesh_3mf.hpp where lib3mf is built in).
#include "common.hpp"

#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/svg.hpp>
#if defined(FABSYNTH_HAS_LIB3MF)
#include <fabsynth/io/mesh_3mf.hpp>
#endif

#include <array>
#include <filesystem>
#include <optional>
#include <vector>

namespace fabsynth::python {

void bind_io(py::module_& m) {
    m.def("read_mesh", [](const std::filesystem::path& path) {
        triangle_mesh mesh;
        {
            py::gil_scoped_release nogil;
            mesh = io::read_mesh(path);
        }
        return mesh_to(mesh);
    }, py::arg("path"),
          "Reads a triangle mesh (.obj, .stl, .ply by extension).\n\n"
          "Returns (V, F): V float64 n x 3 (the file's units, mm for the library), F int64 m x 3 vertex indices.\n"
          "Raises IoError for unreadable or malformed files, InvalidInput for an unknown extension.");
    m.def("write_mesh", [](const std::filesystem::path& path, const darray& V, const py::array& F) {
        const triangle_mesh mesh = mesh_from(V, F);
        py::gil_scoped_release nogil;
        io::write_mesh(path, mesh);
    }, py::arg("path"), py::arg("V"), py::arg("F"),
          "Writes (V, F) as .obj (exact decimals), .stl or .ply (binary float32) by extension, atomically\n"
          "(a failed write leaves no half-written file). V: n x 3 float64, F: m x 3 integer indices.");
#if defined(FABSYNTH_HAS_LIB3MF)
    m.def("write_3mf", [](const std::filesystem::path& path, const darray& V, const py::array& F, const std::string& name,
                          const std::optional<py::array>& face_colours) {
        const triangle_mesh mesh = mesh_from(V, F);
        io::mesh_3mf_options o{.name = name};
        if (face_colours) {
            const auto c = u8array::ensure(*face_colours);
            if (face_colours->dtype().kind() != 'u' || face_colours->itemsize() != 1 || !c || c.ndim() != 2 || c.shape(1) != 3)
                throw invalid_input("face_colours must be an m x 3 uint8 array (sRGB per face)");
            o.face_colours.resize(static_cast<std::size_t>(c.shape(0)));
            for (std::size_t f = 0; f < o.face_colours.size(); ++f)
                for (std::size_t k = 0; k < 3; ++k) o.face_colours[f][k] = c.data()[3 * f + k];
        }
        py::gil_scoped_release nogil;
        io::write_3mf(path, mesh, o);
    }, py::arg("path"), py::arg("V"), py::arg("F"), py::arg("name") = "fabsynth mesh", py::arg("face_colours") = py::none(),
          "Writes (V, F) as a 3MF file in millimetres (V in mm); `name` is the object name slicers show;\n"
          "face_colours: optional m x 3 uint8 sRGB, one per face, written as per-triangle colours.");
    m.def("read_3mf", [](const std::filesystem::path& path, bool colours) {
        triangle_mesh mesh;
        std::vector<std::array<std::uint8_t, 4>> rgba;
        {
            py::gil_scoped_release nogil;
            mesh = io::read_3mf(path, colours ? &rgba : nullptr);
        }
        if (!colours) return py::object(mesh_to(mesh));
        u8array c({static_cast<py::ssize_t>(rgba.size()), py::ssize_t{4}});
        for (std::size_t f = 0; f < rgba.size(); ++f)
            for (std::size_t k = 0; k < 4; ++k) c.mutable_data()[4 * f + k] = rgba[f][k];
        const py::tuple vf = mesh_to(mesh);
        return py::object(py::make_tuple(vf[0], vf[1], c));
    }, py::arg("path"), py::arg("colours") = false,
          "(V, F) of a 3MF file's meshes, in mm; with colours=True (V, F, C), C m x 4 uint8 RGBA per face\n"
          "(alpha 0 for a face without a colour).");
    m.attr("has_3mf") = true;
#else
    m.attr("has_3mf") = false;
#endif
    m.def("read_png", [](const std::filesystem::path& path) {
        image8 img;
        {
            py::gil_scoped_release nogil;
            img = io::read_png(path);
        }
        return image_to(std::move(img));
    }, py::arg("path"),
          "Reads a PNG as uint8: shape (h, w) for grey pictures, (h, w, c) for c = 2 (grey + alpha), 3 (RGB), 4 (RGBA).\n"
          "Row 0 is the top row of the picture; 16-bit files keep their high byte. Raises IoError.");
    m.def("read_png_info", [](const std::filesystem::path& path) {
        const io::png_info i = io::read_png_info(path);
        py::dict d;
        d["width"] = i.width, d["height"] = i.height, d["channels"] = i.channels, d["bit_depth"] = i.bit_depth;
        d["pixel_mm"] = i.pixel_mm ? py::object(py::make_tuple(i.pixel_mm->x, i.pixel_mm->y)) : py::object(py::none());
        return d;
    }, py::arg("path"),
          "The PNG header: dict(width, height, channels, bit_depth, pixel_mm), pixel_mm = (x, y) in mm from the\n"
          "pHYs chunk, or None when the file has none.");
    m.def("write_png", [](const std::filesystem::path& path, const py::array& image, double pixel_mm) {
        const image8 img = image_from(image, "image");
        py::gil_scoped_release nogil;
        io::write_png(path, img, {.pixel_mm = pixel_mm});
    }, py::arg("path"), py::arg("image"), py::arg("pixel_mm") = 0.0,
          "Writes a uint8 array (h, w) or (h, w, c), c = 1..4, as PNG, atomically. pixel_mm > 0 stores the\n"
          "physical pixel size (mm) in a pHYs chunk, as the slicers' stacks carry it; 0 stores none.");
    m.def("read_svg", [](const std::filesystem::path& path, double tolerance) {
        const io::svg_document doc = io::read_svg(path, tolerance);
        py::list shapes;
        for (const io::svg_shape& s : doc.shapes) {
            py::list paths;
            for (const auto& sp : s.subpaths) paths.append(points_to(sp));
            py::dict d;
            d["subpaths"] = paths;
            d["closed"] = s.closed;
            d["fill"] = s.fill, d["stroke"] = s.stroke, d["stroke_width"] = s.stroke_width, d["id"] = s.id;
            d["fill_rule"] = s.rule == fill_rule::evenodd ? "evenodd" : "nonzero";
            shapes.append(d);
        }
        py::dict out;
        out["width"] = doc.width, out["height"] = doc.height, out["width_unit"] = doc.width_unit, out["height_unit"] = doc.height_unit;
        out["view_box"] = doc.view_box ? py::object(py::make_tuple(doc.view_box->min_x, doc.view_box->min_y, doc.view_box->width, doc.view_box->height))
                                       : py::object(py::none());
        out["shapes"] = shapes;
        return out;
    }, py::arg("path"), py::arg("tolerance") = 0.01,
          "Reads an SVG drawing, curves flattened to within `tolerance` user units.\n\n"
          "Returns dict(width, height, width_unit, height_unit, view_box=(min_x, min_y, w, h) or None, shapes):\n"
          "each shape a dict(subpaths=[n x 2 float64 arrays in user units, y down], closed=[bool], fill, stroke,\n"
          "stroke_width, id, fill_rule).");
}

}  // namespace fabsynth::python
