// SPDX-License-Identifier: MIT
#pragma once
/// @file svg.hpp  Reading SVG drawings as flattened polylines, and writing them back.
///
/// Usage:
///   fabsynth::io::svg_document doc = fabsynth::io::read_svg("band.svg", {.tolerance = 0.01});
///   for (const auto& s : doc.shapes)
///       for (std::size_t i = 0; i < s.subpaths.size(); ++i) use(s.subpaths[i], s.closed[i]);
///   fabsynth::io::write_svg("out.svg", doc);   // read_svg("out.svg") == doc, exactly (coordinates
///                                             // beyond 1e9 need svg_read_options::max_coordinate)
///
/// What is read:
///  - shapes `path` (M L H V C S Q T A Z, absolute and relative), `polygon`, `polyline`, `rect`
///    (with rx/ry rounded corners), `circle`, `ellipse`, `line`; one svg_shape per element;
///  - containers `svg` (root, and nested ones as a group translated by x, y; a nested viewBox
///    is ignored), `g`, `a`, `switch` (all children drawn);
///  - `transform` on any element (matrix, translate, scale, rotate(a [cx cy]), skewX, skewY,
///    lists of these), composed down the tree;
///  - `fill`, `stroke`, `stroke-width`, `fill-rule`, as attributes or in `style="..."` (style
///    wins), inherited from groups (`inherit` allowed); `display="none"` hides a subtree; `id`;
///  - the root's `width`, `height` (number + unit kept) and `viewBox`.
/// Every other element (`defs`, `symbol`, `use`, `text`, `style`, `script`, `image`, `title`,
/// `desc`, `metadata`, `clipPath`, `mask`, `pattern`, gradients, `foreignObject`, elements of
/// other namespaces, prefixed names such as `svg:path`...) is skipped with its whole subtree:
/// it is not drawn, or not drawn by this reader (`use` references are not resolved). CSS style
/// sheets, `preserveAspectRatio`, opacity, clipping and markers are ignored. stroke-width in
/// em, ex or % is taken as user units.
///
/// Coordinates are in the root's user units (viewBox units) after applying every transform; the
/// viewBox-to-viewport mapping is not applied. Curves are flattened so that no point of the true
/// curve is farther than `tolerance` from the polyline (measured after transforms). Closed
/// subpaths (Z, polygon, rect, circle, ellipse) are stored without repeating the first point;
/// subpaths with fewer than 2 points after that are dropped (they draw nothing), so an empty
/// `d`, a zero-size rect or a zero radius gives a shape without subpaths. stroke_width is
/// scaled by sqrt|det| of the element's transform (exact for similarity transforms).
///
/// Errors: io_error "fabsynth: FILE:LINE:COLUMN: what" for malformed XML (unterminated tags,
/// comments or quotes, mismatched end tags), a root that is not <svg>, empty files, unparsable
/// numbers ("1e", "NaN", "inf", out-of-range values), path data not starting with M, unknown
/// path commands or transforms, wrong argument counts, a missing required attribute (path d,
/// polygon/polyline points, rect width/height, circle r, ellipse rx/ry), negative sizes,
/// relative units (%, em, ex) in geometry attributes, more than `max_points` points after
/// flattening, or coordinates overflowing after transforms. invalid_input for a bad tolerance.
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/io/atomic_file.hpp"
#include "fabsynth/io/detail/read_file.hpp"
#include "fabsynth/io/detail/svg_path.hpp"
#include "fabsynth/io/detail/svg_scan.hpp"
#include "fabsynth/io/detail/svg_xml.hpp"

namespace fabsynth::io {

/// One drawn element, flattened. subpaths[i] is a polyline in root user units; closed[i] tells
/// whether it is a closed ring (then its first point is not repeated at the end).
struct svg_shape {
    std::vector<std::vector<vec2>> subpaths;
    std::vector<bool> closed;               ///< same size as subpaths
    fill_rule rule = fill_rule::nonzero;   ///< the SVG `fill-rule`
    std::string fill = "black";            ///< paint as written ("none", "#000000", "red", "url(#g)"...)
    std::string stroke = "none";           ///< paint as written
    double stroke_width = 1.0;             ///< root user units
    std::string id;                        ///< the element's id ("" if none)

