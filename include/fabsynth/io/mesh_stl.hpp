// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh_stl.hpp  STL triangle meshes, ASCII and binary: read (welded) and write.
///
/// Reading: the encoding is detected from the content, not the first word, because many binary
/// files start with "solid" too. A file is binary when its size is exactly 84 + 50 * (facet count
/// stored at byte 80) (unless it also starts with "solid" and parses completely as ASCII);
/// otherwise it is ASCII if it starts with "solid", and rejected if not.
/// Corners with exactly equal positions are welded into one vertex (numbered in order of first
/// appearance), so a closed STL reads back as a closed indexed mesh. Stored normals are ignored
/// (they must still parse in ASCII files; non-finite ones are tolerated since many exporters
/// write "nan" for degenerate facets). ASCII loops with more than 3 vertices are fan-triangulated.
///
/// Rejected with io_error: empty files, truncated binary data ("byte N"), facet counts the file
/// size cannot hold, non-finite coordinates, unparsable numbers, missing keywords ("FILE:LINE").
///
/// Writing: binary (float32 little-endian, the default) or ASCII (shortest exact decimals, so
/// ASCII round-trips doubles exactly). The binary header never starts with "solid".
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
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
#include "fabsynth/io/detail/weld.hpp"
#include "fabsynth/io/encoding.hpp"

