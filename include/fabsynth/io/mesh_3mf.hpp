// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh_3mf.hpp  3MF triangle meshes (the format current slicers prefer), through lib3mf 1.x.
///
/// Needs the optional CMake target fabsynth::lib3mf (found when Debian's lib3mf-dev is installed),
/// which links lib3mf and defines FABSYNTH_HAS_LIB3MF; without it this header stops with #error.
///
/// Writing: one mesh object with one build item (no transform), in the unit of mesh_3mf_options
/// (millimetres by default, fabsynth's unit). Coordinates are rounded to float, and lib3mf 1.x
/// prints them cut to 6 decimals, so a position reads back within 1e-6 units (+ float rounding)
/// of float(x): 1 nm in millimetres, far below any printer's resolution. The same mesh and options give the same bytes: the UUIDs the
/// production extension asks for are derived from the content, not drawn at random. The file is
/// built in memory and written atomically (io/atomic_file.hpp). Refused with
/// invalid_input: a mesh without faces, non-finite or non-float coordinates, face indices out of
/// range, triangles that repeat a vertex (3MF forbids them), face colours not one per face.
/// Face colours (mesh_3mf_options::face_colours) are per-triangle colour properties, which
/// colour-aware slicers show and multi-material printers can use.
///
/// Reading: every build item that refers to a mesh object, with its transform applied, merged
/// into one triangle_mesh (vertices of item 0 first), in millimetres (converted from the file's
/// unit). Vertex order and triangles are kept as stored. Refused with io_error naming the file:
/// not a ZIP or a truncated one (checked here), anything lib3mf cannot read (no 3D model part,
/// malformed XML), component (assembly) objects, no build item, no triangles, non-finite
/// coordinates. (lib3mf 1.8.1 leaks about 0.5 KB of libzip state per read; writing is clean.)
///
/// Usage:
///   const auto mesh = fabsynth::io::read_mesh(FABSYNTH_DATA_DIR "/meshes/spot.stl");
///   fabsynth::io::write_3mf("spot.3mf", mesh);                       // millimetres
///   fabsynth::io::write_3mf("spot_in.3mf", inches, {.unit = fabsynth::io::unit_3mf::inch});
///   const auto back = fabsynth::io::read_3mf("spot.3mf");
///   fabsynth::io::write_3mf("red.3mf", mesh, {.face_colours = std::vector(mesh.faces.size(), std::array<std::uint8_t, 3>{200, 30, 30})});
#if !defined(FABSYNTH_HAS_LIB3MF)
#error "fabsynth/io/mesh_3mf.hpp needs lib3mf: link the CMake target fabsynth::lib3mf (Debian: lib3mf-dev), which defines FABSYNTH_HAS_LIB3MF"
#endif

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/io/atomic_file.hpp"
#include "fabsynth/io/detail/lib3mf_api.hpp"
#include "fabsynth/io/detail/mesh_check.hpp"
#include "fabsynth/io/detail/read_file.hpp"

