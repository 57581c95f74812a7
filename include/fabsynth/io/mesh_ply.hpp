// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh_ply.hpp  PLY triangle meshes (ASCII, binary little- and big-endian): read and write.
///
/// Reading: the header must declare an element "vertex" with scalar properties x, y, z (any
/// numeric type; other properties such as normals or colours are read and ignored) and an
/// element "face" with a list property "vertex_indices" (or "vertex_index") of an integer type.
/// Other elements are skipped. Faces with more than 3 corners are fan-triangulated. ASCII bodies
/// must hold one element item per line (as every writer does), which catches wrong counts at
/// the line where they occur.
///
/// Rejected with io_error (header and ASCII body: "FILE:LINE", binary body: "FILE: byte N"):
/// empty files, a bad magic/format line, unknown types, missing x/y/z or face list, element
/// counts the file cannot hold (checked before allocating), counts that do not match the data
/// (too little data or data left over), unparsable or non-finite coordinates, face indices outside
/// [0, vertex count), faces with fewer than 3 corners, truncated binary data.
///
/// Writing: binary little-endian (float32 x y z, the default) or ASCII (double x y z printed with
/// shortest exact decimals); faces as `property list uchar int vertex_indices`.
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/io/atomic_file.hpp"
#include "fabsynth/io/detail/binary.hpp"
#include "fabsynth/io/detail/mesh_check.hpp"
#include "fabsynth/io/detail/read_file.hpp"
#include "fabsynth/io/detail/text.hpp"
#include "fabsynth/io/encoding.hpp"

namespace fabsynth::io {

namespace detail {

enum class ply_type : std::uint8_t { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

inline bool ply_type_from_name(std::string_view s, ply_type& t) {
    struct entry {
        std::string_view name;
        ply_type type;
    };
    static constexpr entry table[] = {
        {"char", ply_type::int8},     {"int8", ply_type::int8},       {"uchar", ply_type::uint8},
        {"uint8", ply_type::uint8},   {"short", ply_type::int16},     {"int16", ply_type::int16},
        {"ushort", ply_type::uint16}, {"uint16", ply_type::uint16},   {"int", ply_type::int32},
        {"int32", ply_type::int32},   {"uint", ply_type::uint32},     {"uint32", ply_type::uint32},
        {"float", ply_type::float32}, {"float32", ply_type::float32}, {"double", ply_type::float64},
        {"float64", ply_type::float64}};
    for (const entry& e : table)
        if (e.name == s) return t = e.type, true;
    return false;
}
[[nodiscard]] constexpr std::size_t ply_size(ply_type t) noexcept {
    constexpr std::size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[static_cast<int>(t)];
}
[[nodiscard]] constexpr bool ply_integral(ply_type t) noexcept { return t < ply_type::float32; }

struct ply_property {
    std::string name;
    ply_type type = ply_type::float32;  ///< value type (list items for lists)
    bool is_list = false;
    ply_type count_type = ply_type::uint8;
};
struct ply_element {
    std::string name;
    std::uint64_t count = 0;
    std::size_t line = 0;  ///< header line declaring it
    std::vector<ply_property> props;
};

/// Reads PLY body values in any of the three encodings.
class ply_body {
public:
    ply_body(std::string_view data, std::string_view name, std::size_t offset, std::size_t line, bool ascii,
             byte_order order)
        : c_(data, name, offset, line), ascii_(ascii), order_(order), pos_(offset) {}

