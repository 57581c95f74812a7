// SPDX-License-Identifier: MIT
#pragma once
/// @file pipeline.hpp  The filigree pipeline on a base surface in one call (filigree-synthesis.md
/// part 2, §8): synthesis on the surface (synthesis.hpp here), the strips baked into the base faces
/// (reconstruct.hpp), the structural optimization of §5 on M_b (structure.hpp), the printable solid
/// of eq. 9 (surface/offset.hpp) and the preview, exactly as the `filigree --mesh` tool writes them.
/// The options, timings and conventions are the planar pipeline's (filigree/pipeline.hpp).
///
/// Usage (every length in mm):
///   namespace fg = fabsynth::filigree;
///   fg::surface_filigree_options so;               // the common options + up vector, region, per-vertex scale
///   so.up = {0, 0, 1};                             // the elements' up, projected on the surface
///   so.region_faces = std::vector<std::uint32_t>{...};  // or so.region_curve (points on the mesh); neither: all of it
///   so.class_allowed = fg::face_label_regions(labels, mesh.faces.size(), {{0}, {1}});  // optional: class 0 on faces labelled 0, class 1 on 1
///   const fg::surface_filigree s = fg::make_filigree(classes, weights, mesh, so);   // mesh in mm
///   s.solid;         // printable watertight solid (eq. 9), s.reinforcement.baked = M_b
///   s.preview;       // RGB: the base mesh with the solid, seen from two sides
///
/// Progress and errors: as the planar make_filigree (reported between the named phases; false
/// cancels), plus invalid_input for a bad region, up vector or per-vertex scale.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/progress.hpp"
#include "fabsynth/filigree/pipeline.hpp"
#include "fabsynth/filigree/surface/field.hpp"
#include "fabsynth/filigree/surface/reconstruct.hpp"
#include "fabsynth/filigree/surface/structure.hpp"
#include "fabsynth/filigree/surface/synthesis.hpp"
#include "fabsynth/geometry/extrude.hpp"
#include "fabsynth/geometry/mesh.hpp"
#include "fabsynth/geometry/mesh_topology.hpp"
#include "fabsynth/geometry/render.hpp"
#include "fabsynth/surface/curve_region.hpp"
#include "fabsynth/surface/exponential_map.hpp"
#include "fabsynth/surface/offset.hpp"

namespace fabsynth::filigree {

/// Options of the surface form: the common options plus where and how the elements lie.
struct surface_filigree_options : filigree_options {
    vec3 up{0, 0, 1};                         ///< the elements' up vector (projected on the surface), gravity along -up; finite, non-zero
    std::optional<std::vector<std::uint32_t>> region_faces;  ///< faces (0-based) to cover; none (and no curve): the whole mesh
    std::optional<std::vector<vec3>> region_curve;           ///< or a closed curve drawn on the mesh (mm): the smaller side it encloses (curve_region.hpp)
    double region_curve_reach = 0;            ///< how far curve points may lie off the mesh, mm; 0: 2% of the mesh's bounding-box diagonal
    std::string region_name;                  ///< names the region in messages (e.g. its file); empty: "region" / "curve region"
    std::vector<double> vertex_scale;         ///< one element scale factor per mesh vertex; empty: 1 everywhere
    /// User directions at mesh vertices (§7.2, Fig. 16a's sketched constraints), harmonically
    /// interpolated over the surface (surface/field.hpp); empty: the elements follow `up` everywhere.
    std::vector<direction_constraint> directions;
    /// Element sets per region on the mesh (Fig. 1c): whether class `cls` may have an instance's
    /// reference point on mesh face `face` (0-based); empty: every class everywhere.
    /// face_label_regions (surface/space.hpp) builds one from a label per face.
    std::function<bool(std::uint32_t cls, std::uint32_t face)> class_allowed;
    double solid_cell = 0;                    ///< grid spacing of the thickening, mm; 0: a third of the final thickness
};

/// The base mesh of a surface filigree with its region and control fields (built once from the
/// options' up, directions, region_* and vertex_scale; make_filigree builds one, or takes one built by the
/// caller, e.g. to check the region's size before the work). Not copyable: the fields point into it.
class surface_filigree_base {
public:
    surface_filigree_base(triangle_mesh mesh, const surface_filigree_options& opt)
        : mesh_(checked(std::move(mesh))), patcher_(mesh_), region_(make_region(opt)), direction_(opt.directions.empty() ? surface_direction_field::from_up_vector(patcher_, opt.up)
                                                 : surface_direction_field::from_constraints(patcher_, opt.directions, opt.up)),
          scale_(opt.vertex_scale.empty() ? surface_scale_field::constant(mesh_, 1.0) : surface_scale_field::per_vertex(mesh_, opt.vertex_scale)) {}
    surface_filigree_base(const surface_filigree_base&) = delete;
    surface_filigree_base& operator=(const surface_filigree_base&) = delete;