namespace fabsynth::io {

/// The length unit a 3MF file declares for its coordinates.
enum class unit_3mf { micrometer, millimeter, centimeter, inch, foot, meter };

/// Options of write_3mf.
struct mesh_3mf_options {
    /// Unit the coordinates are given in (written as they are, and declared as this unit).
    unit_3mf unit = unit_3mf::millimeter;
    /// Name of the mesh object, shown by slicers.
    std::string name = "fabsynth mesh";
    /// sRGB colour of each triangle (one per face, in face order), written as per-triangle colour
    /// properties (3MF core colour groups); empty: no colours.
    std::vector<std::array<std::uint8_t, 3>> face_colours = {};
};

/// Millimetres per unit.
[[nodiscard]] constexpr double millimetres_per(unit_3mf u) noexcept {
    switch (u) {
        case unit_3mf::micrometer: return 0.001;
        case unit_3mf::millimeter: return 1.0;
        case unit_3mf::centimeter: return 10.0;
        case unit_3mf::inch: return 25.4;
        case unit_3mf::foot: return 304.8;
        case unit_3mf::meter: return 1000.0;
    }
    return 1.0;
}

namespace detail {

/// Owns one lib3mf object (released with lib3mf_release).
class lib3mf_object {
public:
    lib3mf_object() = default;
    lib3mf_object(const lib3mf_object&) = delete;
    lib3mf_object& operator=(const lib3mf_object&) = delete;
    ~lib3mf_object() {
        if (h_) lib3mf::release(h_);
    }
    [[nodiscard]] lib3mf::handle get() const noexcept { return h_; }
    /// For lib3mf's out-parameters; releases what was held.
    [[nodiscard]] lib3mf::handle* out() noexcept {
        if (h_) lib3mf::release(h_), h_ = nullptr;
        return &h_;
    }

private:
    lib3mf::handle h_ = nullptr;
};

/// lib3mf's message for the last error of `object` (or a generic one).
inline std::string lib3mf_message(lib3mf::handle object, const char* step) {
    lib3mf::dword code = 0;
    const char* msg = nullptr;
    std::string s = std::string(step) + " failed";
    if (object && lib3mf::getlasterror(object, &code, &msg) == 0 && msg && *msg) s += std::string(": ") + msg;
    else if (object && code) s += " (lib3mf error " + std::to_string(code) + ")";
    return s;
}

/// Throws io_error naming `file` unless lib3mf's interface major version is 1.
inline void check_lib3mf_version(std::string_view file) {
    lib3mf::dword major = 0, minor = 0, micro = 0;
    if (lib3mf::getinterfaceversion(&major, &minor, &micro) != 0 || major != 1)
        throw io_error(file, 0, "lib3mf interface version " + std::to_string(major) + "." + std::to_string(minor) +
                                    " is not the 1.x this build was written for");
}

/// A new lib3mf model, or io_error naming `file`.
inline void create_model(lib3mf_object& model, std::string_view file) {
    check_lib3mf_version(file);
    if (lib3mf::createmodel(model.out()) != 0 || !model.get()) throw io_error(file, 0, "lib3mf cannot create a model");
}

inline constexpr lib3mf::dword lib3mf_unit(unit_3mf u) noexcept {
    switch (u) {
        case unit_3mf::micrometer: return lib3mf::unit_micrometer;
        case unit_3mf::millimeter: return lib3mf::unit_millimeter;
        case unit_3mf::centimeter: return lib3mf::unit_centimeter;
        case unit_3mf::inch: return lib3mf::unit_inch;
        case unit_3mf::foot: return lib3mf::unit_foot;
        case unit_3mf::meter: return lib3mf::unit_meter;
    }
    return lib3mf::unit_millimeter;
}

/// A version-4-shaped UUID from a 64-bit content hash and a salt (reproducible output).
inline std::string content_uuid(std::uint64_t content, std::uint64_t salt) {
    static constexpr char hex[] = "0123456789abcdef";
    const std::uint64_t a = hash64(content, salt, 1), b = hash64(content, salt, 2);
    std::string u;
    for (int i = 0; i < 32; ++i) {
        const std::uint64_t word = i < 16 ? a : b;
        unsigned nibble = static_cast<unsigned>(word >> (4 * (i % 16))) & 15u;
        if (i == 12) nibble = 4;                    // version 4
        if (i == 16) nibble = 8 | (nibble & 3u);    // RFC 4122 variant
        if (i == 8 || i == 12 || i == 16 || i == 20) u += '-';
        u += hex[nibble];
    }
    return u;
}

}  // namespace detail

/// 3MF bytes (a ZIP package) of a triangle mesh; `name` is used in error messages.
inline std::string format_3mf(const triangle_mesh& m, const mesh_3mf_options& opt = {}, std::string_view name = "3MF") {
    const std::string file(name);
    if (m.faces.empty()) throw invalid_input(file + ": mesh has no faces (3MF needs at least one triangle)");
    detail::check_mesh_for_writing(m, file);
    detail::check_fits_float(m, file, "3MF");
    if (m.vertices.size() >= 0x7fffffffu || m.faces.size() >= 0x7fffffffu)
        throw invalid_input(file + ": mesh too large for 3MF (2^31 vertices or triangles)");
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        const auto& t = m.faces[f];
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
            throw invalid_input(file + ": face " + std::to_string(f) + " repeats a vertex (3MF forbids degenerate triangles)");
    }
    std::vector<detail::lib3mf::vertex> vertices(m.vertices.size());
    for (std::size_t i = 0; i < m.vertices.size(); ++i)
        vertices[i] = {{static_cast<float>(m.vertices[i].x), static_cast<float>(m.vertices[i].y), static_cast<float>(m.vertices[i].z)}};
    std::vector<detail::lib3mf::triangle> triangles(m.faces.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) triangles[f] = {{m.faces[f][0], m.faces[f][1], m.faces[f][2]}};
    std::uint64_t content = hash64(vertices.size(), triangles.size(), static_cast<std::uint64_t>(opt.unit));
    for (const auto& v : vertices)
        for (float x : v.position) content = hash64(content, std::bit_cast<std::uint32_t>(x));
    for (const auto& t : triangles) content = hash64(content, t.indices[0], t.indices[1], t.indices[2]);
    for (char ch : opt.name) content = hash64(content, static_cast<unsigned char>(ch));
    if (!opt.face_colours.empty() && opt.face_colours.size() != m.faces.size())
        throw invalid_input(file + ": " + std::to_string(opt.face_colours.size()) + " face colours for " + std::to_string(m.faces.size()) +
                            " faces (one per face, or none)");
    for (const auto& c : opt.face_colours) content = hash64(content, c[0], c[1], c[2]);

