// SPDX-License-Identifier: MIT
#pragma once
/// @file inp.hpp  Reader for the linear-static subset of Abaqus / CalculiX .inp decks.
///
/// Supported keywords and parameters (case-insensitive; "**" starts a comment line):
///   *HEADING
///   *NODE [,NSET=n]                        id[, x[, y[, z]]]   (empty or missing coordinates are 0,
///                                          as in CalculiX; further columns must be empty or 0)
///   *ELEMENT, TYPE=C3D8|C3D6|S3 [,ELSET=e]  id, n1, ..., nk (lines ending in ',' continue)
///   *NSET, NSET=n [,GENERATE]   *ELSET, ELSET=e [,GENERATE]    ids or set names / first, last[, inc]
///   *MATERIAL, NAME=m
///   *ELASTIC [,TYPE=ISO|ISOTROPIC]         one row: E, nu[, temperature]
///   *DENSITY                               one row: rho[, temperature]
///   *SOLID SECTION, ELSET=e, MATERIAL=m     *SHELL SECTION, ELSET=e, MATERIAL=m: thickness
///   *STEP [,NLGEOM=NO] [,INC=n], *STATIC [,SOLVER=s], *END STEP   one linear static step
///   *BOUNDARY [,OP=MOD] [,TYPE=DISPLACEMENT]  node|nset, first_dof[, last_dof[, value]]   or
///               node|nset, ENCASTRE|PINNED|XSYMM|YSYMM|ZSYMM|XASYMM|YASYMM|ZASYMM
///               (rotational DOFs skipped on solid nodes)
///   *CLOAD [,OP=MOD]  node|nset, dof, magnitude          (repeated loads on one dof add up, as in CalculiX)
///   *DLOAD [,OP=MOD]  element|elset, GRAV, g, nx, ny, nz (g [mm/s^2] along the normalised direction)
///                     element|elset, P, pressure         (S3 shells only; CalculiX's sign: positive P pushes
///                                                       along the normal, so it is read as pressure_load -P)
///   *NODE PRINT, *EL PRINT, *NODE FILE, *EL FILE: output requests, accepted and ignored with their
///   parameters and data lines.
/// The reader says yes only to what it honours: any other keyword, any other parameter (USER,
/// SUBMODEL, AMPLITUDE, OP=NEW, ORIENTATION, OFFSET, INPUT, ...), any data column it would not use and
/// any data line it cannot honour throws io_error naming the file, line, keyword and parameter or
/// column. Temperature-dependent tables (a second *ELASTIC or *DENSITY row) are refused: CalculiX
/// would interpolate them at the initial temperature, which this linear reader does not model. A
/// single row with a temperature is honoured (it holds at every temperature, as in CalculiX). STEP
/// INC= (the increment limit) and STATIC SOLVER= (CalculiX's choice of linear solver) cannot change a
/// linear static solution and are accepted. A number above 1e30 in magnitude is refused too (it
/// would overflow the element integrals). DOFs in decks are 1-based (1-3 = ux..uz,
/// 4-6 = rx..rz); fem::load_case uses 0-based DOFs and 0-based node/element indices.
/// Units are whatever the deck uses; fabsynth assumes mm, N, MPa, t/mm^3, s.
///
/// Usage:
///   fabsynth::fem::inp_deck d = fabsynth::fem::parse_inp(text, "cantilever.inp");
///   auto r = fabsynth::fem::solve_linear_static(d.model, d.loads);
///   // d.model.node_ids / element_ids hold the deck's numbers for output.
#include <algorithm>
#include <charconv>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/fem/boundary.hpp"
#include "fabsynth/fem/mesh.hpp"

namespace fabsynth::fem {

/// A parsed deck: the model (mesh with the deck's node/element numbers as labels), the load case,
/// the named sets (upper-case names -> 0-based indices) and the heading text.
struct inp_deck {
    mesh model;
    load_case loads;
    std::map<std::string, std::vector<std::uint32_t>> node_sets, element_sets;
    std::string heading;
    std::vector<std::string> ignored_keywords;  ///< keywords accepted without effect (output requests)
};

namespace detail {

inline std::string upper(std::string_view s) {
    std::string r(s);
    for (char& c : r) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return r;
}
inline std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}
inline std::vector<std::string_view> split_commas(std::string_view s) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= s.size(); ++i)
        if (i == s.size() || s[i] == ',') out.push_back(trim(s.substr(start, i - start))), start = i + 1;
    return out;
}