    [[nodiscard]] const triangle_mesh& mesh() const noexcept { return mesh_; }
    [[nodiscard]] const surface_patcher& patcher() const noexcept { return patcher_; }
    [[nodiscard]] const surface_region& region() const noexcept { return region_; }
    [[nodiscard]] surface_control field() const noexcept { return {&direction_, &scale_}; }

private:
    static triangle_mesh checked(triangle_mesh m) {
        if (m.faces.empty()) throw invalid_input("filigree: the base mesh has no faces");
        return m;
    }
    surface_region make_region(const surface_filigree_options& opt) const {
        surface_region r = region_of(opt);
        r.class_allowed = opt.class_allowed;
        return r;
    }
    surface_region region_of(const surface_filigree_options& opt) const {
        if (opt.region_faces && opt.region_curve) throw invalid_input("filigree: give region_faces or region_curve, not both");
        if (opt.region_faces)
            return opt.region_name.empty() ? surface_region::of_faces(patcher_, *opt.region_faces) : surface_region::of_faces(patcher_, *opt.region_faces, opt.region_name);
        if (!opt.region_curve) return surface_region::whole(patcher_);
        // points drawn on a coarser copy of the mesh may lie off it
        const double reach = opt.region_curve_reach > 0 ? opt.region_curve_reach : 0.02 * glm::length(bounding_box(mesh_).size());
        std::vector<std::uint32_t> inside;
        try {
            inside = faces_inside_curve(mesh_, *opt.region_curve, reach);
        } catch (const invalid_input& e) {  // "fabsynth: curve region: ...": name the region instead
            if (opt.region_name.empty()) throw;
            const std::string what = e.what();
            const std::size_t at = what.find("curve region: ");
            throw invalid_input(opt.region_name + ": " + (at == std::string::npos ? what : what.substr(at + 14)));
        }
        return opt.region_name.empty() ? surface_region::of_faces(patcher_, inside) : surface_region::of_faces(patcher_, inside, opt.region_name);
    }