    namespace l = detail::lib3mf;
    detail::lib3mf_object model, mesh, item, writer;
    detail::create_model(model, name);
    auto check = [&](l::result r, l::handle object, const char* step) {
        if (r != 0) throw io_error(name, 0, detail::lib3mf_message(object, step));
    };
    check(l::model_setunit(model.get(), detail::lib3mf_unit(opt.unit)), model.get(), "setting the unit");
    check(l::model_addmeshobject(model.get(), mesh.out()), model.get(), "adding the mesh object");
    check(l::object_setnameutf8(mesh.get(), opt.name.c_str()), mesh.get(), "naming the mesh object");
    check(l::meshobject_setgeometry(mesh.get(), vertices.data(), static_cast<l::dword>(vertices.size()), triangles.data(),
                                    static_cast<l::dword>(triangles.size())),
          mesh.get(), "setting the mesh geometry");
    if (!opt.face_colours.empty()) {
        detail::lib3mf_object properties;
        check(l::meshobject_createpropertyhandler(mesh.get(), properties.out()), mesh.get(), "creating the colour properties");
        for (std::size_t f = 0; f < opt.face_colours.size(); ++f) {
            const auto& c = opt.face_colours[f];
            check(l::propertyhandler_setsinglecolorrgb(properties.get(), static_cast<l::dword>(f), c[0], c[1], c[2]), properties.get(),
                  "setting a triangle colour");
        }
        // 3MF wants an object-level default when triangles carry properties: the first face's colour
        detail::lib3mf_object fallback;
        check(l::object_createdefaultpropertyhandler(mesh.get(), fallback.out()), mesh.get(), "creating the default colour");
        const auto& c0 = opt.face_colours.front();
        check(l::defaultpropertyhandler_setcolorrgb(fallback.get(), c0[0], c0[1], c0[2]), fallback.get(), "setting the default colour");
    }
    check(l::object_setuuidutf8(mesh.get(), detail::content_uuid(content, 1).c_str()), mesh.get(), "setting the object UUID");
    check(l::model_addbuilditem(model.get(), mesh.get(), nullptr, item.out()), model.get(), "adding the build item");
    check(l::builditem_setuuidutf8(item.get(), detail::content_uuid(content, 2).c_str()), item.get(), "setting the item UUID");
    check(l::model_setbuilduuidutf8(model.get(), detail::content_uuid(content, 3).c_str()), model.get(), "setting the build UUID");
    check(l::model_querywriter(model.get(), "3mf", writer.out()), model.get(), "creating the 3MF writer");
    l::ulong64 size = 0;
    check(l::writer_getstreamsize(writer.get(), &size), writer.get(), "sizing the 3MF package");
    std::string bytes(static_cast<std::size_t>(size), '\0');
    check(l::writer_writetobuffer(writer.get(), reinterpret_cast<unsigned char*>(bytes.data()), size), writer.get(),
          "writing the 3MF package");
    return bytes;
}

