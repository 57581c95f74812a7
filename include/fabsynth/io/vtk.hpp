// SPDX-License-Identifier: MIT
#pragma once
/// @file vtk.hpp  Legacy VTK files (version 3.0) that ParaView opens: meshes, unstructured grids
/// and regular grids with per-point / per-cell fields; reading of STRUCTURED_POINTS.
///
/// Binary files store big-endian numbers as the legacy format requires (doubles for coordinates,
/// int32 for connectivity, each field in its own vtk_type); ASCII files print shortest exact
/// decimals, so both encodings round-trip every type exactly. Field values are held as doubles;
/// `type` chooses how the file stores them: unsigned_char (1 byte: masks, labels), unsigned_short,
/// int, float (4 bytes: normals, densities) or double (8 bytes, the default). A 512^3 mask thus
/// takes 128 MiB as unsigned_char instead of 1 GiB as double. All writers are atomic and throw
/// invalid_input (naming the file) for inconsistent input: field sizes != count * components,
/// non-finite values, values the field's type cannot hold (integer types: whole numbers in range;
/// float: |x| <= FLT_MAX, stored rounded to the nearest float), empty field names, node ids out
/// of range, node counts that do not fit the cell type. Spaces and other special bytes in field
/// names are escaped as %XX, as VTK itself does.
///
/// Fields with 1..4 components are written as SCALARS (with LOOKUP_TABLE default); others (e.g.
/// 6 stress components) as FIELD arrays. Both show up as arrays in ParaView, in the given order.
///
/// Usage:
///   fabsynth::io::structured_points g;
///   g.dims = {nx, ny, nz};
///   g.spacing = fabsynth::vec3(0.5);
///   g.fields.push_back({"density", 1, values});        // values.size() == g.value_count()
///   g.fields.push_back({"solid", 1, mask, fabsynth::io::vtk_type::uint8});   // 0/1 as bytes
///   fabsynth::io::write_vtk("density.vtk", g);
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/io/atomic_file.hpp"
#include "fabsynth/io/detail/binary.hpp"
#include "fabsynth/io/detail/read_file.hpp"
#include "fabsynth/io/detail/text.hpp"
#include "fabsynth/io/encoding.hpp"

namespace fabsynth::io {

/// How a field's values are stored in the file (legacy VTK data type in brackets).
enum class vtk_type : std::uint8_t {
    float64,  ///< [double] 8 bytes, exact for any double (the default)
    float32,  ///< [float] 4 bytes, values rounded to the nearest float
    int32,    ///< [int] 4 bytes, whole numbers in [-2^31, 2^31)
    uint16,   ///< [unsigned_short] 2 bytes, whole numbers in [0, 65535]
    uint8,    ///< [unsigned_char] 1 byte, whole numbers in [0, 255] (masks, labels)
};

/// The legacy VTK name of a type ("double", "float", "int", "unsigned_short", "unsigned_char").
[[nodiscard]] constexpr std::string_view vtk_type_name(vtk_type t) noexcept {
    switch (t) {
        case vtk_type::float64: return "double";
        case vtk_type::float32: return "float";
        case vtk_type::int32: return "int";
        case vtk_type::uint16: return "unsigned_short";
        case vtk_type::uint8: return "unsigned_char";
    }
    return "double";
}

/// A named array attached to points or cells: values.size() == count * components, tuple-major
/// (the components of item i are values[i*components .. i*components+components-1]), stored in
/// the file as `type`. The reader sets `type` from the file: unsigned_char, unsigned_short, int,
/// float and double map to their own type, char and short to int32, wider integers to float64.
struct vtk_field {
    std::string name;
    int components = 1;
    std::vector<double> values;
    vtk_type type = vtk_type::float64;
    friend bool operator==(const vtk_field&, const vtk_field&) = default;
};

/// One cell of an unstructured grid: a VTK cell type id and its node (point) indices in VTK's
/// node order for that type.
struct vtk_cell {
    std::uint8_t type = 0;
    std::vector<std::uint32_t> nodes;
};

/// VTK cell type ids (vtkCellType.h) for the common cells.
namespace vtk_cell_type {
inline constexpr std::uint8_t vertex = 1, poly_vertex = 2, line = 3, poly_line = 4, triangle = 5, triangle_strip = 6,
                              polygon = 7, pixel = 8, quad = 9, tetra = 10, voxel = 11, hexahedron = 12, wedge = 13,
                              pyramid = 14, quadratic_edge = 21, quadratic_triangle = 22, quadratic_quad = 23,
                              quadratic_tetra = 24, quadratic_hexahedron = 25;
}

/// A regular grid (VTK STRUCTURED_POINTS). `dims` are VTK's DIMENSIONS, i.e. the number of
/// grid *points* per axis (each >= 1); point (i,j,k) sits at origin + (i,j,k) * spacing (mm).
/// With cell_data = false every field has one tuple per point (x fastest, then y, then z);
/// with cell_data = true one per cell, and there are max(dims-1, 1) cells per axis. To show an
/// n-voxel grid as voxels, use dims = n + 1 and cell_data = true; to show voxel centres as
/// points, use dims = n and origin = centre of the first voxel.
struct structured_points {
    ivec3 dims{0};
    vec3 origin{0.0};
    vec3 spacing{1.0};
    bool cell_data = false;
    std::vector<vtk_field> fields;