    /// True unless fill is "none".
    [[nodiscard]] bool filled() const { return fill != "none"; }
    /// True if stroke is not "none" and stroke_width > 0.
    [[nodiscard]] bool stroked() const { return stroke != "none" && stroke_width > 0.0; }
    /// The subpaths as rings for filling (SVG fills open subpaths as if closed); subpaths with
    /// fewer than 3 points are left out.
    [[nodiscard]] std::vector<ring2> rings() const {
        std::vector<ring2> r;
        for (const auto& s : subpaths)
            if (s.size() >= 3) r.push_back(s);
        return r;
    }
    friend bool operator==(const svg_shape&, const svg_shape&) = default;
};

/// A filled shape (fill "#000000", no stroke, even-odd) whose subpaths are the polygons' outer
/// rings each followed by its holes, all closed: the layout of data/vector/ files.
[[nodiscard]] inline svg_shape shape_from_polygons(const std::vector<polygon_with_holes>& polys) {
    svg_shape s;
    s.fill = "#000000";
    s.rule = fill_rule::evenodd;
    for (const polygon_with_holes& p : polys) {
        s.subpaths.push_back(p.outer);
        for (const ring2& h : p.holes) s.subpaths.push_back(h);
    }
    s.closed.assign(s.subpaths.size(), true);
    return s;
}

/// A stroked shape (fill "none", stroke "#000000") of open polylines, as in data/filigree/.
/// stroke_width in user units (>= 0; invalid_input otherwise).
[[nodiscard]] inline svg_shape shape_from_polylines(const std::vector<std::vector<vec2>>& lines, double stroke_width = 1.0) {
    if (!(stroke_width >= 0.0) || !std::isfinite(stroke_width))
        throw invalid_input("shape_from_polylines: stroke_width must be finite and >= 0");
    svg_shape s;
    s.fill = "none";
    s.stroke = "#000000";
    s.stroke_width = stroke_width;
    s.subpaths = lines;
    s.closed.assign(lines.size(), false);
    return s;
}

/// The root's viewBox="min_x min_y width height" (user units).
struct svg_view_box {
    double min_x = 0, min_y = 0, width = 0, height = 0;
    [[nodiscard]] box2 box() const { return box2({min_x, min_y}, {min_x + width, min_y + height}); }
    friend bool operator==(const svg_view_box&, const svg_view_box&) = default;
};

/// A drawing: the root's size attributes and every drawn shape in document order.
struct svg_document {
    double width = 0;                     ///< root `width` number (0 = attribute absent)
    double height = 0;                    ///< root `height` number (0 = attribute absent)
    std::string width_unit, height_unit;  ///< "" (user units), "px", "mm", "cm", "in", "pt", "pc", "em", "ex" or "%"
    std::optional<svg_view_box> view_box;
    std::vector<svg_shape> shapes;

