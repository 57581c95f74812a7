// SPDX-License-Identifier: MIT
#pragma once
/// @file svg_xml.hpp  Internal: a small non-validating XML tokenizer for the SVG reader, plus the
/// error-location helper shared by the SVG internals. Not part of the public API.
///
/// Written by hand because none of the allowed dependencies parses XML, and SVG needs only this
/// much: elements, attributes (quoted values, the 5 predefined entities and character
/// references), comments, CDATA, processing instructions and a skipped DOCTYPE. Text content is
/// ignored. Every malformation throws io_error "FILE:LINE:COLUMN: what" (column counted in bytes).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/core/error.hpp"

namespace fabsynth::io::detail::svg {

/// The text being parsed and its display name; turns byte offsets into line:column errors.
struct source {
    std::string_view text;
    std::string_view name;

    [[noreturn]] void fail(std::size_t offset, std::string_view what) const {
        if (offset > text.size()) offset = text.size();
        std::size_t line = 1, col = 1;
        for (std::size_t i = 0; i < offset; ++i) {
            if (text[i] == '\n') ++line, col = 1;
            else ++col;
        }
        throw io_error(std::string(name) + ":" + std::to_string(line) + ":" + std::to_string(col) + ": " +
                       std::string(what));
    }
};

/// One attribute: name, raw (undecoded) value and the byte offset of the value in the text.
struct xml_attribute {
    std::string_view name;
    std::string_view raw;
    std::size_t offset = 0;
};

[[nodiscard]] constexpr bool is_xml_space(char c) noexcept { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

[[nodiscard]] constexpr bool is_name_start(char c) noexcept {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == ':' ||
           static_cast<unsigned char>(c) >= 0x80;
}
[[nodiscard]] constexpr bool is_name_char(char c) noexcept {
    return is_name_start(c) || (c >= '0' && c <= '9') || c == '-' || c == '.';
}

/// Appends code point cp as UTF-8.
inline void append_utf8(std::string& out, std::uint32_t cp) {
    if (cp < 0x80) {
        out += static_cast<char>(cp);
    } else if (cp < 0x800) {
        out += static_cast<char>(0xC0 | (cp >> 6));
        out += static_cast<char>(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
        out += static_cast<char>(0xE0 | (cp >> 12));
        out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (cp & 0x3F));
    } else {
        out += static_cast<char>(0xF0 | (cp >> 18));
        out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
        out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (cp & 0x3F));
    }
}

/// Decodes entity and character references of an attribute value found at `offset`.
[[nodiscard]] inline std::string decode_attribute(const source& src, const xml_attribute& a) {
    std::string out;
    out.reserve(a.raw.size());
    for (std::size_t i = 0; i < a.raw.size();) {
        if (a.raw[i] != '&') {
            out += a.raw[i++];
            continue;
        }
        const std::size_t semi = a.raw.find(';', i);
        if (semi == std::string_view::npos || semi - i > 12)
            src.fail(a.offset + i, "'&' in attribute value does not start a reference (write &amp;)");
        const std::string_view ent = a.raw.substr(i + 1, semi - i - 1);
        if (ent == "lt") out += '<';
        else if (ent == "gt") out += '>';
        else if (ent == "amp") out += '&';
        else if (ent == "quot") out += '"';
        else if (ent == "apos") out += '\'';
        else if (ent.size() >= 2 && ent[0] == '#') {
            const bool hex = ent[1] == 'x';
            const std::string_view digits = ent.substr(hex ? 2 : 1);
            std::uint32_t cp = 0;
            bool ok = !digits.empty();
            for (char c : digits) {
                int d = -1;
                if (c >= '0' && c <= '9') d = c - '0';
                else if (hex && c >= 'a' && c <= 'f') d = c - 'a' + 10;
                else if (hex && c >= 'A' && c <= 'F') d = c - 'A' + 10;
                if (d < 0 || cp > 0x10FFFF) { ok = false; break; }
                cp = cp * (hex ? 16u : 10u) + static_cast<std::uint32_t>(d);
            }
            if (!ok || cp == 0 || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))
                src.fail(a.offset + i, "invalid character reference &" + std::string(ent) + ";");
            append_utf8(out, cp);
        } else {
            src.fail(a.offset + i, "unknown entity &" + std::string(ent) + "; (only the 5 XML entities are supported)");
        }
        i = semi + 1;
    }
    return out;
}

/// Maximum element nesting depth accepted (bounds the reader's stacks on hostile input).
inline constexpr std::size_t max_xml_depth = 1024;

/// Maximum number of attributes on one element (bounds the duplicate-attribute check).
inline constexpr std::size_t max_xml_attributes = 1024;

