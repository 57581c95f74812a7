// SPDX-License-Identifier: MIT
#pragma once
/// @file pipeline.hpp  The vector-pattern pipeline in one call (Zhou et al. 2014): a band exemplar
/// synthesized along a planar curve, in a rectangle (§6.2), along a curve in space, or along a
/// curve drawn on a surface and embossed onto or carved out of it (§6.3), then turned into a
/// printable watertight mesh, the drawing in the plane and a preview image.
///
/// make_pattern(exemplar, where, options, progress) is a thin function over the named phases in
/// detail::pipeline, each callable and testable alone:
///  1. scaled_exemplar: the exemplar scaled uniformly so that its height is options.band_height.
///  2. band_synthesis_options: options.synthesis with the band's length L, closedness and height.
///  3. one pair of phases per form of `where`, progress reported between the two:
///     - synthesize_curve_band (check the band fits the curve, |v| <= H/2; synthesize_along) and
///       extrude_planar_band (the result mapped onto the curve is the drawing,
///       vector_pattern/band_map.hpp; the slab is extruded in the parameter domain,
///       geometry/extrude.hpp, and mirrored to a y-up frame: the drawing is y-down, as SVG);
///     - synthesize_rectangle_band (synthesize_rectangle) and extrude_rectangle_band (triangulate,
///       extrude, mirror);
///     - synthesize_curve_band (check the band fits, synthesize_along; the drawing is the developed
///       band, u along the curve, v across) and extrude_along_space_curve;
///     - traced_surface_band (a closed genus-0 mesh is cut open at the vertex farthest from the
///       points, harmonic disk map, trace_surface_curve, band_curve with points closer than H/8
///       merged), synthesize_space_band, decorated_surface (decorate_surface, the drawing is the
///       developed band).
///     Before the synthesis of an extruded form, require_separate_shapes refuses an exemplar whose
///     shapes touch or cross (a figure-eight, shapes meeting at a corner: no closed solid); before
///     its extrusion, require_separate_band_shapes refuses a synthesized pattern that does so, at
///     its place along the curve.
///  4. finish: weld_to_float (merges only what keeps the mesh closed: a closed indexed mesh stays
///     closed in float), require_watertight (the final guard; a failure is a solver_error: a bug of
///     the producer), the solid's topology (surfaces only), the view box of the drawing and the preview:
///     the coverage image of the drawing for planar forms, a shaded render of the solid from two
///     opposite sides for curves in space and surfaces.
/// Progress: reported between every phase (fractions in [0, 1], stage names as the phases) and
/// inside the synthesis, at every length layer of the sequence DP (dp::solve_sequence), so a
/// cancellation (the callback returning false: fabsynth::cancelled) stops the DP within a layer.
/// The other inner calls (decorate_surface, disk_parameterization, the extrusions, the renderers)
/// take no callback: a cancellation there takes effect at the next phase boundary. No file I/O
/// (drivers read and write).
///
/// Usage:
///   #include <fabsynth/vector_pattern.hpp>
///   #include <fabsynth/io/image.hpp>
///   #include <fabsynth/io/svg.hpp>
///   namespace vp = fabsynth::vector_pattern;
///   const vp::exemplar ex = vp::exemplar_from_svg(fabsynth::io::read_svg("data/vector/greek_key.svg"));
///   vp::pattern_options opt;
///   opt.band_height = 10;                      // mm: the exemplar is scaled to this height
///   opt.synthesis.components = 1;              // exact topology of the pattern
///   // along a planar curve (also: vp::in_rectangle{60, 40}, vp::along_space_curve{space_curve::polyline(...)},
///   //                       vp::on_surface{mesh, points, true} with opt.decoration.mode = decoration_mode::carve)
///   const vp::pattern_result r = vp::make_pattern(ex, vp::along_planar_curve{fabsynth::planar_curve::circle(40)}, opt,
///       [](double f, std::string_view stage) { return true; /* false cancels */ });
///   fabsynth::io::write_svg("band.svg", fabsynth::io::document_of(r.drawn, r.view));
///   fabsynth::io::write_png("band.png", r.preview);
///   // r.mesh: watertight, 1 mm thick; r.synthesis.components == 1; r.natural_length, r.stretch
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/coverage_image.hpp"
#include "fabsynth/geometry/curve.hpp"
#include "fabsynth/surface/disk_parameterization.hpp"
#include "fabsynth/geometry/extrude.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/render.hpp"
#include "fabsynth/geometry/space_curve.hpp"
#include "fabsynth/surface/curve.hpp"
#include "fabsynth/surface/decoration.hpp"
#include "fabsynth/geometry/triangulate.hpp"
#include "fabsynth/vector_pattern/band_map.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"
#include "fabsynth/vector_pattern/synthesis.hpp"