/// Writes a triangle mesh as 3MF (atomically). Coordinates are taken to be in opt.unit
/// (millimetres by default). Throws invalid_input for a mesh 3MF cannot hold (see file comment),
/// io_error if lib3mf or the file system fails.
inline void write_3mf(const std::filesystem::path& path, const triangle_mesh& m, const mesh_3mf_options& opt = {}) {
    atomic_write(path, format_3mf(m, opt, path.string()));
}

/// Parses 3MF bytes into one triangle mesh in millimetres (see file comment); `name` prefixes
/// error messages. With `face_rgba`, also the colour of each face (in the order of the result's
/// faces): sRGB and alpha 255 for a triangle with a colour property (the mean of its corners'
/// colours when they differ), {0, 0, 0, 0} for one without.
inline triangle_mesh parse_3mf(std::string_view bytes, std::string_view name, std::vector<std::array<std::uint8_t, 4>>* face_rgba = nullptr) {
    namespace l = detail::lib3mf;
    if (bytes.empty()) throw io_error(name, 0, "file is empty");
    // A 3MF file is a ZIP package: check its first local header and its end-of-central-directory
    // record here, so non-ZIP and truncated input get a located message (and never reach
    // lib3mf 1.8.1's failed-open path, which leaks libzip's source object).
    if (bytes.size() < 22 || bytes.substr(0, 4) != std::string_view("PK\x03\x04", 4))
        throw io_error::at_byte(name, 0, "not a 3MF file (no ZIP signature)");
    const std::size_t eocd = bytes.rfind(std::string_view("PK\x05\x06", 4));
    if (eocd == std::string_view::npos || eocd + 22 > bytes.size() || bytes.size() - eocd > 22 + 65535)
        throw io_error(name, 0, "truncated 3MF package (no ZIP end-of-central-directory record)");
    detail::lib3mf_object model, reader, items;
    detail::create_model(model, name);
    if (l::model_queryreader(model.get(), "3mf", reader.out()) != 0)
        throw io_error(name, 0, detail::lib3mf_message(model.get(), "creating the 3MF reader"));
    std::vector<unsigned char> buffer(bytes.begin(), bytes.end());  // lib3mf takes a non-const buffer
    if (l::reader_readfrombuffer(reader.get(), buffer.data(), buffer.size()) != 0)
        throw io_error(name, 0, "not a readable 3MF file: " + detail::lib3mf_message(reader.get(), "lib3mf reading"));
    l::dword unit = l::unit_millimeter;
    if (l::model_getunit(model.get(), &unit) != 0 || unit > l::unit_meter) throw io_error(name, 0, "3MF file has an unknown unit");
    const double scale = millimetres_per(static_cast<unit_3mf>(unit));
    if (l::model_getbuilditems(model.get(), items.out()) != 0)
        throw io_error(name, 0, detail::lib3mf_message(model.get(), "listing the build items"));

    triangle_mesh out;
    std::size_t item_count = 0;
    for (;;) {
        l::boolean more = 0;
        if (l::builditemiterator_movenext(items.get(), &more) != 0) throw io_error(name, 0, "cannot iterate the 3MF build items");
        if (!more) break;
        const std::string what = "build item " + std::to_string(item_count++);
        detail::lib3mf_object item, object;
        l::boolean is_mesh = 0;
        l::transform t{};
        if (l::builditemiterator_getcurrent(items.get(), item.out()) != 0 ||
            l::builditem_getobjectresource(item.get(), object.out()) != 0 ||
            l::builditem_getobjecttransform(item.get(), &t) != 0 || l::object_ismeshobject(object.get(), &is_mesh) != 0)
            throw io_error(name, 0, what + ": " + detail::lib3mf_message(item.get(), "reading"));
        if (!is_mesh) throw io_error(name, 0, what + " is a components (assembly) object; fabsynth reads mesh objects only");
        l::dword nv = 0, nt = 0;
        if (l::meshobject_getvertexcount(object.get(), &nv) != 0 || l::meshobject_gettrianglecount(object.get(), &nt) != 0)
            throw io_error(name, 0, what + ": " + detail::lib3mf_message(object.get(), "reading the mesh size"));
        std::vector<l::vertex> vertices(nv);
        std::vector<l::triangle> triangles(nt);
        l::dword got_v = 0, got_t = 0;
        if ((nv && l::meshobject_getvertices(object.get(), vertices.data(), nv, &got_v) != 0) ||
            (nt && l::meshobject_gettriangleindices(object.get(), triangles.data(), nt, &got_t) != 0) || got_v != nv || got_t != nt)
            throw io_error(name, 0, what + ": " + detail::lib3mf_message(object.get(), "reading the mesh"));
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        if (out.vertices.size() + nv >= 0xffffffffULL) throw io_error(name, 0, "3MF file has more than 2^32-1 vertices");
        for (std::size_t i = 0; i < vertices.size(); ++i) {
            const float* p = vertices[i].position;
            vec3 q;
            for (int r = 0; r < 3; ++r)  // fields[r] is row r of [R | t] (lib3mf's translation: fields[r][3])
                q[r] = (double(p[0]) * t.fields[r][0] + double(p[1]) * t.fields[r][1] + double(p[2]) * t.fields[r][2] +
                        double(t.fields[r][3])) * scale;
            if (!all_finite(q)) throw io_error(name, 0, what + ": vertex " + std::to_string(i) + " is not finite");
            out.vertices.push_back(q);
        }
        for (std::size_t f = 0; f < triangles.size(); ++f) {
            const auto* ix = triangles[f].indices;
            if (ix[0] >= nv || ix[1] >= nv || ix[2] >= nv)
                throw io_error(name, 0, what + ": triangle " + std::to_string(f) + " has a vertex index out of range");
            out.faces.push_back({base + ix[0], base + ix[1], base + ix[2]});
        }
        if (face_rgba) {
            detail::lib3mf_object properties;
            if (l::meshobject_createpropertyhandler(object.get(), properties.out()) != 0)
                throw io_error(name, 0, what + ": " + detail::lib3mf_message(object.get(), "reading the triangle properties"));
            for (l::dword f = 0; f < nt; ++f) {
                l::dword type = l::property_none;
                l::triangle_colour c{};
                std::array<std::uint8_t, 4> rgba{0, 0, 0, 0};
                if (l::propertyhandler_getpropertytype(properties.get(), f, &type) == 0 && type == l::property_colour &&
                    l::propertyhandler_getcolor(properties.get(), f, &c) == 0) {
                    const auto mean = [&](unsigned char l::colour::*channel) {
                        return static_cast<std::uint8_t>((c.corners[0].*channel + c.corners[1].*channel + c.corners[2].*channel + 1) / 3);
                    };
                    rgba = {mean(&l::colour::red), mean(&l::colour::green), mean(&l::colour::blue), 255};
                }
                face_rgba->push_back(rgba);
            }
        }
    }
    if (item_count == 0) throw io_error(name, 0, "3MF file has no build items");
    if (out.faces.empty()) throw io_error(name, 0, "3MF file has no triangles");
    return out;
}

/// Reads a 3MF file into one triangle mesh in millimetres (see parse_3mf, also for `face_rgba`).
inline triangle_mesh read_3mf(const std::filesystem::path& path, std::vector<std::array<std::uint8_t, 4>>* face_rgba = nullptr) {
    return parse_3mf(detail::read_file(path), path.string(), face_rgba);
}

}  // namespace fabsynth::io
