// SPDX-License-Identifier: MIT
#pragma once
// The step between a tool's mesh and its files: simplification with guarantees
// (geometry/simplify.hpp), one option pair and one report for every tool that writes a mesh.
//
//   tool::mesh_simplification simplify(app, 0.05, "0.05 mm");   // --mesh-tolerance, --no-simplify
//   ...
//   const triangle_mesh out = simplify(raw, common, "pattern.stl");   // prints, warns, reports
//   io::write_stl(file, out);
//
// The option is --mesh-tolerance, not --tolerance: curve_patterns and filigree already use
// --tolerance for the approximation of their input curves.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <fabsynth/geometry/simplify.hpp>

#include "tool.hpp"

namespace fabsynth::tool {

class mesh_simplification {
public:
    /// Adds --mesh-tolerance (default `default_mm`, described as `default_text`) and --no-simplify.
    mesh_simplification(CLI::App& app, double default_mm, const std::string& default_text) : tolerance_(default_mm) {
        option_ = app.add_option("--mesh-tolerance", tolerance_,
                       "simplify written meshes within this distance of the extracted surface (two-sided Hausdorff), mm; default " +
                           default_text)
            ->check(CLI::PositiveNumber);
        app.add_flag("--no-simplify", off_, "write meshes as extracted, without simplification");
    }

    /// Changes the default once it is known (e.g. half the voxel size), unless the user gave one.
    void default_tolerance(double mm) {
        if (option_->count() == 0) tolerance_ = mm;
    }
    [[nodiscard]] double tolerance() const noexcept { return tolerance_; }
    [[nodiscard]] bool enabled() const noexcept { return !off_; }

    /// The mesh to write for `raw`, named `file` in the messages: simplified unless --no-simplify;
    /// prints a line, warns when the raw mesh is kept, and adds {"file", "raw_triangles",
    /// "triangles", "simplified", "tolerance_mm", "hausdorff_mm" (certified bound),
    /// "hausdorff_measured_mm", "runs" (decimation passes, 0 with --no-simplify), "seconds"} to
    /// the JSON summary's "meshes" list.
    [[nodiscard]] triangle_mesh operator()(const triangle_mesh& raw, common& c, const std::string& file) {
        simplify_report rep;
        rep.raw_faces = rep.faces = raw.faces.size();
        rep.tolerance = tolerance_;
        const auto t0 = std::chrono::steady_clock::now();
        triangle_mesh out = off_ ? raw : simplify_mesh(raw, {.tolerance = tolerance_}, &rep);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!off_ && !rep.simplified) c.warn(file + ": " + rep.warning);
        char line[256];
        if (rep.simplified)
            std::snprintf(line, sizeof line, "%s: %zu -> %zu triangles, Hausdorff %.3g mm (bound %.3g, tolerance %.3g), %d run%s, %.2f s", file.c_str(),
                          rep.raw_faces, rep.faces, rep.hausdorff.lower, rep.hausdorff.upper, tolerance_, rep.attempts, rep.attempts == 1 ? "" : "s", seconds);
        else
            std::snprintf(line, sizeof line, "%s: %zu triangles, not simplified", file.c_str(), rep.raw_faces);
        if (!c.quiet()) c.say(line);
        meshes_.push_back({{"file", file},
                           {"raw_triangles", rep.raw_faces},
                           {"triangles", rep.faces},
                           {"simplified", rep.simplified},
                           {"tolerance_mm", off_ ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(tolerance_)},
                           {"hausdorff_mm", rep.hausdorff.upper},
                           {"hausdorff_measured_mm", rep.hausdorff.lower},
                           {"runs", rep.attempts},
                           {"seconds", seconds}});
        c.summary({{"meshes", meshes_}});
        source_ = std::move(rep.source);
        return out;
    }

    /// Colour of each face of the mesh the last call returned, from `raw_colours` (one per vertex
    /// of the raw mesh it was given): the colour two or three corners share, else corner 0's.
    [[nodiscard]] std::vector<std::array<std::uint8_t, 3>> face_colours(const triangle_mesh& written,
                                                                      const std::vector<std::array<std::uint8_t, 3>>& raw_colours) const {
        std::vector<std::array<std::uint8_t, 3>> out;
        if (raw_colours.empty()) return out;
        out.reserve(written.faces.size());
        const auto colour = [&](std::uint32_t v) { return raw_colours.at(source_.empty() ? v : source_.at(v)); };
        for (const auto& t : written.faces) {
            const auto a = colour(t[0]), b = colour(t[1]), c = colour(t[2]);
            out.push_back(b == c ? b : a);
        }
        return out;
    }

    /// The "meshes" list so far (for a tool's own report file).
    [[nodiscard]] const nlohmann::ordered_json& report() const noexcept { return meshes_; }

private:
    CLI::Option* option_ = nullptr;
    double tolerance_;
    bool off_ = false;
    nlohmann::ordered_json meshes_ = nlohmann::ordered_json::array();
    std::vector<std::uint32_t> source_;  // of the last call: raw vertex of each written vertex (empty: the same mesh)
};

}  // namespace fabsynth::tool