    /// Bounding box of every point of every shape (empty box if there are none).
    [[nodiscard]] box2 bounds() const {
        box2 b;
        for (const auto& s : shapes)
            for (const auto& sp : s.subpaths)
                for (const vec2& p : sp) b.extend(p);
        return b;
    }
    friend bool operator==(const svg_document&, const svg_document&) = default;
};

/// A drawing in mm of `view` (its viewBox and width/height) holding `polys` as one filled shape
/// (shape_from_polygons): what the pattern tools write as OUT.svg.
[[nodiscard]] inline svg_document document_of(const std::vector<polygon_with_holes>& polys, const box2& view) {
    svg_document doc;
    doc.width = view.size().x, doc.height = view.size().y;
    doc.width_unit = doc.height_unit = "mm";
    doc.view_box = svg_view_box{view.lo.x, view.lo.y, view.size().x, view.size().y};
    doc.shapes.push_back(shape_from_polygons(polys));
    return doc;
}

/// Reader options.
struct svg_read_options {
    double tolerance = 0.01;                  ///< max curve-to-polyline distance, root user units (> 0)
    std::size_t max_points = 50'000'000;      ///< limit on points in the whole document (bounds memory)
    /// Largest |x| and |y| of a point after transforms (root user units; 1e9 is 1000 km in mm): a
    /// larger one is refused naming the element's line, before squares and grids downstream
    /// overflow or lose every digit. Infinity accepts every finite coordinate.
    double max_coordinate = 1e9;
};

namespace detail::svg {

/// Absolute length units in px (CSS: 96 px per inch). Returns 0 for units that are not absolute.
[[nodiscard]] inline double unit_scale(std::string_view u) noexcept {
    if (u.empty() || u == "px") return 1.0;
    if (u == "in") return 96.0;
    if (u == "cm") return 96.0 / 2.54;
    if (u == "mm") return 96.0 / 25.4;
    if (u == "pt") return 96.0 / 72.0;
    if (u == "pc") return 16.0;
    return 0.0;
}
[[nodiscard]] inline bool known_unit(std::string_view u) noexcept {
    return unit_scale(u) > 0.0 || u == "em" || u == "ex" || u == "%";
}

/// Parses "number unit?" with surrounding whitespace; returns the number, unit in `unit`.
inline double parse_length(scanner& sc, std::string_view& unit) {
    sc.skip_wsp();
    if (!sc.at_number()) sc.fail("expected a number");
    const double v = sc.number();
    const std::size_t u0 = sc.pos;
    while (!sc.at_end() && ((sc.peek() >= 'a' && sc.peek() <= 'z') || (sc.peek() >= 'A' && sc.peek() <= 'Z') || sc.peek() == '%'))
        ++sc.pos;
    unit = sc.s.substr(u0, sc.pos - u0);
    if (!known_unit(unit)) {
        sc.pos = u0;
        sc.fail("unknown unit '" + std::string(unit) + "'");
    }
    sc.skip_wsp();
    if (!sc.at_end()) sc.fail("unexpected text after the length");
    return v;
}

[[nodiscard]] inline std::string_view trim(std::string_view s) noexcept {
    while (!s.empty() && (is_xml_space(s.front()) || s.front() == '\f')) s.remove_prefix(1);
    while (!s.empty() && (is_xml_space(s.back()) || s.back() == '\f')) s.remove_suffix(1);
    return s;
}

struct style {
    std::string fill = "black", stroke = "none";
    double stroke_width = 1.0;  // in the element's local units
    fill_rule rule = fill_rule::nonzero;
};

/// Builds an svg_document from XML events (the handler of parse_xml).
class reader {
public:
    svg_document doc;

    reader(const source& src, const svg_read_options& opt) : src_(src), opt_(opt), budget_(opt.max_points) {}

    void start(std::string_view name, const std::vector<xml_attribute>& attrs, std::size_t offset) {
        attrs_ = &attrs;
        if (frames_.empty()) {
            if (name != "svg") src_.fail(offset, "root element is <" + std::string(name) + ">, not <svg>");
            read_root();
        }
        const frame parent = frames_.empty() ? frame{} : frames_.back();
        if (parent.skip) return frames_.push_back({{}, {}, true});
        const bool container = name == "svg" || name == "g" || name == "a" || name == "switch";
        const bool shape = name == "path" || name == "polygon" || name == "polyline" || name == "rect" ||
                           name == "circle" || name == "ellipse" || name == "line";
        if (!container && !shape) return frames_.push_back({{}, {}, true});
        frame f = parent;
        bool hidden = false;
        apply_style(f.st, hidden);
        if (hidden) return frames_.push_back({{}, {}, true});
        if (name == "svg" && frames_.size() > 0) f.ctm = f.ctm * affine2{1, 0, 0, 1, coord("x"), coord("y")};
        if (const xml_attribute* t = find("transform")) {
            const std::string v = decode_attribute(src_, *t);
            scanner sc{&src_, v, t->offset, 0, "transform"};
            f.ctm = f.ctm * parse_transform(sc);
        }
        if (shape) {
            read_shape(name, f, offset);
            f.skip = true;  // children of shapes are not drawn
        }
        frames_.push_back(std::move(f));
    }
    void end() { frames_.pop_back(); }

private:
    struct frame {
        affine2 ctm;
        style st;
        bool skip = false;
    };
    const source& src_;
    svg_read_options opt_;
    std::size_t budget_;
    std::vector<frame> frames_;
    const std::vector<xml_attribute>* attrs_ = nullptr;