class inp_parser {
public:
    inp_parser(std::string_view text, std::string_view file) : text_(text), file_(file) {}

    inp_deck run() {
        std::size_t pos = 0;
        std::string kw;
        std::map<std::string, std::string> params;
        while (pos <= text_.size()) {
            const std::size_t eol = std::min(text_.find('\n', pos), text_.size());
            std::string_view line = text_.substr(pos, eol - pos);
            ++line_;
            pos = eol + 1;
            if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
            if (line.find('\0') != std::string_view::npos) fail("NUL byte in text");
            const std::string_view t = trim(line);
            if (t.empty() || t.starts_with("**")) {
                if (eol == text_.size()) break;
                continue;
            }
            if (t.front() == '*') {
                finish_block(kw);
                const auto parts = split_commas(t.substr(1));
                kw = upper(parts[0]);
                params.clear();
                for (std::size_t i = 1; i < parts.size(); ++i) {
                    if (parts[i].empty()) continue;
                    const auto eq = parts[i].find('=');
                    const std::string key = upper(trim(parts[i].substr(0, eq)));
                    params[key] = eq == std::string_view::npos ? std::string() : std::string(trim(parts[i].substr(eq + 1)));
                }
                begin_block(kw, params);
            } else {
                if (kw.empty()) fail("data line before any keyword");
                data_line(kw, params, t);
            }
            if (eol == text_.size()) break;
        }
        finish_block(kw);
        if (in_step_) fail("*STEP without *END STEP");
        return finish();
    }

private:
    struct raw_bc { std::size_t line; std::string target; int first, last; double value; };
    struct raw_cload { std::size_t line; std::string target; int dof; double value; };
    struct raw_dload { std::size_t line; std::string target; bool grav; vec3 acc; double p; };
    struct raw_section { std::size_t line; std::string elset, material; bool shell; double thickness; bool has_thickness; };

    std::string_view text_, file_;
    std::size_t line_ = 0;
    inp_deck d_;
    std::unordered_map<std::int64_t, std::uint32_t> node_index_, elem_index_;
    std::map<std::string, isotropic_material> materials_;
    std::map<std::string, std::pair<bool, bool>> material_has_;  // (elastic, density) seen
    std::string current_material_;
    std::vector<raw_section> sections_;
    std::vector<raw_bc> bcs_;
    std::vector<raw_cload> cloads_;
    std::vector<raw_dload> dloads_;
    int steps_ = 0;
    bool in_step_ = false;
    // block state
    element_kind etype_ = element_kind::hex8;
    std::string set_name_;
    bool generate_ = false;
    std::vector<std::string_view> pending_;  // element tokens across continuation lines
    bool section_data_seen_ = false;
    int rows_ = 0;  // data rows of the current *ELASTIC / *DENSITY block

    [[noreturn]] void fail(std::string_view what) const {
        if (what.starts_with("fabsynth: ")) what.remove_prefix(10);  // re-located library error
        throw io_error(file_, line_, what);
    }