namespace fabsynth::vector_pattern {

/// A band along a curve in the plane (mm; geometry/curve.hpp). Closed if the curve is.
struct along_planar_curve {
    planar_curve curve;
};

/// A rectangle of width x height mm (§6.2), u in [0, width], v in [0, height].
struct in_rectangle {
    double width = 0.0;   ///< mm, > 0
    double height = 0.0;  ///< mm, > 0
};

/// A band along a curve in space (mm; geometry/space_curve.hpp: rotation-minimising frames and
/// its twist). The band lies along the frame's normal, the slab's thickness along the binormal.
struct along_space_curve {
    space_curve curve;
};

/// A band along a curve drawn on a surface (§6.3), embossed or carved as options.decoration.mode
/// says.
struct on_surface {
    triangle_mesh surface;     ///< #V x 3 positions (mm), #F triangles: a disk-topology mesh or a closed genus-0 one
    std::vector<vec3> points;  ///< #P >= 2 points (mm) on the surface, snapped to it, that the curve passes through
    bool closed = false;       ///< the curve's last point is joined to its first
};

/// Where the pattern goes.
using pattern_where = std::variant<along_planar_curve, in_rectangle, along_space_curve, on_surface>;

/// Options of make_pattern; the defaults are the paper's and the curve_patterns tool's.
struct pattern_options {
    double band_height = 0.0;  ///< H, mm (> 0): the exemplar is scaled uniformly to this height
    /// Topology (components, holes, closed_loop), seed, slicing, beta... of the synthesis. Its
    /// length, closed and band_height are set by make_pattern (L of the curve, the curve's
    /// closedness, H); for a rectangle, components, holes and seed apply to the final rectangle
    /// and the rest is rectangle_options::base.
    synthesis_options synthesis{};
    double thickness = 1.0;        ///< slab thickness of planar forms and space curves, mm (> 0); surfaces use `decoration`
    double chord_tolerance = 0.0;  ///< max chord error of the mapped outlines, mm; 0 = H / 1000
    double max_band_heights = 1e5; ///< a band longer than this many heights H is refused (tolerances underflow)
    /// Surfaces: mode (emboss / carve), shell and relief height (mm), cell (mm; 0 = decoration_cell()).
    surface_decoration_options decoration{};
    surface_curve_options surface_curve{};          ///< surfaces: sampling of the drawn curve
    disk_parameterization_options parameterization{};  ///< surfaces: the harmonic map's border
    double merge_spacing = 0.125;  ///< surfaces: band-curve points closer than this fraction of H are merged
    double view_padding = 0.02;    ///< the drawing's view box: its bounds grown by this fraction of the longer side
    preview_options preview{.max_side = 1600, .supersample = 4};           ///< planar forms: coverage image
    render_view render_direction{.direction = {0.35, 1.0, -0.45}, .up = {0, 0, 1}};  ///< curves in space, surfaces
    render_options render{.width = 800, .height = 800};                    ///< one of the two rendered sides
};

/// What make_pattern returns.
struct pattern_result {
    synthesis_result synthesis;  ///< in band coordinates (u along the curve in [0, L], v across); counts, DP figures
    /// The drawing, in the plane (mm, y down as in SVG): the pattern mapped onto the planar curve,
    /// the rectangle, or the developed band (u, v) of a curve in space or on a surface.
    std::vector<polygon_with_holes> drawn;
    box2 view;          ///< view box of the drawing (its bounds padded by view_padding)
    triangle_mesh mesh; ///< the printable solid, watertight, vertices welded in single precision (mm);
                        ///< planar forms in a y-up frame (the drawing mirrored), 3D forms in the input's frame
    image8 preview;     ///< planar forms: grey coverage of `drawn` over `view`; 3D: RGB render from two sides
    // report figures
    double band_length = 0.0;     ///< L, mm (0 for a rectangle)
    bool closed = false;          ///< the curve is closed
    double natural_length = 0.0;  ///< l = synthesis.achieved_length, mm
    double stretch = 1.0;         ///< L / l (every piece is stretched along the curve by it); 1 for a rectangle
    std::size_t rings = 0;        ///< rings drawn: outlines plus holes of `drawn`
    std::size_t edge_crossings = 0;  ///< surfaces: mesh edges the drawn curve crosses
    bool cut_open = false;        ///< surfaces: the closed mesh was cut open for the map (far from the points)
    mesh_topology_info solid{};   ///< surfaces: topology of `mesh` (components, genus); default otherwise
    bool in_space = false;        ///< a curve in space or a surface (the preview is then a render)
};

/// The decoration grid spacing make_pattern uses on a surface (mm): options.decoration.cell, or if
/// it is 0 a quarter of min(shell, relief height) (emboss) or of the shell (carve), at most H / 40.
[[nodiscard]] inline double decoration_cell(const pattern_options& opt) {
    const surface_decoration_options& d = opt.decoration;
    if (d.cell > 0.0) return d.cell;
    const bool emboss = d.mode == decoration_mode::emboss;
    return std::min(0.25 * (emboss ? std::min(d.shell, d.height) : d.shell), opt.band_height / 40.0);
}

/// Peak memory of decorating `surface` at grid spacing `cell` (mm), bytes: its level set has about
/// 9 triangles per cell^2 of each side of the shell, about 200 bytes each at the peak (measured:
/// benchmarks/README.md, bands on surfaces). For a driver's memory limit, before make_pattern.
[[nodiscard]] inline double estimated_decoration_bytes(const triangle_mesh& surface, double cell) {
    return 200.0 * 9.0 * 2.0 * surface_area(surface) / (cell * cell);
}

/// Throws invalid_input, naming `name` (the exemplar's file, say) and the place in the exemplar's
/// own units, if two of the exemplar's shapes, or two parts of one shape, touch or cross (closer
/// than 1e-6 of its height; geometry/extrude.hpp's find_ring_contact): a self-intersecting
/// outline repaired into a figure-eight, two shapes meeting at a corner, a hole touching its
/// outline. A band of such shapes extruded (a planar curve, a rectangle, a curve in space) has a
/// contact that is no closed 2-manifold solid, so make_pattern refuses it before the synthesis.
/// (On a surface the level set merges the shapes there, so surfaces take such exemplars.)
inline void require_separate_shapes(const exemplar& ex, const std::string& name) {
    const auto c = find_ring_contact(ex.polygons, 1e-6 * ex.height());
    if (!c) return;
    throw invalid_input(name + ": the exemplar's shapes " +
                        (c->polygon_a == c->polygon_b ? "touch themselves" : "touch each other (its polygons " + std::to_string(c->polygon_a) + " and " + std::to_string(c->polygon_b) + ", after repair)") +
                        " at (" + std::to_string(c->at.x) + ", " + std::to_string(c->at.y) +
                        ") in its own units (a self-intersecting or touching outline): an extruded band would not be a closed solid there; "
                        "move the shapes apart or let them overlap in the exemplar");
}

namespace detail::pipeline {

/// Phase 1: the exemplar scaled to height H.
[[nodiscard]] inline exemplar scaled_exemplar(const exemplar& raw, double band_height) {
    if (!(raw.height() > 0.0)) throw invalid_input("make_pattern: the exemplar has no height");
    return scaled(raw, band_height / raw.height());
}

/// Phase 2: the synthesis options for a band of length L (mm).
[[nodiscard]] inline synthesis_options band_synthesis_options(const pattern_options& opt, double length, bool closed) {
    if (!(length <= opt.max_band_heights * opt.band_height))
        throw invalid_input("make_pattern: the band is " + std::to_string(length) + " mm long, more than " + std::to_string(opt.max_band_heights) +
                            " band heights");
    if (opt.synthesis.closed_loop && !closed) throw invalid_input("make_pattern: closed_loop needs a closed curve");
    synthesis_options so = opt.synthesis;
    so.band_height = opt.band_height;
    so.length = length;
    so.closed = closed;
    return so;
}

/// The phases' common product before finish().
struct band_solid {
    synthesis_result synthesis;
    std::vector<polygon_with_holes> drawn;
    triangle_mesh mesh;
    double band_length = 0.0;
    bool closed = false;
};

[[nodiscard]] inline curve_extrude_options extrude_options(const pattern_options& opt) {
    return {.thickness = opt.thickness, .chord_tolerance = opt.chord_tolerance > 0.0 ? opt.chord_tolerance : opt.band_height / 1000.0};
}

/// Phase 3, before an extrusion: the synthesized pattern's shapes must not touch (they would share
/// an edge of the solid; find_ring_contact, closer than 1e-6 H). Contacts on the cut lines u = 0
/// and u = L are left alone: on a closed curve they are the seam's, glued by the extrusion; on an
/// open one the band's flat ends, where shapes cut by the same line meet in a vertex the
/// extrusion keeps closed (the lace along a line of the main job has one).
inline void require_separate_band_shapes(const band_solid& b, const pattern_options& opt) {
    const double tol = 1e-6 * opt.band_height;
    const auto c = find_ring_contact(b.synthesis.polygons, tol);
    if (!c) return;
    if (std::abs(c->at.x) <= tol || std::abs(c->at.x - b.band_length) <= tol) return;
    throw invalid_input("make_pattern: the synthesized pattern's shapes touch at u = " + std::to_string(c->at.x) + " mm along the curve, v = " +
                        std::to_string(c->at.y) + " mm across it: the extruded band would not be a closed solid there; "
                        "try another seed, band height or component count");
}

/// Phase 3, before the synthesis along a curve in space: the band (|v| <= H/2, thickness along
/// the binormal) must not meet itself far along the curve (space_curve::find_self_contact: a helix
/// whose turns are closer than the band is high, a curve crossing itself); the extrusion would be
/// a self-intersecting solid, watertight but not printable as meant.
inline void require_band_clear_of_itself(const space_curve& curve, const pattern_options& opt) {
    const auto c = curve.find_self_contact(0.5 * opt.band_height, opt.thickness);
    if (!c) return;
    const auto mm = [](double v) {
        char b[32];
        std::snprintf(b, sizeof b, "%.4g", v);
        return std::string(b);
    };
    throw invalid_input("make_pattern: the band meets itself: its cross-sections at u = " + mm(c->u1) + " mm and u = " + mm(c->u2) +
                        " mm along the curve come within " + mm(c->distance) + " mm of each other near (" + mm(c->at.x) + ", " + mm(c->at.y) + ", " +
                        mm(c->at.z) + ") (band height " + mm(opt.band_height) + " mm, thickness " + mm(opt.thickness) + " mm; parts closer than " +
                        mm(c->clearance) + " mm count as touching); lower the band height or the twist, or move those parts of the curve apart");
}

/// Phase 3, first half for a curve (planar_curve or space_curve): check that the band fits the curve
/// (the exemplar itself, |v| <= H/2), then the synthesis along it. Along a curve in space (space and
/// surface bands) the drawing is the developed band; a planar curve's is mapped in its second half.
template <class Curve>
void synthesize_curve_band(const exemplar& ex, const Curve& curve, const pattern_options& opt, band_solid& b, const progress_span& progress = {}) {
    curve.check_band(0.5 * opt.band_height);
    b.band_length = curve.length();
    b.closed = curve.closed();
    b.synthesis = synthesize_along(ex, band_synthesis_options(opt, b.band_length, b.closed), progress);
    if constexpr (std::is_same_v<Curve, space_curve>) b.drawn = b.synthesis.polygons;
}

/// Phase 3, planar curve, second half: the drawing (the result mapped onto the curve) and the slab
/// (extruded in the parameter domain), mirrored to a y-up frame (the drawing is y-down, as SVG).
inline void extrude_planar_band(const planar_curve& curve, const pattern_options& opt, band_solid& b) {
    const curve_extrude_options eo = extrude_options(opt);
    b.drawn = map_to_curve(b.synthesis.polygons, curve, {.chord_tolerance = eo.chord_tolerance});
    b.mesh = extrude_along_curve(b.synthesis.polygons, curve, eo);
    mirror_y(b.mesh);
}

/// Phase 3, rectangle (§6.2), first half: synthesize_rectangle, with options.synthesis's
/// components, holes and seed for the final rectangle and the rest as the base of both passes.
inline void synthesize_rectangle_band(const exemplar& ex, const in_rectangle& rect, const pattern_options& opt, band_solid& b,
                                      const progress_span& progress = {}) {
    if (opt.synthesis.closed_loop) throw invalid_input("make_pattern: closed_loop needs a closed curve (a rectangle has none)");
    rectangle_options ro;
    ro.width = require_positive(rect.width, "make_pattern: rectangle width");
    ro.height = require_positive(rect.height, "make_pattern: rectangle height");
    ro.components = opt.synthesis.components;
    ro.holes = opt.synthesis.holes;
    ro.seed = opt.synthesis.seed;
    ro.base = opt.synthesis;
    ro.base.band_height = opt.band_height;
    b.synthesis = synthesize_rectangle(ex, ro, progress);
    b.drawn = b.synthesis.polygons;
}

/// Phase 3, rectangle, second half: triangulated, extruded and mirrored to a y-up frame.
inline void extrude_rectangle_band(const pattern_options& opt, band_solid& b) {
    b.mesh = extrude(triangulate(b.drawn), opt.thickness);
    mirror_y(b.mesh);
}

/// The band's curve on a surface (first half of the surface phase).
struct traced_band {
    space_curve curve;
    std::size_t edge_crossings = 0;
    bool cut_open = false;
};

/// A closed genus-0 mesh is cut open at the vertex farthest from the points; the points are joined
/// by a spline in the disk map and traced on the mesh; the band curve merges points closer than
/// merge_spacing H.
[[nodiscard]] inline traced_band traced_surface_band(const on_surface& s, const pattern_options& opt) {
    validate(s.surface, "make_pattern: surface");
    const mesh_topology_info t = analyze_topology(s.surface);
    const bool cut = t.boundary_edges == 0 && t.components == 1 && t.genus == 0;
    const disk_parameterization phi(cut ? cut_open(s.surface, farthest_vertex(s.surface, s.points)) : s.surface, opt.parameterization);
    const surface_curve drawn = trace_surface_curve(phi, s.points, s.closed, opt.surface_curve);
    return {.curve = drawn.band_curve(opt.band_height * opt.merge_spacing), .edge_crossings = drawn.edge_crossings, .cut_open = cut};
}

/// Decorate a surface with the synthesized band (second half of the surface phase).
[[nodiscard]] inline triangle_mesh decorated_surface(const on_surface& s, const space_curve& curve, const synthesis_result& r,
                                                     const pattern_options& opt) {
    surface_decoration_options deco = opt.decoration;
    deco.cell = decoration_cell(opt);
    return decorate_surface(s.surface, curve, r.polygons, deco);
}

/// Phase 4 (the parts that follow the form): weld, check, view, preview.
inline void finish(band_solid&& b, bool in_space, bool on_a_surface, const pattern_options& opt, pattern_result& out) {
    weld_to_float(b.mesh);
    require_watertight(b.mesh, on_a_surface ? "the decorated solid, rounded to single precision," : "the extruded mesh, rounded to single precision,");
    if (on_a_surface) out.solid = analyze_topology(b.mesh);
    const box2 bounds = bounding_box(b.drawn);
    if (bounds.empty()) throw solver_error("the synthesized pattern is empty");
    out.view = framed_view(bounds, opt.view_padding);
    out.preview = in_space ? render_two_sides(b.mesh, opt.render_direction, opt.render) : preview_image(b.drawn, out.view, opt.preview);
    for (const auto& p : b.drawn) out.rings += 1 + p.holes.size();
    out.in_space = in_space;
    out.band_length = b.band_length;
    out.closed = b.closed;
    out.natural_length = b.synthesis.achieved_length;
    out.stretch = b.band_length > 0 && b.synthesis.achieved_length > 0 ? b.band_length / b.synthesis.achieved_length : 1.0;
    out.synthesis = std::move(b.synthesis);
    out.drawn = std::move(b.drawn);
    out.mesh = std::move(b.mesh);
}

inline void check_options(const pattern_options& opt) {
    if (!(std::isfinite(opt.band_height) && opt.band_height > 0.0)) throw invalid_input("make_pattern: band_height must be finite and > 0 mm");
    if (!(std::isfinite(opt.thickness) && opt.thickness > 0.0)) throw invalid_input("make_pattern: thickness must be finite and > 0 mm");
    if (!(std::isfinite(opt.chord_tolerance) && opt.chord_tolerance >= 0.0))
        throw invalid_input("make_pattern: chord_tolerance must be finite and >= 0 mm (0 = H / 1000)");
    if (!(opt.max_band_heights > 0.0)) throw invalid_input("make_pattern: max_band_heights must be > 0");
    if (!(std::isfinite(opt.merge_spacing) && opt.merge_spacing >= 0.0)) throw invalid_input("make_pattern: merge_spacing must be finite and >= 0");
}

}  // namespace detail::pipeline

/// The whole pipeline (see the file comment).
/// @param[in] ex        the band exemplar as read (vector_pattern/exemplar.hpp; filled shapes along x, any scale):
///                      it is scaled uniformly to height options.band_height
/// @param[in] where     along_planar_curve, in_rectangle, along_space_curve or on_surface (lengths in mm)
/// @param[in] options   see pattern_options (band_height is required)
/// @param[in] progress  called as progress(fraction in [0, 1], stage) between the phases and at
///                      every DP layer; returning false throws fabsynth::cancelled at that point
/// Throws invalid_input for a request that cannot be built (a band that does not fit its curve,
/// a band along a space curve whose distant parts meet, checked before the synthesis, bad options, a surface that is neither a disk nor a closed genus-0 mesh, an exemplar or a
/// synthesized pattern whose shapes touch or cross, for the extruded forms), no_solution when no
/// piece sequence meets the topology, solver_error for a result that fails its checks (a bug).
template <progress_callback P = no_progress>
[[nodiscard]] pattern_result make_pattern(const exemplar& ex, const pattern_where& where, const pattern_options& options, P&& progress = {}) {
    namespace ph = detail::pipeline;
    ph::check_options(options);
    report_progress(progress, 0.0, "scale the exemplar");
    const exemplar scaled_ex = ph::scaled_exemplar(ex, options.band_height);
    pattern_result out;
    ph::band_solid b;
    bool in_space = false, surface = false;
    if (!std::holds_alternative<on_surface>(where)) require_separate_shapes(ex, "make_pattern");
    if (const auto* c = std::get_if<along_planar_curve>(&where)) {
        report_progress(progress, 0.05, "synthesis");
        ph::synthesize_curve_band(scaled_ex, c->curve, options, b, progress_span(progress, 0.05, 0.5));
        report_progress(progress, 0.5, "extrusion");
        ph::require_separate_band_shapes(b, options);
        ph::extrude_planar_band(c->curve, options, b);
    } else if (const auto* r = std::get_if<in_rectangle>(&where)) {
        report_progress(progress, 0.05, "synthesis");
        ph::synthesize_rectangle_band(scaled_ex, *r, options, b, progress_span(progress, 0.05, 0.5));
        report_progress(progress, 0.5, "extrusion");
        ph::require_separate_band_shapes(b, options);
        ph::extrude_rectangle_band(options, b);
    } else if (const auto* s = std::get_if<along_space_curve>(&where)) {
        in_space = true;
        s->curve.check_band(0.5 * options.band_height);
        ph::require_band_clear_of_itself(s->curve, options);
        report_progress(progress, 0.05, "synthesis");
        ph::synthesize_curve_band(scaled_ex, s->curve, options, b, progress_span(progress, 0.05, 0.5));
        report_progress(progress, 0.5, "extrusion");
        ph::require_separate_band_shapes(b, options);
        b.mesh = extrude_along_space_curve(b.synthesis.polygons, s->curve, ph::extrude_options(options));
    } else {
        const on_surface& su = std::get<on_surface>(where);
        in_space = surface = true;
        report_progress(progress, 0.05, "parameterize the surface");
        const ph::traced_band band = ph::traced_surface_band(su, options);
        out.edge_crossings = band.edge_crossings;
        out.cut_open = band.cut_open;
        report_progress(progress, 0.1, "synthesis");
        ph::synthesize_curve_band(scaled_ex, band.curve, options, b, progress_span(progress, 0.1, 0.5));
        report_progress(progress, 0.5, "decorate the surface");
        b.mesh = ph::decorated_surface(su, band.curve, b.synthesis, options);
    }
    report_progress(progress, 0.8, "mesh");
    ph::finish(std::move(b), in_space, surface, options, out);
    report_progress(progress, 1.0, "done");
    return out;
}

}  // namespace fabsynth::vector_pattern