    [[nodiscard]] const xml_attribute* find(std::string_view n) const {
        for (const xml_attribute& a : *attrs_)
            if (a.name == n) return &a;
        return nullptr;
    }
    // A coordinate or size attribute in user units; `fallback` when absent.
    double coord(std::string_view n, double fallback = 0.0, bool required = false, std::size_t elem = 0,
                 std::string_view elem_name = {}) {
        const xml_attribute* a = find(n);
        if (!a) {
            if (required)
                src_.fail(elem, "<" + std::string(elem_name) + "> is missing the required attribute " + std::string(n));
            return fallback;
        }
        const std::string v = decode_attribute(src_, *a);
        scanner sc{&src_, v, a->offset, 0, n};
        std::string_view unit;
        const double x = parse_length(sc, unit);
        const double s = unit_scale(unit);
        if (s == 0.0) {
            sc.pos = 0;
            sc.fail("relative unit '" + std::string(unit) + "' is not supported here");
        }
        const double r = x * s;
        if (!std::isfinite(r)) sc.fail("value overflows the double range");
        return r;
    }
    double nonnegative(std::string_view n, double fallback, bool required, std::size_t elem, std::string_view elem_name) {
        const double v = coord(n, fallback, required, elem, elem_name);
        if (v < 0.0) {
            const xml_attribute* a = find(n);
            src_.fail(a ? a->offset : elem, std::string(n) + " must not be negative");
        }
        return v;
    }

    void read_root() {
        auto size = [&](std::string_view n, double& value, std::string& unit) {
            const xml_attribute* a = find(n);
            if (!a) return;
            const std::string v = decode_attribute(src_, *a);
            if (trim(v) == "auto") return;
            scanner sc{&src_, v, a->offset, 0, n};
            std::string_view u;
            value = parse_length(sc, u);
            unit = std::string(u);
            if (value < 0.0) src_.fail(a->offset, std::string(n) + " must not be negative");
        };
        size("width", doc.width, doc.width_unit);
        size("height", doc.height, doc.height_unit);
        if (const xml_attribute* a = find("viewBox")) {
            const std::string v = decode_attribute(src_, *a);
            scanner sc{&src_, v, a->offset, 0, "viewBox"};
            svg_view_box vb;
            sc.skip_wsp();
            if (!sc.at_number()) sc.fail("expected 4 numbers");
            vb.min_x = sc.number();
            vb.min_y = sc.next_number("expected 4 numbers");
            vb.width = sc.next_number("expected 4 numbers");
            vb.height = sc.next_number("expected 4 numbers");
            sc.skip_wsp();
            if (!sc.at_end()) sc.fail("expected exactly 4 numbers");
            if (vb.width < 0 || vb.height < 0) src_.fail(a->offset, "viewBox width and height must not be negative");
            doc.view_box = vb;
        }
    }

    void set_property(style& st, std::string_view prop, std::string_view value, std::size_t at, bool& hidden) {
        value = trim(value);
        if (value.empty()) return;
        const bool inherit = value == "inherit";
        if (prop == "fill") {
            if (!inherit) st.fill = std::string(value);
        } else if (prop == "stroke") {
            if (!inherit) st.stroke = std::string(value);
        } else if (prop == "fill-rule") {
            if (value == "nonzero") st.rule = fill_rule::nonzero;
            else if (value == "evenodd") st.rule = fill_rule::evenodd;
            else if (!inherit) src_.fail(at, "fill-rule must be nonzero, evenodd or inherit, got '" + std::string(value) + "'");
        } else if (prop == "stroke-width") {
            if (inherit) return;
            scanner sc{&src_, value, at, 0, "stroke-width"};
            std::string_view unit;
            const double w = parse_length(sc, unit);
            const double s = unit_scale(unit);  // relative units: taken as user units
            const double ws = w * (s > 0.0 ? s : 1.0);
            if (!(ws >= 0.0) || !std::isfinite(ws)) src_.fail(at, "stroke-width must be a finite number >= 0");
            st.stroke_width = ws;
        } else if (prop == "display") {
            if (value == "none") hidden = true;
        }
    }