namespace fabsynth::io {

namespace detail {

inline triangle_mesh parse_stl_binary(std::string_view bytes, std::string_view name) {
    const std::uint32_t n = load<std::uint32_t>(bytes.data() + 80, byte_order::little);
    triangle_mesh m;
    m.faces.reserve(n);  // safe: the caller checked 84 + 50 n == file size
    vertex_welder weld(m);
    for (std::size_t f = 0; f < n; ++f) {
        const std::size_t base = 84 + 50 * f;
        std::array<std::uint32_t, 3> tri{};
        for (int k = 0; k < 3; ++k) {
            vec3 p;
            for (int a = 0; a < 3; ++a) {
                const std::size_t at = base + 12 + 12 * static_cast<std::size_t>(k) + 4 * static_cast<std::size_t>(a);
                const float x = load<float>(bytes.data() + at, byte_order::little);
                if (!std::isfinite(x))
                    throw io_error::at_byte(name, at, std::string("facet ") + std::to_string(f) + " has a non-finite coordinate");
                p[a] = static_cast<double>(x);
            }
            if (m.vertices.size() >= 0xffffffffULL) throw io_error::at_byte(name, base, "more than 2^32-1 vertices");
            tri[static_cast<std::size_t>(k)] = weld.add(p);
        }
        m.faces.push_back(tri);
    }
    return m;
}

inline triangle_mesh parse_stl_ascii(std::string_view bytes, std::string_view name) {
    token_cursor c(bytes, name);
    auto expect = [&](std::string_view word) {
        const std::string_view t = c.require(std::string("'") + std::string(word) + "'");
        if (!iequals(t, word)) c.fail(std::string("expected '") + std::string(word) + "', found " + quote(t));
    };
    triangle_mesh m;
    vertex_welder weld(m);
    std::vector<std::uint32_t> loop;
    // Reads facets up to and including "endsolid [name]".
    auto read_solid = [&] {
        c.skip_line();  // the solid's name, possibly empty or with spaces
        for (;;) {
            const std::string_view t = c.require("'facet' or 'endsolid'");
            if (iequals(t, "endsolid")) break;
            if (!iequals(t, "facet")) c.fail(std::string("expected 'facet' or 'endsolid', found ") + quote(t));
            expect("normal");
            for (int a = 0; a < 3; ++a) {
                const std::string_view v = c.require("normal component");
                if (!to_double(v)) c.fail(std::string("cannot parse normal component from ") + quote(v));
            }
            expect("outer");
            expect("loop");
            loop.clear();
            for (;;) {
                const std::string_view w = c.require("'vertex' or 'endloop'");
                if (iequals(w, "endloop")) break;
                if (!iequals(w, "vertex")) c.fail(std::string("expected 'vertex' or 'endloop', found ") + quote(w));
                vec3 p;
                for (int a = 0; a < 3; ++a) p[a] = c.finite(c.require("vertex coordinate"), "vertex coordinate");
                if (m.vertices.size() >= 0xffffffffULL) c.fail("more than 2^32-1 vertices");
                loop.push_back(weld.add(p));
            }
            if (loop.size() < 3) c.fail(std::string("facet has ") + std::to_string(loop.size()) + " vertices, expected 3");
            for (std::size_t i = 1; i + 1 < loop.size(); ++i) m.faces.push_back({loop[0], loop[i], loop[i + 1]});
            expect("endfacet");
        }
        c.skip_line();  // "endsolid" may repeat the name
    };
    expect("solid");
    read_solid();
    // Some files hold several solids one after another; read them all into one mesh.
    for (std::string_view t = c.next(); !t.empty(); t = c.next()) {
        if (!iequals(t, "solid")) c.fail(std::string("unexpected ") + quote(t) + " after 'endsolid'");
        read_solid();
    }
    if (m.faces.empty()) throw io_error(name, 0, "ASCII STL has no facets");
    return m;
}

}  // namespace detail

/// Parses STL bytes (ASCII or binary, detected as described in the file comment).
inline triangle_mesh parse_stl(std::string_view bytes, std::string_view name) {
    if (bytes.empty()) throw io_error(name, 0, "file is empty");
    std::size_t first = 0;
    while (first < bytes.size() && detail::is_space(bytes[first])) ++first;
    const bool says_solid = bytes.size() - first >= 5 && detail::iequals(bytes.substr(first, 5), "solid");
    if (bytes.size() >= 84) {
        const std::uint64_t n = detail::load<std::uint32_t>(bytes.data() + 80, detail::byte_order::little);
        const std::uint64_t need = 84 + 50 * n;
        if (need == bytes.size()) {
            if (n == 0) throw io_error::at_byte(name, 80, "binary STL has no facets");
            // Size fits binary. A file starting with "solid" is still almost surely binary (many
            // exporters write that header), but an ASCII file could match the size by chance:
            // accept it as ASCII only if it parses as ASCII.
            if (says_solid) {
                try {
                    return detail::parse_stl_ascii(bytes, name);
                } catch (const io_error&) {
                }
            }
            return detail::parse_stl_binary(bytes, name);
        }
        if (!says_solid)
            throw io_error::at_byte(name, 80,
                                    std::string("binary STL header says ") + std::to_string(n) + " facets, which need " +
                                        std::to_string(need) + " bytes, but the file has " +
                                        std::to_string(bytes.size()) + (need > bytes.size() ? " (truncated)" : ""));
    } else if (!says_solid) {
        throw io_error::at_byte(name, bytes.size(),
                                std::string("file of ") + std::to_string(bytes.size()) +
                                    " bytes is neither ASCII STL (no 'solid') nor binary STL (needs >= 84 bytes)");
    }
    return detail::parse_stl_ascii(bytes, name);
}

/// Reads an STL file (ASCII or binary); vertices are welded by exact position.
inline triangle_mesh read_stl(const std::filesystem::path& path) {
    return parse_stl(detail::read_file(path), path.string());
}

/// STL bytes for a mesh. Facet normals are the normalised cross products (0 if degenerate).
inline std::string format_stl(const triangle_mesh& m, encoding enc = encoding::binary) {
    auto unit_normal = [&](std::size_t f) {
        const vec3 n = face_normal_area2(m, f);
        const double len = glm::length(n);
        return len > 0 && std::isfinite(len) ? n / len : vec3(0.0);
    };
    std::string out;
    if (enc == encoding::binary) {
        if (m.faces.size() > 0xffffffffULL) throw invalid_input("mesh has too many faces for binary STL");
        out.reserve(84 + 50 * m.faces.size());
        std::string header = "fabsynth binary STL";  // must not start with "solid"
        header.resize(80, ' ');
        out += header;
        detail::store(out, static_cast<std::uint32_t>(m.faces.size()), detail::byte_order::little);
        for (std::size_t f = 0; f < m.faces.size(); ++f) {
            const vec3 n = unit_normal(f);
            for (int a = 0; a < 3; ++a) detail::store(out, static_cast<float>(n[a]), detail::byte_order::little);
            for (std::uint32_t v : m.faces[f])
                for (int a = 0; a < 3; ++a)
                    detail::store(out, static_cast<float>(m.vertices[v][a]), detail::byte_order::little);
            detail::store(out, std::uint16_t{0}, detail::byte_order::little);
        }
        return out;
    }
    out = "solid fabsynth\n";
    auto xyz = [&](const vec3& p) {
        for (int a = 0; a < 3; ++a) {
            out += ' ';
            detail::append_number(out, p[a]);
        }
        out += '\n';
    };
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        out += "  facet normal";
        xyz(unit_normal(f));
        out += "    outer loop\n";
        for (std::uint32_t v : m.faces[f]) {
            out += "      vertex";
            xyz(m.vertices[v]);
        }
        out += "    endloop\n  endfacet\n";
    }
    out += "endsolid fabsynth\n";
    return out;
}

/// Writes `m` as STL (binary float32 by default; ASCII prints exact doubles). Atomic.
/// Binary output rounds coordinates to float; coordinates beyond float range become inf, so
/// they are refused with invalid_input. Throws invalid_input for invalid meshes.
inline void write_stl(const std::filesystem::path& path, const triangle_mesh& m, encoding enc = encoding::binary) {
    detail::check_mesh_for_writing(m, path.string());
    if (enc == encoding::binary) detail::check_fits_float(m, path.string(), "binary STL");
    atomic_write(path, format_stl(m, enc));
}

}  // namespace fabsynth::io