    /// A value of type t; `what` names it in errors. Integers are range-checked for their type.
    double real(ply_type t, std::string_view what) {
        if (ascii_) {
            const std::string_view tok = token(what);
            if (ply_integral(t)) return static_cast<double>(int_token(tok, t, what));
            const auto v = to_double(tok);
            if (!v) c_.fail(std::string("cannot parse ") + std::string(what) + " from " + quote(tok));
            return *v;
        }
        const char* p = bytes(t, what);
        switch (t) {
            case ply_type::int8: return load<std::int8_t>(p, order_);
            case ply_type::uint8: return load<std::uint8_t>(p, order_);
            case ply_type::int16: return load<std::int16_t>(p, order_);
            case ply_type::uint16: return load<std::uint16_t>(p, order_);
            case ply_type::int32: return load<std::int32_t>(p, order_);
            case ply_type::uint32: return load<std::uint32_t>(p, order_);
            case ply_type::float32: return static_cast<double>(load<float>(p, order_));
            case ply_type::float64: return load<double>(p, order_);
        }
        return 0;
    }
    /// An integer value (t must be integral).
    std::int64_t integer(ply_type t, std::string_view what) {
        if (ascii_) return int_token(token(what), t, what);
        return static_cast<std::int64_t>(real(t, what));  // exact: every integral type fits a double
    }
    /// Starts the next element item: ASCII PLY holds one item per line (blank lines are skipped).
    void begin_item() { first_ = true; }
    /// Ends an item: in ASCII the rest of its line must be empty.
    void end_item(std::string_view element, std::uint64_t item) {
        if (!ascii_ || first_) return;
        const std::string_view t = c_.next_on_line();
        if (!t.empty())
            c_.fail(std::string("unexpected ") + quote(t) + " after " + std::string(element) + " " + std::to_string(item) +
                    " (wrong property count or element count?)");
        c_.skip_line();
    }
    /// Throws io_error at the last value read (line or byte).
    [[noreturn]] void fail(const std::string& what) const {
        if (ascii_) c_.fail(what);
        c_.fail_at_byte(last_, what);
    }
    /// Bytes left (binary) or characters left (ASCII) after the current position.
    [[nodiscard]] std::size_t remaining() const noexcept { return ascii_ ? c_.remaining() : c_.data().size() - pos_; }
    /// Throws unless all data was consumed (only whitespace may follow ASCII data).
    void expect_end() {
        if (ascii_) {
            const std::string_view t = c_.next();
            if (!t.empty()) c_.fail(std::string("data left after the last element (") + quote(t) + "): header counts are wrong");
        } else if (pos_ != c_.data().size()) {
            c_.fail_at_byte(pos_, std::to_string(c_.data().size() - pos_) +
                                      " bytes left after the last element: header counts are wrong");
        }
    }

private:
    std::string_view token(std::string_view what) {
        if (!first_) return c_.require_on_line(what);
        first_ = false;
        return c_.require(what);
    }
    std::int64_t int_token(std::string_view tok, ply_type t, std::string_view what) {
        static constexpr std::int64_t lo[] = {-128, 0, -32768, 0, std::numeric_limits<std::int32_t>::min(), 0};
        static constexpr std::int64_t hi[] = {127, 255, 32767, 65535, std::numeric_limits<std::int32_t>::max(),
                                              std::numeric_limits<std::uint32_t>::max()};
        const int i = static_cast<int>(t);
        return c_.integer(tok, what, lo[i], hi[i]);
    }
    const char* bytes(ply_type t, std::string_view what) {
        const std::size_t n = ply_size(t);
        last_ = pos_;
        if (c_.data().size() - pos_ < n)
            c_.fail_at_byte(pos_, std::string("file ends inside ") + std::string(what) + " (truncated or header counts too large)");
        const char* p = c_.data().data() + pos_;
        pos_ += n;
        return p;
    }