    triangle_mesh mesh_;
    surface_patcher patcher_;
    surface_region region_;
    surface_direction_field direction_;
    surface_scale_field scale_;
};

/// What make_filigree produces on a base surface.
struct surface_filigree {
    surface_synthesis_result synthesis;          ///< the layout on the surface and its skeletons after the topology cut
    surface_reinforcement_result reinforcement;  ///< the final layout, M_b (baked, largest piece) and thickness after §5
    triangle_mesh solid;                         ///< printable: every point within half the thickness of M_b (eq. 9), watertight
    std::size_t solid_components = 0;            ///< connected pieces of `solid`
    double solid_cell = 0;                       ///< grid spacing `solid` was extracted at, mm
    image8 preview;                              ///< RGB, two 800 x 800 views: the base mesh with the solid, from the side and the opposite side
    image8 histogram;                            ///< Fig. 21: nodal stress before and after §5 (RGB; empty without analysis)
    image8 stress_map;                           ///< Fig. 10: surface_stress_map of the final analysis (RGB, as the preview; empty without analysis)
    std::vector<std::size_t> instances_per_class;  ///< of the synthesized layout (synthesis.instances, before §5's insertions), per class
    filigree_timings seconds;
};

namespace detail::pipeline {

// The base mesh with the solid on it, vertex-coloured (base beige, solid brown), for the preview.
inline triangle_mesh with_solid(const triangle_mesh& base, const triangle_mesh& solid, std::vector<std::array<std::uint8_t, 3>>& colours) {
    triangle_mesh both = base;
    colours.assign(base.vertices.size(), {236, 228, 210});
    const auto off = static_cast<std::uint32_t>(base.vertices.size());
    for (const vec3& v : solid.vertices) both.vertices.push_back(v), colours.push_back({140, 62, 28});
    for (auto f : solid.faces) {
        for (auto& k : f) k += off;
        both.faces.push_back(f);
    }
    return both;
}

// The previews' view: from a side perpendicular to up, up upward (render_two_sides adds the
// opposite side); 800 x 800 pixels per side.
inline render_view side_view(vec3 up) {
    const vec3 u = glm::normalize(up);
    const vec3 side = std::abs(u.z) < 0.9 ? glm::normalize(glm::cross(u, vec3(0, 0, 1))) : vec3(0, 1, 0);
    return {side, u};
}
inline render_options preview_look() {
    render_options look;
    look.width = 800, look.height = 800;
    return look;
}

// The base with the solid from a side perpendicular to up and from the opposite side, up upward.
inline image8 surface_preview(const triangle_mesh& base, const triangle_mesh& solid, vec3 up) {
    std::vector<std::array<std::uint8_t, 3>> colours;
    const triangle_mesh scene = with_solid(base, solid, colours);
    return render_two_sides(scene, side_view(up), preview_look(), colours);
}

}  // namespace detail::pipeline

/// Fig. 10 on a surface: the analysed mesh `fem` (mm; surface_reinforcement_result::fem) seen as the
/// preview sees the piece (from a side perpendicular to `up` and from the opposite side, 800 x 800
/// pixels each, then the legend of stress_map_image in a 260-pixel column, RGB), each vertex coloured by its von Mises stress over the yield stress
/// (`report.node_von_mises` / `report.yield`, MPa; the colours of stress_map_image: blue 0, green
/// half the yield, red at the yield, magenta above it: the weak nodes), shaded, interpolated over the
/// faces. Throws invalid_input unless the report holds one stress per vertex of `fem` and a yield > 0.
[[nodiscard]] inline image8 surface_stress_map(const triangle_mesh& fem, const structural_report& report, vec3 up) {
    if (fem.faces.empty()) throw invalid_input("surface stress map: the analysed mesh has no face");
    if (report.node_von_mises.size() != fem.vertices.size())
        throw invalid_input("surface stress map: the report holds " + std::to_string(report.node_von_mises.size()) + " nodal stresses for a mesh of " +
                            std::to_string(fem.vertices.size()) + " vertices");
    if (!(report.yield > 0)) throw invalid_input("surface stress map: the yield stress must be > 0 MPa");
    std::vector<std::array<std::uint8_t, 3>> colours;
    colours.reserve(fem.vertices.size());
    for (const double s : report.node_von_mises) colours.push_back(detail::figures::to_rgb(detail::figures::stress_colour(s / report.yield)));
    const image8 views = render_two_sides(fem, detail::pipeline::side_view(up), detail::pipeline::preview_look(), colours);
    canvas cv(views.width + 260, std::max(views.height, 420));  // the views, then the planar map's legend
    for (int y = 0; y < views.height; ++y)
        for (int x = 0; x < views.width; ++x)
            cv.put(x, y, views.channels == 3 ? rgb8{views.at(x, y, 0), views.at(x, y, 1), views.at(x, y, 2)} : rgb8{views.at(x, y), views.at(x, y), views.at(x, y)});
    detail::figures::draw_stress_legend(cv, views.width + 30, cv.img.height, report);
    return cv.img;
}

/// The surface pipeline on a prepared base (mesh, region, fields; opt's up, region_* and
/// vertex_scale were used to build it, the rest is read here): synthesize_on_surface,
/// reinforce_on_surface, thicken_surface and the preview.
template <progress_callback P = no_progress>
[[nodiscard]] surface_filigree make_filigree(std::span<const element> classes, std::span<const double> weights, const surface_filigree_base& base,
                                             const surface_filigree_options& opt = {}, P&& progress = {}) {
    namespace dp = detail::pipeline;
    const auto t_start = dp::clock::now();
    dp::check_weights(classes, weights);
    detail::reinforce::check_thickness(opt.reinforcement);  // bad structure options fail before the synthesis
    if (!detail::reinforce::default_support(opt.reinforcement.support))
        throw invalid_input("filigree on a surface: `support` is the planar form's; the supports are the lowest 5% along `up`");
    surface_filigree r;

    report_progress(progress, 0.05, "synthesis on the surface");
    r.synthesis = synthesize_on_surface(classes, weights, base.region(), base.field(), opt.synthesis, progress_span(progress, 0.05, 0.6));
    r.seconds.synthesis = r.synthesis.seconds;

    report_progress(progress, 0.6, opt.reinforcement.enabled ? "bake and structure" : "bake");
    surface_reinforcement_options sro;
    sro.base = opt.reinforcement, sro.up = opt.up;
    r.reinforcement = reinforce_on_surface(classes, weights, base.region(), base.field(), opt.synthesis, r.synthesis, sro, progress_span(progress, 0.6, 0.8));
    r.seconds.structure = r.reinforcement.seconds;

    report_progress(progress, 0.8, "printable mesh");
    auto t = dp::clock::now();
    surface_offset_options oo;
    // default: the surface_offset guideline (cell <= tau / 4) at a third: the strips are wider than thick
    oo.cell = opt.solid_cell > 0 ? opt.solid_cell : r.reinforcement.thickness / 3;
    r.solid_cell = oo.cell;
    r.solid = thicken_surface(r.reinforcement.baked, r.reinforcement.thickness, oo);
    weld_to_float(r.solid);  // what STL and 3MF store; checked below as written
    const mesh_topology_info topo = analyze_topology(r.solid);
    if (!topo.is_watertight())
        throw solver_error("the printable mesh, rounded to single precision, is not watertight (" + std::to_string(topo.boundary_edges) + " boundary, " +
                           std::to_string(topo.nonmanifold_edges) + " non-manifold edges)");
    r.solid_components = topo.components;
    r.seconds.mesh = dp::since(t);

    report_progress(progress, 0.9, "render");
    t = dp::clock::now();
    if (opt.previews) r.preview = dp::surface_preview(base.mesh(), r.solid, opt.up);
    if (opt.previews && r.reinforcement.analysed) {
        r.histogram = stress_histogram_plot(r.reinforcement);
        r.stress_map = surface_stress_map(r.reinforcement.fem, r.reinforcement.final_report, opt.up);
    }
    r.seconds.previews = dp::since(t);

    r.instances_per_class.assign(classes.size(), 0);
    for (const surface_instance& in : r.synthesis.instances) ++r.instances_per_class[in.shape.cls];
    r.seconds.total = dp::since(t_start);
    report_progress(progress, 1.0, "done");
    return r;
}

/// A filigree on `mesh` (mm) in one call: the base (region, direction and scale fields) from the
/// options, then the surface pipeline above.
template <progress_callback P = no_progress>
[[nodiscard]] surface_filigree make_filigree(std::span<const element> classes, std::span<const double> weights, const triangle_mesh& mesh,
                                             const surface_filigree_options& opt = {}, P&& progress = {}) {
    const auto t_start = detail::pipeline::clock::now();
    report_progress(progress, 0.0, "region and fields");
    const surface_filigree_base base(mesh, opt);
    surface_filigree r = make_filigree(classes, weights, base, opt, progress);
    r.seconds.total = detail::pipeline::since(t_start);
    return r;
}

}  // namespace fabsynth::filigree