    void apply_style(style& st, bool& hidden) {
        for (std::string_view p : {"fill", "stroke", "fill-rule", "stroke-width", "display"})
            if (const xml_attribute* a = find(p)) set_property(st, p, decode_attribute(src_, *a), a->offset, hidden);
        const xml_attribute* a = find("style");
        if (!a) return;
        const std::string v = decode_attribute(src_, *a);
        std::size_t i = 0;
        while (i < v.size()) {
            std::size_t semi = v.find(';', i);
            if (semi == std::string::npos) semi = v.size();
            const std::string_view decl(v.data() + i, semi - i);
            const std::size_t colon = decl.find(':');
            if (colon != std::string_view::npos) {
                const std::string_view prop = trim(decl.substr(0, colon));
                std::string_view value = trim(decl.substr(colon + 1));
                if (value.ends_with("!important")) value = trim(value.substr(0, value.size() - 10));
                set_property(st, prop, value, a->offset + i + colon + 1, hidden);
            }
            i = semi + 1;
        }
    }

    void read_shape(std::string_view name, const frame& f, std::size_t offset) {
        flattener fl(src_, f.ctm, opt_.tolerance, budget_, opt_.max_points);
        fl.at = offset;
        auto parse_attr = [&](std::string_view attr, auto&& body) {
            const xml_attribute* a = find(attr);
            if (!a) src_.fail(offset, "<" + std::string(name) + "> is missing the required attribute " + std::string(attr));
            const std::string v = decode_attribute(src_, *a);
            scanner sc{&src_, v, a->offset, 0, attr};
            body(sc);
        };
        if (name == "path") {
            parse_attr("d", [&](scanner& sc) { parse_path_data(sc, fl); });
        } else if (name == "polygon" || name == "polyline") {
            parse_attr("points", [&](scanner& sc) { parse_points(sc, fl, name == "polygon"); });
        } else if (name == "line") {
            fl.move_to({coord("x1"), coord("y1")});
            fl.line_to({coord("x2"), coord("y2")});
            fl.finish();
        } else if (name == "circle") {
            const double r = nonnegative("r", 0, true, offset, name);
            const vec2 c{coord("cx"), coord("cy")};
            if (r > 0.0) fl.ellipse(c, r, r);
        } else if (name == "ellipse") {
            const double rx = nonnegative("rx", 0, true, offset, name), ry = nonnegative("ry", 0, true, offset, name);
            const vec2 c{coord("cx"), coord("cy")};
            if (rx > 0.0 && ry > 0.0) fl.ellipse(c, rx, ry);
        } else {  // rect
            const double w = nonnegative("width", 0, true, offset, name), h = nonnegative("height", 0, true, offset, name);
            const double x = coord("x"), y = coord("y");
            // SVG 1.1 10.2: a missing rx or ry takes the other's value; both clamp to half the size.
            const bool has_rx = find("rx") != nullptr, has_ry = find("ry") != nullptr;
            double rx = nonnegative("rx", 0, false, offset, name), ry = nonnegative("ry", 0, false, offset, name);
            if (!has_rx) rx = ry;
            if (!has_ry) ry = rx;
            rx = std::min(rx, 0.5 * w);
            ry = std::min(ry, 0.5 * h);
            if (w > 0.0 && h > 0.0) {
                if (rx > 0.0 && ry > 0.0) {
                    auto line_to = [&](vec2 p) { if (p != fl.current()) fl.line_to(p); };
                    fl.move_to({x + rx, y});
                    line_to({x + w - rx, y});
                    fl.arc_to(rx, ry, 0, false, true, {x + w, y + ry});
                    line_to({x + w, y + h - ry});
                    fl.arc_to(rx, ry, 0, false, true, {x + w - rx, y + h});
                    line_to({x + rx, y + h});
                    fl.arc_to(rx, ry, 0, false, true, {x, y + h - ry});
                    line_to({x, y + ry});
                    fl.arc_to(rx, ry, 0, false, true, {x + rx, y});
                } else {
                    fl.move_to({x, y});
                    fl.line_to({x + w, y});
                    fl.line_to({x + w, y + h});
                    fl.line_to({x, y + h});
                }
                fl.close();
            }
        }
        // svg_read_options::max_coordinate, checked here where the element is known
        for (const auto& sp : fl.subpaths)
            for (const vec2& p : sp)
                if (!(std::abs(p.x) <= opt_.max_coordinate && std::abs(p.y) <= opt_.max_coordinate)) {
                    char msg[160];
                    std::snprintf(msg, sizeof msg, "<%.*s> has a coordinate (%.3g, %.3g) out of range (|x|, |y| <= %.3g after transforms)",
                                  static_cast<int>(name.size()), name.data(), p.x, p.y, opt_.max_coordinate);
                    src_.fail(offset, msg);
                }
        svg_shape s;
        s.subpaths = std::move(fl.subpaths);
        s.closed = std::move(fl.closed);
        s.rule = f.st.rule;
        s.fill = f.st.fill;
        s.stroke = f.st.stroke;
        s.stroke_width = f.ctm.is_identity() ? f.st.stroke_width : f.st.stroke_width * std::sqrt(std::abs(f.ctm.det()));
        if (!std::isfinite(s.stroke_width)) src_.fail(offset, "stroke-width overflows the double range after transforms");
        if (const xml_attribute* a = find("id")) s.id = decode_attribute(src_, *a);
        doc.shapes.push_back(std::move(s));
    }
};

/// Shortest decimal text that reads back to exactly x (std::to_chars round-trip guarantee).
inline void append_number(std::string& out, double x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, r.ptr);
}

/// Appends s with the XML special characters escaped for an attribute value.
inline void append_escaped(std::string& out, std::string_view s) {
    for (char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default: out += c;
        }
    }
}

}  // namespace detail::svg