    token_cursor c_;
    bool ascii_;
    byte_order order_;
    std::size_t pos_;
    std::size_t last_ = 0;
    bool first_ = true;
};

}  // namespace detail

/// Parses PLY bytes (any encoding); `name` prefixes error messages.
inline triangle_mesh parse_ply(std::string_view bytes, std::string_view name) {
    using namespace detail;
    if (bytes.empty()) throw io_error(name, 0, "file is empty");
    token_cursor c(bytes, name);
    if (c.next() != "ply") c.fail("not a PLY file (first line must be 'ply')");
    c.end_line("'ply'");
    if (c.require("'format'") != "format") c.fail("expected 'format' on the second line");
    const std::string_view fmt = c.require_on_line("format name");
    bool ascii = false;
    byte_order order = byte_order::little;
    if (fmt == "ascii") ascii = true;
    else if (fmt == "binary_little_endian") order = byte_order::little;
    else if (fmt == "binary_big_endian") order = byte_order::big;
    else c.fail(std::string("unknown PLY format ") + quote(fmt));
    if (c.require_on_line("format version") != "1.0") c.fail("unsupported PLY version (expected 1.0)");
    c.end_line("the format version");

    std::vector<ply_element> elements;
    for (;;) {
        const std::string_view kw = c.require("'end_header'");
        if (kw == "end_header") {
            c.end_line("'end_header'");
            break;
        }
        if (kw == "comment" || kw == "obj_info") {
            c.skip_line();
        } else if (kw == "element") {
            ply_element e;
            e.line = c.line();
            e.name = std::string(c.require_on_line("element name"));
            e.count = static_cast<std::uint64_t>(
                c.integer(c.require_on_line("element count"), "element count", 0, std::numeric_limits<std::int64_t>::max()));
            c.end_line("the element count");
            elements.push_back(std::move(e));
        } else if (kw == "property") {
            if (elements.empty()) c.fail("'property' before any 'element'");
            ply_property p;
            std::string_view t = c.require_on_line("property type");
            if (t == "list") {
                p.is_list = true;
                const std::string_view ct = c.require_on_line("list count type");
                if (!ply_type_from_name(ct, p.count_type) || !ply_integral(p.count_type))
                    c.fail(std::string("list count type must be an integer type, got ") + quote(ct));
                t = c.require_on_line("list item type");
            }
            if (!ply_type_from_name(t, p.type)) c.fail(std::string("unknown property type ") + quote(t));
            p.name = std::string(c.require_on_line("property name"));
            c.end_line("the property name");
            elements.back().props.push_back(std::move(p));
        } else {
            c.fail(std::string("unexpected ") + quote(kw) + " in the PLY header");
        }
    }

    // Locate the data we keep and check the header against what the file can hold.
    const ply_element* vert = nullptr;
    const ply_element* face = nullptr;
    int ix = -1, iy = -1, iz = -1, iface = -1;
    std::uint64_t need_min = 0;  // lower bound on body bytes implied by the header
    const std::size_t body_bytes = bytes.size() - c.offset();
    for (const ply_element& e : elements) {
        std::uint64_t per = 0;
        for (const ply_property& p : e.props) per += ascii ? 2 : ply_size(p.is_list ? p.count_type : p.type);
        if (per > 0 && e.count > (body_bytes + 1) / per)
            throw io_error(name, e.line,
                           std::string("element '") + e.name + "' declares " + std::to_string(e.count) + " items but the " +
                               std::to_string(body_bytes) + " bytes of data cannot hold that many");
        need_min += per * e.count;
        if (need_min > body_bytes + 1)
            throw io_error(name, e.line, std::string("element counts exceed the ") + std::to_string(body_bytes) + " bytes of data");
        if (e.name == "vertex" && !vert) {
            vert = &e;
            for (std::size_t i = 0; i < e.props.size(); ++i) {
                const ply_property& p = e.props[i];
                int* slot = p.name == "x" ? &ix : p.name == "y" ? &iy : p.name == "z" ? &iz : nullptr;
                if (slot && p.is_list) throw io_error(name, e.line, std::string("vertex property '") + p.name + "' is a list");
                if (slot) *slot = static_cast<int>(i);
            }
            if (ix < 0 || iy < 0 || iz < 0) throw io_error(name, e.line, "element 'vertex' lacks x, y or z");
            if (e.count > 0xffffffffULL) throw io_error(name, e.line, "more than 2^32-1 vertices");
        } else if (e.name == "face" && !face) {
            face = &e;
            for (std::size_t i = 0; i < e.props.size(); ++i)
                if (e.props[i].is_list && (e.props[i].name == "vertex_indices" || e.props[i].name == "vertex_index"))
                    iface = static_cast<int>(i);
            if (iface < 0) throw io_error(name, e.line, "element 'face' has no list property 'vertex_indices'");
            if (!ply_integral(e.props[static_cast<std::size_t>(iface)].type))
                throw io_error(name, e.line, "face vertex indices must have an integer type");
        }
    }
    if (!vert) throw io_error(name, 0, "no element 'vertex' in the header");
    if (!face) throw io_error(name, 0, "no element 'face' in the header (a triangle mesh is required)");

    triangle_mesh m;
    m.vertices.reserve(static_cast<std::size_t>(vert->count));  // bounded by the file size (checked above)
    m.faces.reserve(static_cast<std::size_t>(face->count));
    ply_body body(bytes, name, c.offset(), c.line() + 1, ascii, order);
    std::vector<std::int64_t> corners;
    for (const ply_element& e : elements) {
        const bool is_vert = &e == vert, is_face = &e == face;
        if (e.props.empty()) continue;  // holds no data; its count (unbounded by the file size) must not drive a loop
        for (std::uint64_t item = 0; item < e.count; ++item) {
            body.begin_item();
            vec3 p(0.0);
            for (std::size_t k = 0; k < e.props.size(); ++k) {
                const ply_property& prop = e.props[k];
                const int ki = static_cast<int>(k);
                if (!prop.is_list) {
                    const double v = body.real(prop.type, prop.name);  // no per-value string building: messages carry the line/byte
                    if (is_vert && (ki == ix || ki == iy || ki == iz)) {
                        if (!std::isfinite(v)) body.fail(std::string("vertex ") + std::to_string(item) + " has a non-finite coordinate");
                        p[ki == ix ? 0 : ki == iy ? 1 : 2] = v;
                    }
                    continue;
                }
                const std::int64_t n = body.integer(prop.count_type, "list length");
                if (n < 0) body.fail(std::string("negative list length ") + std::to_string(n));
                if (static_cast<std::uint64_t>(n) * (ascii ? 2 : ply_size(prop.type)) > body.remaining() + 1)
                    body.fail(std::string("list of ") + std::to_string(n) + " items runs past the end of the file");
                const bool keep = is_face && ki == iface;
                if (keep) {
                    if (n < 3) body.fail(std::string("face ") + std::to_string(item) + " has " + std::to_string(n) + " corners, expected at least 3");
                    corners.clear();
                }
                for (std::int64_t j = 0; j < n; ++j) {
                    if (!keep) {
                        body.real(prop.type, prop.name);
                        continue;
                    }
                    const std::int64_t idx = body.integer(prop.type, "face vertex index");
                    if (idx < 0 || static_cast<std::uint64_t>(idx) >= vert->count)
                        body.fail(std::string("face ") + std::to_string(item) + " indexes vertex " + std::to_string(idx) + ", but there are " +
                                  std::to_string(vert->count) + " vertices");
                    corners.push_back(idx);
                }
                if (keep)
                    for (std::size_t i = 1; i + 1 < corners.size(); ++i)
                        m.faces.push_back({static_cast<std::uint32_t>(corners[0]), static_cast<std::uint32_t>(corners[i]),
                                           static_cast<std::uint32_t>(corners[i + 1])});
            }
            body.end_item(e.name, item);
            if (is_vert) m.vertices.push_back(p);
        }
    }
    body.expect_end();
    if (m.faces.empty()) throw io_error(name, face->line, "the mesh has no faces");
    return m;
}

/// Reads a PLY file (see file comment).
inline triangle_mesh read_ply(const std::filesystem::path& path) {
    return parse_ply(detail::read_file(path), path.string());
}

/// PLY bytes for a mesh (binary: little-endian float32 coordinates; ASCII: exact doubles).
inline std::string format_ply(const triangle_mesh& m, encoding enc = encoding::binary) {
    const bool bin = enc == encoding::binary;
    std::string out = "ply\nformat ";
    out += bin ? "binary_little_endian" : "ascii";
    out += std::string(" 1.0\ncomment written by fabsynth\nelement vertex ") + std::to_string(m.vertices.size()) + "\n";
    for (const char* a : {"x", "y", "z"}) out += std::string("property ") + (bin ? "float " : "double ") + a + "\n";
    out += std::string("element face ") + std::to_string(m.faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    using detail::byte_order;
    if (bin) {
        out.reserve(out.size() + 12 * m.vertices.size() + 13 * m.faces.size());
        for (const vec3& v : m.vertices)
            for (int a = 0; a < 3; ++a) detail::store(out, static_cast<float>(v[a]), byte_order::little);
        for (const auto& f : m.faces) {
            detail::store(out, std::uint8_t{3}, byte_order::little);
            for (std::uint32_t i : f) detail::store(out, static_cast<std::int32_t>(i), byte_order::little);
        }
        return out;
    }
    for (const vec3& v : m.vertices) {
        for (int a = 0; a < 3; ++a) {
            if (a) out += ' ';
            detail::append_number(out, v[a]);
        }
        out += '\n';
    }
    for (const auto& f : m.faces) {
        out += '3';
        for (std::uint32_t i : f) {
            out += ' ';
            detail::append_number(out, static_cast<std::int64_t>(i));
        }
        out += '\n';
    }
    return out;
}

/// Writes `m` as PLY (binary little-endian float32 by default). Atomic. Throws invalid_input for
/// invalid meshes or (binary) coordinates beyond float range.
inline void write_ply(const std::filesystem::path& path, const triangle_mesh& m, encoding enc = encoding::binary) {
    detail::check_mesh_for_writing(m, path.string());
    if (enc == encoding::binary) detail::check_fits_float(m, path.string(), "binary PLY");
    atomic_write(path, format_ply(m, enc));
}

}  // namespace fabsynth::io