    static constexpr double max_magnitude = 1e30;
    double number(std::string_view s, const char* what) const {
        double v = 0;
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v))
            fail(std::string("expected a finite number for ") + what + ", got '" + std::string(s) + "'");
        // element integrals take products and cubes of these (det J ~ size^3, K ~ E size): refuse
        // what would overflow there, here where the line is known
        if (std::abs(v) > max_magnitude)
            fail(std::string(what) + " = " + std::string(s) + " is out of range (|value| <= 1e30)");
        return v;
    }
    std::int64_t integer(std::string_view s, const char* what) const {
        std::int64_t v = 0;
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size())
            fail(std::string("expected an integer for ") + what + ", got '" + std::string(s) + "'");
        return v;
    }
    /// Integer in [lo, hi] (checked before narrowing).
    int small_int(std::string_view s, const char* what, int lo, int hi) const {
        const std::int64_t v = integer(s, what);
        if (v < lo || v > hi) fail(std::string(what) + " must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + std::to_string(v));
        return static_cast<int>(v);
    }
    static bool is_integer(std::string_view s) {
        std::int64_t v = 0;
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
        return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
    }
    std::string param(const std::map<std::string, std::string>& p, const char* key, const std::string& kw) const {
        const auto it = p.find(key);
        if (it == p.end() || it->second.empty()) fail("*" + kw + " needs the parameter " + key + "=");
        return it->second;
    }

    /// Refuses any parameter of `kw` outside `allowed`, naming it (and what is supported).
    void only_parameters(const std::string& kw, const std::map<std::string, std::string>& p,
                         std::initializer_list<const char*> allowed) const {
        for (const auto& entry : p) {  // not a structured binding: clang 14 cannot capture one in the lambda
            const std::string& key = entry.first;
            const std::string& value = entry.second;
            if (std::find_if(allowed.begin(), allowed.end(), [&key](const char* a) { return key == a; }) != allowed.end()) continue;
            std::string supported;
            for (const char* a : allowed) supported += std::string(supported.empty() ? "" : ", ") + a;
            fail("*" + kw + " parameter " + key + (value.empty() ? "" : "=" + value) + " is not supported" +
                 (supported.empty() ? " (*" + kw + " takes no parameters)" : " (supported: " + supported + ")"));
        }
    }
    /// OP=MOD is CalculiX's default for loads and boundary conditions; OP=NEW would remove those of
    /// earlier steps, which a one-step reader does not keep apart, so it is refused.
    void op_mod_only(const std::string& kw, const std::map<std::string, std::string>& p) const {
        const auto it = p.find("OP");
        if (it != p.end() && upper(it->second) != "MOD") fail("*" + kw + " parameter OP=" + it->second + " is not supported (only OP=MOD)");
    }

    void begin_block(const std::string& kw, const std::map<std::string, std::string>& p) {
        generate_ = p.count("GENERATE") > 0;
        set_name_.clear();
        pending_.clear();
        section_data_seen_ = false;
        rows_ = 0;
        if (kw != "ELASTIC" && kw != "DENSITY") current_material_.clear();  // material data ends at any other keyword
        if (kw == "HEADING") return only_parameters(kw, p, {});
        if (kw == "NODE") {
            only_parameters(kw, p, {"NSET"});
            if (p.count("NSET")) set_name_ = upper(p.at("NSET")), d_.node_sets[set_name_];
            return;
        }
        if (kw == "ELEMENT") {
            only_parameters(kw, p, {"TYPE", "ELSET"});
            const std::string type = upper(param(p, "TYPE", kw));
            if (type == "C3D8") etype_ = element_kind::hex8;
            else if (type == "C3D6") etype_ = element_kind::wedge6;
            else if (type == "S3") etype_ = element_kind::shell3;
            else fail("*ELEMENT TYPE=" + type + " is not supported (supported: C3D8, C3D6, S3)");
            if (p.count("ELSET")) set_name_ = upper(p.at("ELSET")), d_.element_sets[set_name_];
            return;
        }
        if (kw == "NSET" || kw == "ELSET") only_parameters(kw, p, {kw == "NSET" ? "NSET" : "ELSET", "GENERATE"});
        if (kw == "NSET") { set_name_ = upper(param(p, "NSET", kw)); d_.node_sets[set_name_]; return; }
        if (kw == "ELSET") { set_name_ = upper(param(p, "ELSET", kw)); d_.element_sets[set_name_]; return; }
        if (kw == "MATERIAL") {
            only_parameters(kw, p, {"NAME"});
            current_material_ = upper(param(p, "NAME", kw));
            if (materials_.count(current_material_)) fail("material " + current_material_ + " is defined twice");
            materials_[current_material_] = {};
            material_has_[current_material_] = {false, false};
            return;
        }
        if (kw == "ELASTIC" || kw == "DENSITY") {
            if (current_material_.empty()) fail("*" + kw + " outside a *MATERIAL");
            if (kw == "DENSITY") return only_parameters(kw, p, {});
            only_parameters(kw, p, {"TYPE"});
            if (p.count("TYPE") && upper(p.at("TYPE")) != "ISOTROPIC" && upper(p.at("TYPE")) != "ISO")
                fail("*ELASTIC TYPE=" + p.at("TYPE") + " is not supported (only ISO / ISOTROPIC)");
            if (material_has_[current_material_].first) fail("material " + current_material_ + " has a second *ELASTIC");
            return;
        }
        if (kw == "SOLID SECTION" || kw == "SHELL SECTION") {
            only_parameters(kw, p, {"ELSET", "MATERIAL"});
            sections_.push_back({line_, upper(param(p, "ELSET", kw)), upper(param(p, "MATERIAL", kw)), kw == "SHELL SECTION", 0, false});
            return;
        }
        if (kw == "STEP") {
            if (in_step_) fail("*STEP inside another *STEP");
            only_parameters(kw, p, {"NLGEOM", "INC"});
            if (p.count("INC")) integer(p.at("INC"), "*STEP INC");
            if (++steps_ > 1) fail("only one *STEP is supported");
            if (p.count("NLGEOM") && upper(p.at("NLGEOM")) != "NO") fail("*STEP NLGEOM=YES is not supported (linear analysis only)");
            in_step_ = true;
            return;
        }
        if (kw == "STATIC") {
            if (!in_step_) fail("*STATIC outside *STEP");
            only_parameters(kw, p, {"SOLVER"});
            return;
        }
        if (kw == "END STEP") {
            only_parameters(kw, p, {});
            if (!in_step_) fail("*END STEP without *STEP");
            in_step_ = false;
            return;
        }
        if (kw == "BOUNDARY" || kw == "CLOAD" || kw == "DLOAD") {
            if (p.count("AMPLITUDE")) fail("*" + kw + " parameter AMPLITUDE= is not supported (static analysis)");
            if (kw == "BOUNDARY") only_parameters(kw, p, {"OP", "TYPE"});
            else only_parameters(kw, p, {"OP"});
            if (p.count("TYPE") && upper(p.at("TYPE")) != "DISPLACEMENT") fail("*" + kw + " parameter TYPE=" + p.at("TYPE") + " is not supported (only DISPLACEMENT)");
            op_mod_only(kw, p);
            return;
        }
        if (kw == "NODE PRINT" || kw == "EL PRINT" || kw == "NODE FILE" || kw == "EL FILE") {
            d_.ignored_keywords.push_back("*" + kw);
            return;
        }
        fail("unsupported keyword *" + kw);
    }

    void data_line(const std::string& kw, const std::map<std::string, std::string>&, std::string_view t) {
        auto f = split_commas(t);
        if (kw == "HEADING") {
            if (!d_.heading.empty()) d_.heading += '\n';
            d_.heading += std::string(t);
            return;
        }
        if (kw == "NODE PRINT" || kw == "EL PRINT" || kw == "NODE FILE" || kw == "EL FILE") return;
        if (kw == "STEP" || kw == "END STEP") fail("unexpected data line after *" + kw);
        if (kw == "STATIC") return;  // time increments: irrelevant for a linear static step
        if (!f.empty() && f.back().empty() && kw != "ELEMENT") f.pop_back();  // trailing comma
        if (kw == "NODE") {
            // CalculiX reads id, x, y, z and takes an empty or missing coordinate as 0; it ignores
            // further columns, which are refused here unless they hold nothing (empty or 0), so a
            // misplaced coordinate is never dropped silently.
            if (f.empty()) fail("*NODE line needs: id[, x[, y[, z]]]");
            const std::int64_t id = integer(f[0], "node id");
            if (id <= 0) fail("node id must be positive, got " + std::to_string(id));
            const auto coordinate = [&](std::size_t i, const char* what) { return i < f.size() && !f[i].empty() ? number(f[i], what) : 0.0; };
            for (std::size_t i = 4; i < f.size(); ++i)
                if (!f[i].empty() && number(f[i], "*NODE column") != 0.0)
                    fail("*NODE column " + std::to_string(i + 1) + " ('" + std::string(f[i]) + "') is not read: a node line is id, x, y, z");
            const vec3 x(coordinate(1, "x"), coordinate(2, "y"), coordinate(3, "z"));
            if (!node_index_.emplace(id, static_cast<std::uint32_t>(d_.model.nodes.size())).second)
                fail("node " + std::to_string(id) + " is defined twice");
            if (d_.model.nodes.size() >= 0xffffffffu) fail("too many nodes");
            if (!set_name_.empty()) d_.node_sets[set_name_].push_back(static_cast<std::uint32_t>(d_.model.nodes.size()));
            d_.model.nodes.push_back(x);
            d_.model.node_ids.push_back(id);
            return;
        }
        if (kw == "ELEMENT") {
            const std::size_t need = 1 + static_cast<std::size_t>(num_nodes(etype_));
            const bool cont = !f.empty() && f.back().empty();
            if (cont) f.pop_back();
            pending_.insert(pending_.end(), f.begin(), f.end());
            if (cont && pending_.size() < need) return;
            if (pending_.size() != need)
                fail(std::string("*ELEMENT TYPE=") + kind_name(etype_) + " line needs an id and " + std::to_string(need - 1) +
                     " node ids, got " + std::to_string(pending_.size()) + " values");
            const std::int64_t id = integer(pending_[0], "element id");
            if (id <= 0) fail("element id must be positive, got " + std::to_string(id));
            element e;
            e.kind = etype_;
            e.section = 0xffffffffu;  // assigned by a section later
            for (std::size_t a = 1; a < need; ++a) {
                const std::int64_t nid = integer(pending_[a], "node id");
                const auto it = node_index_.find(nid);
                if (it == node_index_.end()) fail("element " + std::to_string(id) + " references undefined node " + std::to_string(nid));
                e.nodes[a - 1] = it->second;
            }
            pending_.clear();
            if (!elem_index_.emplace(id, static_cast<std::uint32_t>(d_.model.elements.size())).second)
                fail("element " + std::to_string(id) + " is defined twice");
            if (!set_name_.empty()) d_.element_sets[set_name_].push_back(static_cast<std::uint32_t>(d_.model.elements.size()));
            d_.model.elements.push_back(e);
            d_.model.element_ids.push_back(id);
            return;
        }
        if (kw == "NSET" || kw == "ELSET") {
            const bool nodes = kw == "NSET";
            auto& dst = nodes ? d_.node_sets[set_name_] : d_.element_sets[set_name_];
            const auto& index = nodes ? node_index_ : elem_index_;
            if (generate_) {
                if (f.size() < 2 || f.size() > 3) fail("*" + kw + ", GENERATE line needs: first, last[, increment]");
                const std::int64_t a = integer(f[0], "first"), b = integer(f[1], "last"), inc = f.size() > 2 ? integer(f[2], "increment") : 1;
                if (inc <= 0 || b < a) fail("*" + kw + ", GENERATE needs first <= last and increment > 0");
                if ((b - a) / inc > 10'000'000) fail("*" + kw + ", GENERATE range is too large (> 1e7 ids)");
                for (std::int64_t i = a; i <= b; i += inc) {
                    const auto it = index.find(i);
                    if (it == index.end()) fail(std::string(nodes ? "node " : "element ") + std::to_string(i) + " in *" + kw + " " + set_name_ + " is not defined");
                    dst.push_back(it->second);
                }
                return;
            }
            for (std::string_view s : f) {
                if (s.empty()) continue;
                const auto ids = resolve(s, nodes);
                dst.insert(dst.end(), ids.begin(), ids.end());
            }
            return;
        }
        if (kw == "ELASTIC") {
            if (++rows_ > 1)
                fail("*ELASTIC: a second row makes a temperature-dependent table, which is not supported; give one row E, nu[, temperature]");
            if (f.size() < 2 || f.size() > 3) fail("*ELASTIC, TYPE=ISO line needs: E, nu[, temperature], got " + std::to_string(f.size()) + " values");
            if (f.size() > 2 && !f[2].empty()) number(f[2], "temperature");
            materials_[current_material_].E = number(f[0], "E");
            materials_[current_material_].nu = number(f[1], "nu");
            material_has_[current_material_].first = true;
            return;
        }
        if (kw == "DENSITY") {
            if (++rows_ > 1)
                fail("*DENSITY: a second row makes a temperature-dependent table, which is not supported; give one row rho[, temperature]");
            if (f.empty() || f.size() > 2) fail("*DENSITY line needs: density[, temperature], got " + std::to_string(f.size()) + " values");
            if (f.size() > 1 && !f[1].empty()) number(f[1], "temperature");
            materials_[current_material_].density = number(f[0], "density");
            material_has_[current_material_].second = true;
            return;
        }
        if (kw == "SOLID SECTION" || kw == "SHELL SECTION") {
            if (section_data_seen_) fail("*" + kw + " takes at most one data line");
            section_data_seen_ = true;
            if (kw == "SHELL SECTION") {
                if (f.empty()) fail("*SHELL SECTION line needs: thickness");
                for (std::size_t i = 1; i < f.size(); ++i)
                    if (!f[i].empty()) fail("*SHELL SECTION column " + std::to_string(i + 1) + " ('" + std::string(f[i]) + "') is not supported: the line is the thickness");
                sections_.back().thickness = number(f[0], "shell thickness");
                sections_.back().has_thickness = true;
            } else if (std::any_of(f.begin(), f.end(), [](std::string_view v) { return !v.empty(); })) {
                fail("*SOLID SECTION data (a thickness) is only meaningful for 2D elements; remove it");
            }
            return;
        }
        if (kw == "BOUNDARY") {
            if (f.size() < 2 || f.size() > 4) fail("*BOUNDARY line needs: node|nset, first_dof[, last_dof[, value]] or node|nset, ENCASTRE|PINNED|...");
            if (!is_integer(f[1])) {
                const std::string type = upper(f[1]);
                static const std::map<std::string, std::vector<int>> shorthand = {
                    {"ENCASTRE", {1, 2, 3, 4, 5, 6}}, {"PINNED", {1, 2, 3}}, {"XSYMM", {1, 5, 6}}, {"YSYMM", {2, 4, 6}},
                    {"ZSYMM", {3, 4, 5}}, {"XASYMM", {2, 3, 4}}, {"YASYMM", {1, 3, 5}}, {"ZASYMM", {1, 2, 6}}};
                const auto it = shorthand.find(type);
                if (it == shorthand.end()) fail("*BOUNDARY type " + type + " is not supported");
                if (f.size() > 2) fail("*BOUNDARY " + type + " takes no further values");
                for (int dof : it->second) bcs_.push_back({line_, std::string(f[0]), -dof, -dof, 0.0});  // negative: skip if absent
                return;
            }
            const int first = small_int(f[1], "*BOUNDARY first dof", 1, 6);
            const int last = f.size() > 2 && !f[2].empty() ? small_int(f[2], "*BOUNDARY last dof", 1, 6) : first;
            const double value = f.size() > 3 ? number(f[3], "prescribed value") : 0.0;
            if (first < 1 || last > 6 || last < first) fail("*BOUNDARY dofs must satisfy 1 <= first <= last <= 6");
            for (int dof = first; dof <= last; ++dof) bcs_.push_back({line_, std::string(f[0]), dof, dof, value});
            return;
        }
        if (kw == "CLOAD") {
            if (f.size() != 3) fail("*CLOAD line needs: node|nset, dof, magnitude");
            const int dof = small_int(f[1], "*CLOAD dof", 1, 6);
            cloads_.push_back({line_, std::string(f[0]), dof, number(f[2], "magnitude")});
            return;
        }
        if (kw == "DLOAD") {
            if (f.size() < 3) fail("*DLOAD line needs: element|elset, GRAV, g, nx, ny, nz or element|elset, P, pressure");
            const std::string type = upper(f[1]);
            if (type == "GRAV") {
                if (f.size() != 6) fail("*DLOAD GRAV needs: element|elset, GRAV, g, nx, ny, nz");
                const double g = number(f[2], "g");
                vec3 n(number(f[3], "nx"), number(f[4], "ny"), number(f[5], "nz"));
                const double len = glm::length(n);
                if (!(len > 0)) fail("*DLOAD GRAV direction is the zero vector");
                dloads_.push_back({line_, std::string(f[0]), true, g * n / len, 0.0});
            } else if (type == "P") {
                if (f.size() != 3) fail("*DLOAD P needs: element|elset, P, pressure");
                dloads_.push_back({line_, std::string(f[0]), false, vec3(0.0), number(f[2], "pressure")});
            } else {
                fail("*DLOAD type " + type + " is not supported (GRAV, and P on S3 shells)");
            }
            return;
        }
        fail("unexpected data line for *" + kw);
    }

    void finish_block(const std::string& kw) {
        if (kw == "ELEMENT" && !pending_.empty()) fail("*ELEMENT line continued with ',' but the next line is not data");
        if (kw == "SHELL SECTION" && !sections_.back().has_thickness) fail("*SHELL SECTION needs a data line with the thickness");
    }

    std::vector<std::uint32_t> resolve(std::string_view s, bool nodes) const {
        if (is_integer(s)) {
            const std::int64_t id = integer(s, nodes ? "node id" : "element id");
            const auto& index = nodes ? node_index_ : elem_index_;
            const auto it = index.find(id);
            if (it == index.end()) fail(std::string(nodes ? "node " : "element ") + std::to_string(id) + " is not defined");
            return {it->second};
        }
        const auto& sets = nodes ? d_.node_sets : d_.element_sets;
        const auto it = sets.find(upper(s));
        if (it == sets.end()) fail(std::string(nodes ? "node set " : "element set ") + upper(s) + " is not defined");
        return it->second;
    }

    inp_deck finish() {
        mesh& m = d_.model;
        // Sections -> per-element section index; sections are deduplicated by (material, thickness).
        for (const auto& s : sections_) {
            line_ = s.line;
            const auto mit = materials_.find(s.material);
            if (mit == materials_.end()) fail("section references undefined material " + s.material);
            if (!material_has_[s.material].first) fail("material " + s.material + " has no *ELASTIC data");
            try {
                mit->second.validate();
            } catch (const invalid_input& e) {
                fail("material " + s.material + ": " + std::string(std::string_view(e.what()).substr(10)));
            }
            if (s.shell && !(s.thickness > 0)) fail("*SHELL SECTION thickness must be > 0");
            const auto eit = d_.element_sets.find(s.elset);
            if (eit == d_.element_sets.end()) fail("section references undefined element set " + s.elset);
            section sec{mit->second, s.shell ? s.thickness : 0.0};
            std::uint32_t idx = 0;
            while (idx < m.sections.size() && !(m.sections[idx].material == sec.material && m.sections[idx].thickness == sec.thickness)) ++idx;
            if (idx == m.sections.size()) m.sections.push_back(sec);
            for (std::uint32_t e : eit->second) {
                const bool shell = m.elements[e].kind == element_kind::shell3;
                if (shell != s.shell)
                    fail(std::string(s.shell ? "*SHELL SECTION" : "*SOLID SECTION") + " assigned to " + kind_name(m.elements[e].kind) +
                         " element " + std::to_string(m.element_label(e)));
                m.elements[e].section = idx;
            }
        }
        line_ = 0;
        for (std::size_t e = 0; e < m.elements.size(); ++e)
            if (m.elements[e].section == 0xffffffffu)
                fail("element " + std::to_string(m.element_label(e)) + " has no *SOLID SECTION / *SHELL SECTION");
        const dof_map dofs(m);
        for (const auto& b : bcs_) {
            line_ = b.line;
            const bool optional = b.first < 0;
            const int dof = (optional ? -b.first : b.first) - 1;
            for (std::uint32_t n : resolve(b.target, true)) {
                if (dof >= dofs.count[n]) {
                    if (optional) continue;
                    fail("*BOUNDARY: node " + std::to_string(m.node_label(n)) + " has no dof " + std::to_string(dof + 1) +
                         (dofs.count[n] ? " (solid nodes have dofs 1-3)" : " (no element uses it)"));
                }
                d_.loads.fixed.push_back({n, dof, b.value});
            }
        }
        for (const auto& c : cloads_) {
            line_ = c.line;
            for (std::uint32_t n : resolve(c.target, true)) {
                if (c.dof > dofs.count[n])
                    fail("*CLOAD: node " + std::to_string(m.node_label(n)) + " has no dof " + std::to_string(c.dof));
                d_.loads.forces.push_back({n, c.dof - 1, c.value});
            }
        }
        for (const auto& l : dloads_) {
            line_ = l.line;
            for (std::uint32_t e : resolve(l.target, false)) {
                if (l.grav) {
                    if (m.sections[m.elements[e].section].material.density <= 0)
                        fail("*DLOAD GRAV on element " + std::to_string(m.element_label(e)) + " whose material has no *DENSITY");
                    d_.loads.gravity.push_back({e, l.acc});
                } else {
                    if (m.elements[e].kind != element_kind::shell3)
                        fail(std::string("*DLOAD P on ") + kind_name(m.elements[e].kind) + " element " + std::to_string(m.element_label(e)) +
                             " is not supported (pressure only on S3 shells)");
                    d_.loads.pressures.push_back({e, -l.p});  // CalculiX: +P along the normal; pressure_load: against it
                }
            }
        }
        if (m.elements.empty()) fail("the deck defines no elements");
        try {
            m.validate();
        } catch (const invalid_input& e) {
            fail(e.what());
        }
        return std::move(d_);
    }
};

}  // namespace detail

/// Parses an .inp deck held in memory. `file` names it in error messages.
/// Throws io_error "FILE:LINE: what" for anything it cannot honour.
[[nodiscard]] inline inp_deck parse_inp(std::string_view text, std::string_view file = "<inp>") {
    return detail::inp_parser(text, file).run();
}

}  // namespace fabsynth::fem