/// Tokenizes `src.text` and calls, in document order,
///   h.start(name, attributes, offset)   for every start or empty-element tag, then
///   h.end()                             for every end tag (also right after an empty-element tag).
/// Checks well-formedness of tags, nesting, a single root element, no text outside the root.
template <class Handler>
void parse_xml(const source& src, Handler& h) {
    const std::string_view t = src.text;
    const std::size_t n = t.size();
    std::size_t pos = 0;
    if (t.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;  // UTF-8 byte order mark
    struct open_tag { std::string_view name; std::size_t offset; };
    std::vector<open_tag> stack;
    std::vector<xml_attribute> attrs;
    bool root_seen = false;

    auto skip_space = [&] { while (pos < n && is_xml_space(t[pos])) ++pos; };
    auto skip_past = [&](std::string_view end, std::size_t start, std::string_view what) {
        const std::size_t e = t.find(end, pos);
        if (e == std::string_view::npos) src.fail(start, "unterminated " + std::string(what));
        pos = e + end.size();
    };
    auto read_name = [&](std::string_view what) {
        if (pos >= n || !is_name_start(t[pos])) src.fail(pos, "expected " + std::string(what));
        const std::size_t b = pos;
        while (pos < n && is_name_char(t[pos])) ++pos;
        return t.substr(b, pos - b);
    };

    while (pos < n) {
        if (t[pos] != '<') {
            const std::size_t b = pos;
            const std::size_t e = t.find('<', pos);
            pos = e == std::string_view::npos ? n : e;
            if (stack.empty())
                for (std::size_t i = b; i < pos; ++i)
                    if (!is_xml_space(t[i])) src.fail(i, "text outside the root element");
            continue;
        }
        const std::size_t start = pos;
        const std::string_view rest = t.substr(pos);
        if (rest.starts_with("<!--")) {
            pos += 4;
            skip_past("-->", start, "comment '<!--'");
        } else if (rest.starts_with("<![CDATA[")) {
            if (stack.empty()) src.fail(start, "CDATA section outside the root element");
            pos += 9;
            skip_past("]]>", start, "CDATA section");
        } else if (rest.starts_with("<?")) {
            pos += 2;
            skip_past("?>", start, "processing instruction '<?'");
        } else if (rest.starts_with("<!")) {
            // DOCTYPE (possibly with an internal subset in [...]): skipped, entities not expanded.
            if (root_seen || !stack.empty()) src.fail(start, "'<!' declaration inside the document");
            pos += 2;
            int bracket = 0;
            char quote = 0;
            for (;; ++pos) {
                if (pos >= n) src.fail(start, "unterminated '<!' declaration");
                const char c = t[pos];
                if (quote) { if (c == quote) quote = 0; }
                else if (c == '"' || c == '\'') quote = c;
                else if (c == '[') ++bracket;
                else if (c == ']') --bracket;
                else if (c == '>' && bracket <= 0) { ++pos; break; }
            }
        } else if (rest.starts_with("</")) {
            pos += 2;
            const std::string_view name = read_name("an element name after '</'");
            skip_space();
            if (pos >= n || t[pos] != '>') src.fail(start, "unterminated end tag </" + std::string(name));
            ++pos;
            if (stack.empty()) src.fail(start, "end tag </" + std::string(name) + "> without a start tag");
            if (stack.back().name != name)
                src.fail(start, "end tag </" + std::string(name) + "> does not match <" + std::string(stack.back().name) + ">");
            stack.pop_back();
            h.end();
        } else {
            ++pos;
            const std::string_view name = read_name("an element name after '<'");
            if (stack.empty() && root_seen) src.fail(start, "second root element <" + std::string(name) + ">");
            attrs.clear();
            bool empty_element = false;
            for (;;) {
                const std::size_t before = pos;
                skip_space();
                if (pos >= n) src.fail(start, "unterminated tag <" + std::string(name) + ">");
                if (t[pos] == '>') { ++pos; break; }
                if (t[pos] == '/') {
                    if (pos + 1 >= n || t[pos + 1] != '>') src.fail(pos, "expected '/>'");
                    pos += 2;
                    empty_element = true;
                    break;
                }
                if (before == pos) src.fail(pos, "expected whitespace before attribute in <" + std::string(name) + ">");
                const std::string_view aname = read_name("an attribute name or '>'");
                skip_space();
                if (pos >= n || t[pos] != '=') src.fail(pos, "expected '=' after attribute " + std::string(aname));
                ++pos;
                skip_space();
                if (pos >= n || (t[pos] != '"' && t[pos] != '\'')) src.fail(pos, "expected a quoted value for attribute " + std::string(aname));
                const char q = t[pos++];
                const std::size_t vb = pos;
                while (pos < n && t[pos] != q) {
                    if (t[pos] == '<') src.fail(pos, "'<' in the value of attribute " + std::string(aname) + " (unterminated quote?)");
                    ++pos;
                }
                if (pos >= n) src.fail(vb - 1, "unterminated value of attribute " + std::string(aname));
                if (attrs.size() >= max_xml_attributes)
                    src.fail(start, "more than " + std::to_string(max_xml_attributes) + " attributes in <" + std::string(name) + ">");
                for (const xml_attribute& a : attrs)  // quadratic, but bounded by max_xml_attributes
                    if (a.name == aname) src.fail(vb, "duplicate attribute " + std::string(aname));
                attrs.push_back({aname, t.substr(vb, pos - vb), vb});
                ++pos;
            }
            if (stack.size() >= max_xml_depth) src.fail(start, "elements nested deeper than " + std::to_string(max_xml_depth));
            root_seen = true;
            h.start(name, attrs, start);
            if (empty_element) h.end();
            else stack.push_back({name, start});
        }
    }
    if (!stack.empty())
        src.fail(stack.back().offset, "element <" + std::string(stack.back().name) + "> is not closed before the end of the file");
    if (!root_seen) src.fail(pos, "no root element (empty or comment-only file)");
}

}  // namespace fabsynth::io::detail::svg