/// Parses SVG text. `name` is used in error messages (e.g. the file name).
/// Throws io_error naming name:line:column (see the file comment), invalid_input if
/// opt.tolerance is not finite and > 0 or opt.max_points is 0.
[[nodiscard]] inline svg_document parse_svg(std::string_view text, std::string_view name, const svg_read_options& opt) {
    require_positive(opt.tolerance, "parse_svg: tolerance");
    if (opt.max_points == 0) throw invalid_input("parse_svg: max_points must be > 0");
    const detail::svg::source src{text, name};
    if (detail::svg::trim(text).empty()) src.fail(0, "empty file");
    detail::svg::reader r(src, opt);
    detail::svg::parse_xml(src, r);
    return std::move(r.doc);
}

/// Parses SVG text with the given flattening tolerance (root user units).
[[nodiscard]] inline svg_document parse_svg(std::string_view text, std::string_view name, double tolerance = 0.01) {
    return parse_svg(text, name, svg_read_options{.tolerance = tolerance});
}

/// Reads and parses an SVG file. Throws io_error if it cannot be read or is malformed.
[[nodiscard]] inline svg_document read_svg(const std::filesystem::path& path, const svg_read_options& opt) {
    return parse_svg(detail::read_file(path), path.string(), opt);
}

/// Reads and parses an SVG file with the given flattening tolerance (root user units).
[[nodiscard]] inline svg_document read_svg(const std::filesystem::path& path, double tolerance = 0.01) {
    return read_svg(path, svg_read_options{.tolerance = tolerance});
}