    /// Tuples each field must hold (points or cells, see above); 0 if dims are not all >= 1.
    [[nodiscard]] std::uint64_t value_count() const noexcept {
        std::uint64_t n = 1;
        for (int a = 0; a < 3; ++a) {
            if (dims[a] < 1) return 0;
            n *= static_cast<std::uint64_t>(cell_data ? std::max(dims[a] - 1, 1) : dims[a]);
        }
        return n;
    }
    friend bool operator==(const structured_points&, const structured_points&) = default;
};

/// Largest number of points (or values per field) the VTK reader and writers accept: 2^31.
inline constexpr std::uint64_t max_vtk_values = std::uint64_t{1} << 31;
/// Largest |ORIGIN| and SPACING accepted (mm): a kilometre-scale grid is no print, and larger values
/// overflow volumes and cell indices downstream, far from the line that gave them.
inline constexpr double max_vtk_coordinate = 1e9;

namespace detail {

/// Writes numbers as ASCII text or big-endian binary.
class vtk_out {
public:
    explicit vtk_out(encoding enc) : bin_(enc == encoding::binary) {}
    void text(std::string_view s) { out_ += s; }
    void real(double x) {
        if (bin_) return store(out_, x, byte_order::big);
        sep();
        append_number(out_, x);
    }
    void integer(std::int64_t x) {
        if (bin_) return store(out_, static_cast<std::int32_t>(x), byte_order::big);
        sep();
        append_number(out_, x);
    }
    /// A field value in its type (already checked to fit, see check_vtk_fields).
    void value(double x, vtk_type t) {
        if (bin_) {
            const auto be = byte_order::big;
            switch (t) {
                case vtk_type::float64: return store(out_, x, be);
                case vtk_type::float32: return store(out_, static_cast<float>(x), be);
                case vtk_type::int32: return store(out_, static_cast<std::int32_t>(x), be);
                case vtk_type::uint16: return store(out_, static_cast<std::uint16_t>(x), be);
                case vtk_type::uint8: out_ += static_cast<char>(static_cast<std::uint8_t>(x)); return;
            }
        }
        sep();
        if (t == vtk_type::float64) append_number(out_, x);
        else if (t == vtk_type::float32) append_float(out_, static_cast<float>(x));
        else append_number(out_, static_cast<std::int64_t>(x));
    }
    /// Ends a data block (newline in both encodings: VTK expects one after binary data).
    void end_block() {
        out_ += '\n';
        col_ = 0;
    }
    /// Ends a row of ASCII values (nothing in binary).
    void end_row() {
        if (!bin_) end_block();
    }
    [[nodiscard]] bool binary() const noexcept { return bin_; }
    [[nodiscard]] const std::string& str() const noexcept { return out_; }
    void header(std::string_view title) {
        out_ += "# vtk DataFile Version 3.0\n";
        out_ += title;
        out_ += bin_ ? "\nBINARY\n" : "\nASCII\n";
    }

private:
    void sep() {
        if (col_++) out_ += ' ';
    }
    std::string out_;
    bool bin_;
    std::size_t col_ = 0;
};

inline void check_vtk_fields(const std::vector<vtk_field>& fields, std::uint64_t count, const std::string& file,
                             std::string_view where) {
    for (const vtk_field& f : fields) {
        const std::string what = file + ": " + std::string(where) + " field '" + f.name + "'";
        if (f.name.empty()) throw invalid_input(file + ": a " + std::string(where) + " field has an empty name");
        if (f.components < 1 || f.components > 1024)
            throw invalid_input(what + ": components " + std::to_string(f.components) + " not in [1, 1024]");
        if (f.values.size() != count * static_cast<std::uint64_t>(f.components))
            throw invalid_input(what + ": has " + std::to_string(f.values.size()) + " values, expected " +
                                std::to_string(count) + " x " + std::to_string(f.components));
        double lo = 0, hi = 0;  // range of the integer types
        switch (f.type) {
            case vtk_type::int32: lo = -2147483648.0, hi = 2147483647.0; break;
            case vtk_type::uint16: hi = 65535; break;
            case vtk_type::uint8: hi = 255; break;
            default: break;
        }
        const bool integral = f.type != vtk_type::float64 && f.type != vtk_type::float32;
        for (std::size_t i = 0; i < f.values.size(); ++i) {
            const double x = f.values[i];
            if (!std::isfinite(x)) throw invalid_input(what + ": value " + std::to_string(i) + " is not finite");
            if (f.type == vtk_type::float32 && std::abs(x) > static_cast<double>(FLT_MAX))
                throw invalid_input(what + ": value " + std::to_string(i) + " (" + std::to_string(x) + ") does not fit a float");
            if (integral && !(x >= lo && x <= hi && x == std::floor(x)))
                throw invalid_input(what + ": value " + std::to_string(i) + " (" + std::to_string(x) + ") is not a whole number in [" +
                                    std::to_string(static_cast<std::int64_t>(lo)) + ", " +
                                    std::to_string(static_cast<std::int64_t>(hi)) + "] for type " +
                                    std::string(vtk_type_name(f.type)));
        }
    }
}

/// A field name as legacy VTK stores it: bytes <= ' ', '%' and >= 127 escaped as %XX
/// (vtkDataWriter's convention; vtkDataReader decodes it).
inline std::string vtk_encode_name(std::string_view s) {
    static constexpr char digits[] = "0123456789ABCDEF";
    std::string out;
    for (char ch : s) {
        const auto u = static_cast<unsigned char>(ch);
        if (u <= 32 || u >= 127 || ch == '%') {
            out += '%';
            out += digits[u >> 4];
            out += digits[u & 15];
        } else {
            out += ch;
        }
    }
    return out;
}

/// Appends "POINT_DATA n" / "CELL_DATA n" and the fields (fields already checked), in order:
/// 1..4 components as SCALARS, more as a one-array FIELD block (VTK's reader merges FIELD blocks).
inline void write_vtk_fields(vtk_out& o, std::string_view section, std::uint64_t count,
                             const std::vector<vtk_field>& fields) {
    if (fields.empty()) return;
    o.text(std::string(section) + " " + std::to_string(count) + "\n");
    for (const vtk_field& f : fields) {
        const std::string type(vtk_type_name(f.type));
        if (f.components <= 4)
            o.text(std::string("SCALARS ") + vtk_encode_name(f.name) + " " + type + " " + std::to_string(f.components) +
                   "\nLOOKUP_TABLE default\n");
        else
            o.text(std::string("FIELD FieldData 1\n") + vtk_encode_name(f.name) + " " + std::to_string(f.components) + " " + std::to_string(count) +
                   " " + type + "\n");
        for (std::size_t i = 0; i < f.values.size(); ++i) {
            o.value(f.values[i], f.type);
            if ((i + 1) % static_cast<std::size_t>(f.components) == 0) o.end_row();
        }
        if (o.binary()) o.end_block();
    }
}

inline void write_vtk_points(vtk_out& o, const std::vector<vec3>& points, const std::string& file) {
    if (points.size() > max_vtk_values)
        throw invalid_input(file + ": " + std::to_string(points.size()) + " points exceed the VTK limit of 2^31");
    for (std::size_t i = 0; i < points.size(); ++i)
        if (!all_finite(points[i])) throw invalid_input(file + ": point " + std::to_string(i) + " is not finite");
    o.text(std::string("POINTS ") + std::to_string(points.size()) + " double\n");
    for (const vec3& p : points) {
        o.real(p.x), o.real(p.y), o.real(p.z);
        o.end_row();
    }
    if (o.binary()) o.end_block();
}

/// Node count a fixed-size VTK cell type needs; 0 for variable-size types; -1 if unknown.
[[nodiscard]] inline int vtk_nodes_per_cell(std::uint8_t type) noexcept {
    switch (type) {
        case 1: return 1;
        case 3: return 2;
        case 5: return 3;
        case 8: case 9: case 10: return 4;
        case 11: case 12: return 8;
        case 13: return 6;
        case 14: return 5;
        case 21: return 3;
        case 22: return 6;
        case 23: return 8;
        case 24: return 10;
        case 25: return 20;
        case 2: case 4: case 6: case 7: return 0;
        default: return -1;
    }
}

}  // namespace detail

/// Writes a triangle mesh as VTK POLYDATA with optional per-vertex (point_fields, count =
/// num_vertices) and per-face (cell_fields, count = num_faces) arrays. Binary by default.
inline void write_vtk(const std::filesystem::path& path, const triangle_mesh& m,
                      const std::vector<vtk_field>& point_fields = {}, const std::vector<vtk_field>& cell_fields = {},
                      encoding enc = encoding::binary) {
    const std::string file = path.string();
    validate(m, (file + ": mesh").c_str());
    if (m.faces.size() > max_vtk_values / 4)
        throw invalid_input(file + ": too many faces for legacy VTK (" + std::to_string(m.faces.size()) + ")");
    detail::check_vtk_fields(point_fields, m.vertices.size(), file, "point");
    detail::check_vtk_fields(cell_fields, m.faces.size(), file, "cell");
    detail::vtk_out o(enc);
    o.header("fabsynth triangle mesh");
    o.text("DATASET POLYDATA\n");
    detail::write_vtk_points(o, m.vertices, file);
    o.text(std::string("POLYGONS ") + std::to_string(m.faces.size()) + " " + std::to_string(4 * m.faces.size()) + "\n");
    for (const auto& f : m.faces) {
        o.integer(3), o.integer(f[0]), o.integer(f[1]), o.integer(f[2]);
        o.end_row();
    }
    if (o.binary()) o.end_block();
    detail::write_vtk_fields(o, "CELL_DATA", m.faces.size(), cell_fields);
    detail::write_vtk_fields(o, "POINT_DATA", m.vertices.size(), point_fields);
    atomic_write(path, o.str());
}

/// Writes an UNSTRUCTURED_GRID: points (mm), cells (VTK type + node ids), optional per-point and
/// per-cell fields. Binary by default.
inline void write_vtk_unstructured(const std::filesystem::path& path, const std::vector<vec3>& points,
                                   const std::vector<vtk_cell>& cells, const std::vector<vtk_field>& point_fields = {},
                                   const std::vector<vtk_field>& cell_fields = {}, encoding enc = encoding::binary) {
    const std::string file = path.string();
    std::uint64_t size = 0;
    for (std::size_t c = 0; c < cells.size(); ++c) {
        const vtk_cell& cell = cells[c];
        const int need = detail::vtk_nodes_per_cell(cell.type);
        const std::string what = file + ": cell " + std::to_string(c) + " (VTK type " + std::to_string(cell.type) + ")";
        if (need < 0) throw invalid_input(what + ": unsupported cell type");
        if (need > 0 && cell.nodes.size() != static_cast<std::size_t>(need))
            throw invalid_input(what + ": has " + std::to_string(cell.nodes.size()) + " nodes, needs " + std::to_string(need));
        if (cell.nodes.empty()) throw invalid_input(what + ": has no nodes");
        for (std::uint32_t n : cell.nodes)
            if (n >= points.size())
                throw invalid_input(what + ": node " + std::to_string(n) + " >= " + std::to_string(points.size()) + " points");
        size += 1 + cell.nodes.size();
    }
    if (size >= max_vtk_values) throw invalid_input(file + ": cell list too large for legacy VTK");
    detail::check_vtk_fields(point_fields, points.size(), file, "point");
    detail::check_vtk_fields(cell_fields, cells.size(), file, "cell");
    detail::vtk_out o(enc);
    o.header("fabsynth unstructured grid");
    o.text("DATASET UNSTRUCTURED_GRID\n");
    detail::write_vtk_points(o, points, file);
    o.text(std::string("CELLS ") + std::to_string(cells.size()) + " " + std::to_string(size) + "\n");
    for (const vtk_cell& cell : cells) {
        o.integer(static_cast<std::int64_t>(cell.nodes.size()));
        for (std::uint32_t n : cell.nodes) o.integer(n);
        o.end_row();
    }
    if (o.binary()) o.end_block();
    o.text(std::string("CELL_TYPES ") + std::to_string(cells.size()) + "\n");
    for (const vtk_cell& cell : cells) {
        o.integer(cell.type);
        o.end_row();
    }
    if (o.binary()) o.end_block();
    detail::write_vtk_fields(o, "CELL_DATA", cells.size(), cell_fields);
    detail::write_vtk_fields(o, "POINT_DATA", points.size(), point_fields);
    atomic_write(path, o.str());
}

/// VTK bytes of a regular grid (see structured_points); `name` is used in error messages.
inline std::string format_vtk(const structured_points& g, encoding enc = encoding::binary, std::string_view name = "VTK") {
    const std::string file(name);
    for (int a = 0; a < 3; ++a)
        if (g.dims[a] < 1) throw invalid_input(file + ": grid dimensions must be >= 1 on every axis");
    std::uint64_t points = 1;
    for (int a = 0; a < 3; ++a) points *= static_cast<std::uint64_t>(g.dims[a]);
    if (points > max_vtk_values)
        throw invalid_input(file + ": grid of " + std::to_string(points) + " points exceeds the limit of 2^31");
    if (!all_finite(g.origin)) throw invalid_input(file + ": grid origin is not finite");
    for (int a = 0; a < 3; ++a)
        if (!(std::isfinite(g.spacing[a]) && g.spacing[a] > 0)) throw invalid_input(file + ": grid spacing must be finite and > 0");
    detail::check_vtk_fields(g.fields, g.value_count(), file, g.cell_data ? "cell" : "point");
    detail::vtk_out o(enc);
    o.header("fabsynth structured points");
    std::string h = std::string("DATASET STRUCTURED_POINTS\nDIMENSIONS ") + std::to_string(g.dims.x) + " " + std::to_string(g.dims.y) +
                    " " + std::to_string(g.dims.z) + "\nORIGIN ";
    for (int a = 0; a < 3; ++a) detail::append_number(h, g.origin[a]), h += a < 2 ? ' ' : '\n';
    h += "SPACING ";
    for (int a = 0; a < 3; ++a) detail::append_number(h, g.spacing[a]), h += a < 2 ? ' ' : '\n';
    o.text(h);
    if (g.fields.empty()) o.text(std::string(g.cell_data ? "CELL_DATA " : "POINT_DATA ") + std::to_string(g.value_count()) + "\n");
    detail::write_vtk_fields(o, g.cell_data ? "CELL_DATA" : "POINT_DATA", g.value_count(), g.fields);
    return o.str();
}

/// Writes a regular grid as VTK STRUCTURED_POINTS (binary by default). Atomic.
inline void write_vtk(const std::filesystem::path& path, const structured_points& g, encoding enc = encoding::binary) {
    atomic_write(path, format_vtk(g, enc, path.string()));
}

namespace detail {

/// Byte size of a legacy VTK data type in binary files; 0 if unsupported.
[[nodiscard]] inline std::size_t vtk_type_size(std::string_view t) noexcept {
    if (t == "unsigned_char" || t == "char") return 1;
    if (t == "unsigned_short" || t == "short") return 2;
    if (t == "unsigned_int" || t == "int" || t == "float") return 4;
    if (t == "unsigned_long" || t == "long" || t == "double" || t == "vtktypeint64" || t == "vtktypeuint64") return 8;
    return 0;
}

/// Array names in legacy VTK escape spaces and other bytes as %XX (vtkDataWriter); decode them.
inline std::string vtk_decode_name(std::string_view s) {
    auto hex = [](char ch) {
        return ch >= '0' && ch <= '9' ? ch - '0' : ch >= 'a' && ch <= 'f' ? ch - 'a' + 10 : ch >= 'A' && ch <= 'F' ? ch - 'A' + 10 : -1;
    };
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() && hex(s[i + 1]) >= 0 && hex(s[i + 2]) >= 0) {
            out += static_cast<char>(hex(s[i + 1]) * 16 + hex(s[i + 2]));
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}

/// The vtk_type a legacy data type is read as (see vtk_field), and for integer types the range
/// their ASCII values must lie in.
struct vtk_read_type {
    vtk_type as = vtk_type::float64;
    bool integral = false;
    double lo = 0, hi = 0;
};
[[nodiscard]] inline vtk_read_type vtk_read_type_of(std::string_view t) noexcept {
    if (t == "unsigned_char") return {vtk_type::uint8, true, 0, 255};
    if (t == "char") return {vtk_type::int32, true, -128, 127};
    if (t == "unsigned_short") return {vtk_type::uint16, true, 0, 65535};
    if (t == "short") return {vtk_type::int32, true, -32768, 32767};
    if (t == "int") return {vtk_type::int32, true, -2147483648.0, 2147483647.0};
    if (t == "unsigned_int") return {vtk_type::float64, true, 0, 4294967295.0};
    if (t == "float") return {vtk_type::float32, false, 0, 0};
    if (t == "double") return {vtk_type::float64, false, 0, 0};
    return {vtk_type::float64, true, -18446744073709551616.0, 18446744073709551616.0};  // 64-bit integers
}

/// Reads `count` tuples of `comps` values of VTK type `type` (ASCII tokens or big-endian bytes);
/// `as` receives the vtk_type the values are kept as. ASCII values of integer types must be
/// whole numbers in the type's range; ASCII floats are rounded to float, as binary ones are.
inline std::vector<double> read_vtk_values(token_cursor& c, bool binary, std::string_view type, std::uint64_t count,
                                           std::uint64_t comps, std::string_view what, vtk_type& as) {
    const std::size_t size = vtk_type_size(type);
    if (!size) c.fail(std::string("unsupported data type ") + quote(type) + " for " + std::string(what));
    const vtk_read_type rt = vtk_read_type_of(type);
    as = rt.as;
    if (comps == 0 || comps > max_vtk_values || count * comps > max_vtk_values)
        throw invalid_input(std::string(c.name()) + ":" + std::to_string(c.line()) + ": " + std::string(what) + " has " +
                            std::to_string(count) + " x " + std::to_string(comps) + " values, more than the limit of 2^31");
    const std::uint64_t n = count * comps;
    std::vector<double> v;
    if (!binary) {
        if (n > c.remaining() / 2 + 1)
            c.fail(std::string(what) + " needs " + std::to_string(n) + " values but the file is too short");
        v.reserve(static_cast<std::size_t>(n));
        for (std::uint64_t i = 0; i < n; ++i) {
            const std::string_view t = c.require(std::string(what) + " values");
            double x = c.finite(t, what);
            if (rt.integral && !(x >= rt.lo && x <= rt.hi && x == std::floor(x)))
                c.fail(std::string(what) + " value " + quote(t) + " is not a whole number in the range of " + std::string(type));
            if (rt.as == vtk_type::float32) {
                if (std::abs(x) > static_cast<double>(FLT_MAX)) c.fail(std::string(what) + " value " + quote(t) + " does not fit a float");
                x = static_cast<double>(static_cast<float>(x));
            }
            v.push_back(x);
        }
        return v;
    }
    c.end_line(std::string(what) + " header");  // binary data starts after this newline
    const std::size_t start = c.offset();
    if (n > c.remaining() / size)
        c.fail_at_byte(start, std::string(what) + " needs " + std::to_string(n * size) + " bytes of binary data, only " +
                                  std::to_string(c.remaining()) + " left (truncated)");
    v.resize(static_cast<std::size_t>(n));
    const char* p = c.data().data() + start;
    for (std::size_t i = 0; i < v.size(); ++i, p += size) {
        double x = 0;
        const auto be = byte_order::big;
        if (type == "unsigned_char") x = static_cast<unsigned char>(*p);
        else if (type == "char") x = static_cast<signed char>(*p);
        else if (type == "unsigned_short") x = load<std::uint16_t>(p, be);
        else if (type == "short") x = load<std::int16_t>(p, be);
        else if (type == "unsigned_int") x = load<std::uint32_t>(p, be);
        else if (type == "int") x = load<std::int32_t>(p, be);
        else if (type == "float") x = static_cast<double>(load<float>(p, be));
        else if (type == "double") x = load<double>(p, be);
        else if (type == "unsigned_long" || type == "vtktypeuint64") x = static_cast<double>(load<std::uint64_t>(p, be));
        else x = static_cast<double>(load<std::int64_t>(p, be));
        if (!std::isfinite(x)) c.fail_at_byte(start + i * size, std::string(what) + " value " + std::to_string(i) + " is not finite");
        v[i] = x;
    }
    c.advance_to(start + v.size() * size);
    return v;
}

}  // namespace detail

/// Parses legacy VTK STRUCTURED_POINTS bytes (ASCII or BINARY) with POINT_DATA or CELL_DATA
/// holding SCALARS (optionally with LOOKUP_TABLE), VECTORS, NORMALS, TENSORS and FIELD arrays.
/// All values are converted to double; each field's `type` tells how the file stored them, so
/// writing the grid again keeps the file's types (see vtk_field). Throws invalid_input for grids of more than 2^31 points
/// (before allocating) and io_error "FILE:LINE" / "FILE: byte N" for anything malformed.
inline structured_points parse_vtk_structured_points(std::string_view bytes, std::string_view name) {
    using detail::quote;
    const auto out_of_range = [](const std::string& what, double v) {
        char msg[120];
        std::snprintf(msg, sizeof msg, "%s %.3g is out of range (|value| <= %.0e mm)", what.c_str(), v, max_vtk_coordinate);
        return std::string(msg);
    };
    if (bytes.empty()) throw io_error(name, 0, "file is empty");
    detail::token_cursor c(bytes, name);
    // Line 1: "# vtk DataFile Version x.y"; line 2: a title; line 3: ASCII or BINARY.
    constexpr std::string_view magic = "# vtk DataFile Version";
    if (bytes.substr(0, magic.size()) != magic) c.fail(std::string("not a legacy VTK file (expected '") + std::string(magic) + "')");
    c.skip_line();
    c.skip_line();
    const std::string_view enc = c.require("ASCII or BINARY");
    bool binary = false;
    if (detail::iequals(enc, "binary")) binary = true;
    else if (!detail::iequals(enc, "ascii")) c.fail(std::string("expected ASCII or BINARY on line 3, found ") + quote(enc));
    std::string_view t = c.require("DATASET");
    if (t != "DATASET") c.fail(std::string("expected 'DATASET', found ") + quote(t));
    t = c.require("dataset type");
    if (t != "STRUCTURED_POINTS") c.fail(std::string("dataset is ") + quote(t) + ", expected STRUCTURED_POINTS");

    structured_points g;
    bool have_dims = false;
    for (;;) {
        t = c.require("POINT_DATA or CELL_DATA");
        if (t == "POINT_DATA" || t == "CELL_DATA") break;
        if (t == "DIMENSIONS") {
            for (int a = 0; a < 3; ++a)
                g.dims[a] = static_cast<int>(c.integer(c.require("dimension"), "dimension", 1, std::numeric_limits<std::int32_t>::max()));
            std::uint64_t points = 1;
            for (int a = 0; a < 3; ++a) points *= static_cast<std::uint64_t>(g.dims[a]);
            if (points > max_vtk_values)
                throw invalid_input(std::string(name) + ":" + std::to_string(c.line()) + ": grid of " + std::to_string(points) +
                                    " points exceeds the limit of 2^31");
            have_dims = true;
        } else if (t == "ORIGIN") {
            for (int a = 0; a < 3; ++a) {
                g.origin[a] = c.finite(c.require("origin"), "origin");
                if (std::abs(g.origin[a]) > max_vtk_coordinate) c.fail(out_of_range("ORIGIN", g.origin[a]));
            }
        } else if (t == "SPACING" || t == "ASPECT_RATIO") {
            for (int a = 0; a < 3; ++a) {
                g.spacing[a] = c.finite(c.require("spacing"), "spacing");
                if (g.spacing[a] <= 0) c.fail("spacing must be > 0");
                if (g.spacing[a] > max_vtk_coordinate) c.fail(out_of_range(std::string(t), g.spacing[a]));
            }
        } else {
            c.fail(std::string("unexpected ") + quote(t) + " in the STRUCTURED_POINTS header");
        }
    }
    if (!have_dims) c.fail(std::string("DIMENSIONS missing before ") + std::string(t));
    g.cell_data = t == "CELL_DATA";
    const std::uint64_t count = g.value_count();
    const std::uint64_t declared = static_cast<std::uint64_t>(c.integer(c.require("value count"), "value count", 0));
    if (declared != count)
        c.fail(std::string(t) + " " + std::to_string(declared) + " does not match the " + std::to_string(count) +
               (g.cell_data ? " cells" : " points") + " of the grid");

    for (t = c.next(); !t.empty(); t = c.next()) {
        if (t == "SCALARS") {
            vtk_field f;
            f.name = detail::vtk_decode_name(c.require_on_line("array name"));
            const std::string_view type = c.require_on_line("data type");
            const std::string_view nc = c.next_on_line();
            f.components = nc.empty() ? 1 : static_cast<int>(c.integer(nc, "number of components", 1, 4));
            detail::token_cursor peek = c;
            if (peek.next() == "LOOKUP_TABLE") {
                c.next();
                c.require_on_line("lookup table name");
            }
            f.values = detail::read_vtk_values(c, binary, type, count, static_cast<std::uint64_t>(f.components), std::string("SCALARS ") + f.name,
                                               f.type);
            g.fields.push_back(std::move(f));
        } else if (t == "VECTORS" || t == "NORMALS" || t == "TENSORS") {
            vtk_field f;
            f.name = detail::vtk_decode_name(c.require_on_line("array name"));
            f.components = t == "TENSORS" ? 9 : 3;
            const std::string_view type = c.require_on_line("data type");
            f.values = detail::read_vtk_values(c, binary, type, count, static_cast<std::uint64_t>(f.components),
                                               std::string(t) + " " + f.name, f.type);
            g.fields.push_back(std::move(f));
        } else if (t == "FIELD") {
            c.require_on_line("field name");
            const auto arrays = c.integer(c.require_on_line("number of arrays"), "number of arrays", 0, 1 << 20);
            for (std::int64_t i = 0; i < arrays; ++i) {
                vtk_field f;
                f.name = detail::vtk_decode_name(c.require("array name"));
                f.components = static_cast<int>(c.integer(c.require_on_line("components"), "components", 1, 1 << 20));
                const auto tuples = c.integer(c.require_on_line("tuples"), "tuples", 0);
                if (static_cast<std::uint64_t>(tuples) != count)
                    c.fail(std::string("FIELD array '") + f.name + "' has " + std::to_string(tuples) + " tuples, expected " + std::to_string(count));
                const std::string_view type = c.require_on_line("data type");
                f.values = detail::read_vtk_values(c, binary, type, count, static_cast<std::uint64_t>(f.components),
                                                   std::string("FIELD array ") + f.name, f.type);
                g.fields.push_back(std::move(f));
            }
        } else if (t == "METADATA") {
            // Written by VTK >= 8 after arrays: skip up to the blank line that ends the block.
            c.skip_line();
            for (;;) {
                const std::size_t at = c.offset();
                if (at >= bytes.size()) break;
                std::size_t e = at;
                while (e < bytes.size() && detail::is_blank(bytes[e])) ++e;
                c.skip_line();
                if (e >= bytes.size() || bytes[e] == '\n') break;
            }
        } else if (t == "POINT_DATA" || t == "CELL_DATA") {
            c.fail("file has both POINT_DATA and CELL_DATA; fabsynth reads one of them");
        } else {
            c.fail(std::string("unsupported VTK attribute ") + quote(t));
        }
    }
    return g;
}

/// Reads a legacy VTK STRUCTURED_POINTS file (see parse_vtk_structured_points).
inline structured_points read_vtk_structured_points(const std::filesystem::path& path) {
    return parse_vtk_structured_points(detail::read_file(path), path.string());
}

}  // namespace fabsynth::io