/// SVG text of the document: one <path> per shape with M/L/Z commands only, every number in
/// the shortest form that reads back exactly, so parse_svg(to_svg_string(d)) == d for any
/// document whose subpaths have >= 2 points and whose closed rings do not repeat their first
/// point. Throws invalid_input if a number is not finite, a size is negative, a unit is
/// unknown, closed.size() != subpaths.size(), or a string holds a character XML cannot carry.
[[nodiscard]] inline std::string to_svg_string(const svg_document& doc) {
    using detail::svg::append_escaped;
    using detail::svg::append_number;
    // Messages are built only on failure (this runs once per point).
    auto check = [](bool ok, auto&& what) {
        if (!ok) throw invalid_input("to_svg_string: " + what());
    };
    auto check_text = [&](std::string_view s, const std::string& what) {
        for (char c : s)
            check(static_cast<unsigned char>(c) >= 0x20 || c == '\t' || c == '\n' || c == '\r',
                  [&] { return what + " contains a control character"; });
    };
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\"";
    auto size = [&](const char* n, double v, const std::string& unit) {
        check(std::isfinite(v) && v >= 0.0, [&] { return std::string(n) + " must be finite and >= 0"; });
        check(detail::svg::known_unit(unit), [&] { return std::string(n) + " unit '" + unit + "' is unknown"; });
        if (v == 0.0 && unit.empty()) return;  // absent
        out.append(" ").append(n).append("=\"");
        append_number(out, v);
        out.append(unit).append("\"");
    };
    size("width", doc.width, doc.width_unit);
    size("height", doc.height, doc.height_unit);
    if (doc.view_box) {
        const svg_view_box& v = *doc.view_box;
        check(std::isfinite(v.min_x) && std::isfinite(v.min_y) && std::isfinite(v.width) && std::isfinite(v.height) &&
                  v.width >= 0 && v.height >= 0,
              [] { return std::string("viewBox must be finite with width, height >= 0"); });
        out += " viewBox=\"";
        append_number(out, v.min_x), out += ' ', append_number(out, v.min_y), out += ' ';
        append_number(out, v.width), out += ' ', append_number(out, v.height), out += '"';
    }
    out += ">\n";
    for (std::size_t i = 0; i < doc.shapes.size(); ++i) {
        const svg_shape& s = doc.shapes[i];
        const std::string where = "shape " + std::to_string(i);
        check(s.closed.size() == s.subpaths.size(), [&] { return where + ": closed.size() != subpaths.size()"; });
        check(std::isfinite(s.stroke_width) && s.stroke_width >= 0, [&] { return where + ": stroke_width must be finite and >= 0"; });
        check(!detail::svg::trim(s.fill).empty() && !detail::svg::trim(s.stroke).empty(),
              [&] { return where + ": fill and stroke must not be empty"; });
        check_text(s.id, where + ": id");
        check_text(s.fill, where + ": fill");
        check_text(s.stroke, where + ": stroke");
        out += "  <path";
        if (!s.id.empty()) out += " id=\"", append_escaped(out, s.id), out += '"';
        out += " fill=\"", append_escaped(out, s.fill), out += "\" stroke=\"", append_escaped(out, s.stroke);
        out += "\" stroke-width=\"", append_number(out, s.stroke_width);
        out += s.rule == fill_rule::evenodd ? "\" fill-rule=\"evenodd\" d=\"" : "\" fill-rule=\"nonzero\" d=\"";
        for (std::size_t k = 0; k < s.subpaths.size(); ++k) {
            const auto& sp = s.subpaths[k];
            for (std::size_t j = 0; j < sp.size(); ++j) {
                check(all_finite(sp[j]), [&] {
                    return where + ": subpath " + std::to_string(k) + " point " + std::to_string(j) + " is not finite";
                });
                out += (k || j) ? (j ? " L " : " M ") : "M ";
                append_number(out, sp[j].x);
                out += ' ';
                append_number(out, sp[j].y);
            }
            if (s.closed[k]) out += " Z";
        }
        out += "\"/>\n";
    }
    out += "</svg>\n";
    return out;
}


/// Writes the document as SVG (see to_svg_string). Throws invalid_input for a bad document and
/// io_error if the file cannot be written.
inline void write_svg(const std::filesystem::path& path, const svg_document& doc) {
    atomic_write(path, to_svg_string(doc));
}

}  // namespace fabsynth::io
