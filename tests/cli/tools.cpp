// The tool convention (docs/tools.md) checked on every tool: exit codes for bad arguments, bad
// files, impossible requests; --json parsed by a JSON parser; --version; no progress control
// characters in a non-terminal stderr; nothing left at the output path after a refused run.
// Tools run as child processes (stdout and stderr to files, stdin closed).
#include <cstdio>
#include <catch2/catch.hpp>
#include <fabsynth/geometry/hausdorff.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/geometry/self_intersection.hpp>
#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/vtk.hpp>
#if defined(FABSYNTH_HAS_LIB3MF)
#include <fabsynth/io/mesh_3mf.hpp>
#endif
#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cli_util.hpp"

namespace {

// --version, --help with defaults, an unknown option, and --json on a failing run.
void check_common(const std::string& tool, const std::vector<std::string>& failing_args, int failing_code) {
    const result v = run(tool, {"--version"});
    CHECK(v.code == 0);
    CHECK(v.out.rfind("fabsynth ", 0) == 0);
    const result h = run(tool, {"--help"});
    CHECK(h.code == 0);
    CHECK(h.out.find("--json") != std::string::npos);
    std::vector<std::string> args = failing_args;
    args.push_back("--no-such-option");
    check_case(tool, {"unknown option", args, 2, "--no-such-option"});
    args = failing_args;
    args.push_back("--json");
    const result f = run(tool, args);
    CHECK(f.code == failing_code);
    const json j = json::parse(f.out);  // throws (fails the test) on invalid JSON
    CHECK(j.at("tool") == tool);
    CHECK(j.at("status") == "error");
    CHECK(j.at("exit_code") == failing_code);
    CHECK(j.at("message").get<std::string>().rfind("fabsynth:", 0) == 0);
}

}  // namespace

TEST_CASE("voxelize follows the tool convention", "[cli][voxelize]") {
    const std::string bad_obj = write_file("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
    const std::string out = (work_dir / "vox_out").string();
    fs::remove_all(out);
    for (const cli_case& c : std::vector<cli_case>{
             {"missing input", {(work_dir / "none.obj").string(), "-o", out}, 5, "does not exist"},
             {"malformed mesh", {bad_obj, "-o", out}, 5, "bad.obj"},
             {"resolution out of range", {(data_dir / "meshes/bunny_lowres.obj").string(), "-r", "0", "-o", out}, 2, "--resolution"},
             {"missing output", {(data_dir / "meshes/bunny_lowres.obj").string()}, 2, "--output"},
         })
        check_case("voxelize", c);
    CHECK_FALSE(fs::exists(out));
    check_common("voxelize", {bad_obj, "-o", out}, 5);

    const result ok = run("voxelize", {(data_dir / "meshes/bunny_lowres.obj").string(), "-r", "24", "-o", out, "--json"});
    REQUIRE(ok.code == 0);
    const json j = json::parse(ok.out);
    CHECK(j.at("status") == "ok");
    CHECK(j.at("watertight") == true);
    CHECK(j.at("grid").size() == 3);
    CHECK(j.at("shell_voxels").get<long>() > 0);
    CHECK(fs::exists(fs::path(out) / "solid.stl"));
    const result quiet = run("voxelize", {(data_dir / "meshes/bunny_lowres.obj").string(), "-r", "16", "-o", out, "--quiet"});
    CHECK(quiet.code == 0);
    CHECK(quiet.err.empty());
}

TEST_CASE("written meshes are simplified within --mesh-tolerance, keeping watertightness, components and genus",
          "[cli][voxelize][simplify]") {
    // voxelize the kitten (genus 1) at a grid whose voxel staircase simplifies well
    const std::string mesh = (data_dir / "meshes/kitten_lowres.obj").string();
    const std::string raw_dir = (work_dir / "simplify_raw").string(), small_dir = (work_dir / "simplify_small").string();
    fs::remove_all(raw_dir), fs::remove_all(small_dir);
    const result raw = run("voxelize", {mesh, "-r", "48", "--no-simplify", "-o", raw_dir, "--json"});
    REQUIRE(raw.code == 0);
    const result small = run("voxelize", {mesh, "-r", "48", "-o", small_dir, "--json"});
    REQUIRE(small.code == 0);
    const json jr = json::parse(raw.out), js = json::parse(small.out);
    const json& mr = jr.at("meshes").at(0);
    const json& ms = js.at("meshes").at(0);
    CHECK(mr.at("simplified") == false);
    CHECK(mr.at("raw_triangles") == mr.at("triangles"));
    CHECK(ms.at("file") == "solid.stl");
    REQUIRE(ms.at("simplified") == true);
    const double voxel = js.at("voxel_mm").get<double>(), tol = ms.at("tolerance_mm").get<double>();
    CHECK(tol == Approx(0.5 * voxel));  // the default: half a voxel

    const fabsynth::triangle_mesh a = fabsynth::io::read_mesh(fs::path(raw_dir) / "solid.stl"), b = fabsynth::io::read_mesh(fs::path(small_dir) / "solid.stl");
    CHECK(ms.at("raw_triangles").get<std::size_t>() == a.faces.size());
    CHECK(ms.at("triangles").get<std::size_t>() == b.faces.size());
    CHECK(b.faces.size() * 3 < a.faces.size());
    const fabsynth::mesh_topology_info ta = fabsynth::analyze_topology(a), tb = fabsynth::analyze_topology(b);
    CHECK(tb.is_watertight());
    CHECK(tb.components == ta.components);
    CHECK(tb.genus == ta.genus);
    CHECK(tb.genus == 1);
    CHECK(fabsynth::find_self_intersections(b).pairs == 0);
    // the distance, measured here on the files (float coordinates), within the stated tolerance
    const fabsynth::hausdorff_interval h = fabsynth::hausdorff_distance(a, b, {.precision = tol / 8, .stop_below = tol});
    CHECK(h.upper <= tol * (1 + 1e-4));
    CHECK(ms.at("hausdorff_mm").get<double>() <= tol);
    CHECK(h.lower <= ms.at("hausdorff_mm").get<double>() + 1e-4 * tol);

    check_case("voxelize", {"zero tolerance", {mesh, "-r", "16", "--mesh-tolerance", "0", "-o", small_dir}, 2, "--mesh-tolerance"});
}

TEST_CASE("fem_solve follows the tool convention", "[cli][fem_solve]") {
    const std::string out = (work_dir / "fem_out").string();
    fs::remove_all(out);
    const std::string unsupported = write_file("contact.inp", "*NODE\n1, 0, 0, 0\n*CONTACT PAIR\n");
    const std::string unsupported_part = write_file(
        "floating.inp",
        "*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n5,0,0,1\n6,1,0,1\n7,1,1,1\n8,0,1,1\n*ELEMENT, TYPE=C3D8, ELSET=E\n1,1,2,3,4,5,6,7,8\n"
        "*MATERIAL, NAME=M\n*ELASTIC\n1000, 0.3\n*SOLID SECTION, ELSET=E, MATERIAL=M\n*STEP\n*STATIC\n*CLOAD\n7, 3, -1\n*END STEP\n");
    for (const cli_case& c : std::vector<cli_case>{
             {"missing deck", {(work_dir / "none.inp").string(), "-o", out}, 5, "does not exist"},
             {"unsupported keyword", {unsupported, "-o", out}, 5, "CONTACT PAIR"},
             {"unknown solver", {(data_dir / "fem/cantilever_c3d8.inp").string(), "-o", out, "--solver", "magic"}, 2, "--solver"},
             {"no supports: singular system", {unsupported_part, "-o", out}, 4, ""},
         })
        check_case("fem_solve", c);
    CHECK_FALSE(fs::exists(fs::path(out) / "displacements.csv"));
    check_common("fem_solve", {unsupported_part, "-o", out}, 4);

    const result ok = run("fem_solve", {(data_dir / "fem/cantilever_c3d8.inp").string(), "-o", out, "--json"});
    REQUIRE(ok.code == 0);
    const json j = json::parse(ok.out);
    CHECK(j.at("nodes") == 189);
    CHECK(j.at("elements") == 80);
    CHECK(j.at("max_displacement_mm").get<double>() > 0);
    CHECK(j.at("relative_residual").get<double>() < 1e-8);
}

TEST_CASE("homogenize follows the tool convention", "[cli][homogenize]") {
    std::string block = "# vtk DataFile Version 3.0\nblock\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 3 3 3\nORIGIN 0 0 0\n"
                        "SPACING 1 1 1\nPOINT_DATA 27\nSCALARS density double 1\nLOOKUP_TABLE default\n";
    for (int i = 0; i < 27; ++i) block += "1\n";
    const std::string grid = write_file("block.vtk", block);
    const std::string preview = (work_dir / "hom_preview.png").string();
    fs::remove(preview);
    const std::string truncated = write_file("truncated.vtk", block.substr(0, block.size() - 20));
    for (const cli_case& c : std::vector<cli_case>{
             {"missing grid", {(work_dir / "none.vtk").string()}, 5, "does not exist"},
             {"truncated grid", {truncated, "--preview", preview}, 5, "truncated.vtk"},
             {"no such field", {grid, "--field", "stiffness"}, 2, "stiffness"},
             {"unknown solver", {grid, "--solver", "magic"}, 2, ""},
         })
        check_case("homogenize", c);
    CHECK_FALSE(fs::exists(preview));
    check_common("homogenize", {grid, "--field", "stiffness"}, 2);

    const result ok = run("homogenize", {grid, "--E", "200", "--nu", "0.3", "--json"});
    REQUIRE(ok.code == 0);
    const json j = json::parse(ok.out);
    CHECK(j.at("E").get<double>() == Approx(200).epsilon(1e-6));
    CHECK(j.at("nu").get<double>() == Approx(0.3).epsilon(1e-6));
    CHECK(j.at("volume_fraction").get<double>() == Approx(1.0));
    CHECK(j.at("C").size() == 6);
}

TEST_CASE("curve_patterns follows the tool convention", "[cli][curve_patterns]") {
    const std::string vec = (data_dir / "vector").string();
    const std::string out = (work_dir / "cp_out.svg").string();
    fs::remove(out);
    for (const cli_case& c : std::vector<cli_case>{
             {"missing exemplar", {"--exemplar", (work_dir / "none.svg").string(), "--line", "100", "--height", "10", "-o", out}, 2, "none.svg"},
             {"NaN height", {"--exemplar", vec + "/greek_key.svg", "--line", "100", "--height", "nan", "-o", out}, 2, "height"},
             {"two shapes", {"--exemplar", vec + "/greek_key.svg", "--line", "100", "--circle", "10", "--height", "10", "-o", out}, 2, ""},
             {"impossible topology",
              {"--exemplar", vec + "/zigzag.svg", "--line", "100", "--height", "10", "--components", "1", "--holes", "3", "-o", out}, 3, ""},
         })
        check_case("curve_patterns", c);
    CHECK_FALSE(fs::exists(out));
    check_common("curve_patterns", {"--exemplar", vec + "/zigzag.svg", "--line", "100", "--height", "10", "--components", "1", "--holes", "3", "-o", out}, 3);

    const result ok = run("curve_patterns", {"--exemplar", vec + "/greek_key.svg", "--line", "120", "--height", "10", "--components", "1", "-o", out, "--json"});
    REQUIRE(ok.code == 0);
    const json j = json::parse(ok.out);
    CHECK(j.at("components") == 1);
    CHECK(j.at("outputs").size() == 3);
    for (const auto& p : j.at("outputs")) CHECK(fs::exists(p.get<std::string>()));
}

TEST_CASE("curve_patterns along a curve in space (--curve3d, --twist)", "[cli][curve_patterns]") {
    const std::string vec = (data_dir / "vector").string();
    const std::string out = (work_dir / "cp3d_out.svg").string();
    fs::remove(out);
    std::string helix, ring;  // a helix of radius 30 mm rising 40 mm over 1.5 turns, and a closed wavy ring
    for (int i = 0; i <= 300; ++i) {
        const double a = 3 * 3.141592653589793 * i / 300;
        helix += std::to_string(30 * std::cos(a)) + "," + std::to_string(30 * std::sin(a)) + "," + std::to_string(40.0 * i / 300) + "\n";
    }
    for (int i = 0; i < 240; ++i) {
        const double a = 2 * 3.141592653589793 * i / 240;
        ring += std::to_string(40 * std::cos(a)) + "," + std::to_string(40 * std::sin(a)) + "," + std::to_string(6 * std::cos(3 * a)) + "\n";
    }
    std::string tight;  // radius 30 mm, 2 turns 6 mm apart: a band 20 mm high, stood up by the twist, crosses the next turn
    for (int i = 0; i <= 400; ++i) {
        const double a = 4 * 3.141592653589793 * i / 400;
        tight += std::to_string(30 * std::cos(a)) + "," + std::to_string(30 * std::sin(a)) + "," + std::to_string(12.0 * i / 400) + "\n";
    }
    const std::string helix_csv = write_file("helix.csv", helix), ring_csv = write_file("ring.csv", ring), tight_csv = write_file("tight_helix.csv", tight);
    const std::string bad_csv = write_file("bad_curve.csv", "0,0,0\n1.2.3,4\n");
    for (const cli_case& c : std::vector<cli_case>{
             {"twist without --curve3d", {"--exemplar", vec + "/greek_key.svg", "--line", "100", "--twist", "90", "--height", "10", "-o", out}, 2, "twist"},
             {"closed with a quarter twist",
              {"--exemplar", vec + "/greek_key.svg", "--curve3d", ring_csv, "--closed", "--twist", "90", "--height", "8", "-o", out}, 2, "360"},
             {"malformed point", {"--exemplar", vec + "/greek_key.svg", "--curve3d", bad_csv, "--height", "8", "-o", out}, 5, "bad_curve.csv:2"},
             {"band wider than the bend",
              {"--exemplar", vec + "/greek_key.svg", "--curve3d", helix_csv, "--height", "80", "-o", out}, 2, "radius of curvature"},
             {"a band meeting itself",
              {"--exemplar", vec + "/greek_key.svg", "--curve3d", tight_csv, "--twist", "180", "--height", "20", "-o", out}, 2, "meets itself"},
         })
        check_case("curve_patterns", c);
    CHECK_FALSE(fs::exists(out));
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"--exemplar", vec + "/greek_key.svg", "--curve3d", helix_csv, "--twist", "180", "--height", "8", "--components", "1"},
             {"--exemplar", vec + "/disks.svg", "--curve3d", ring_csv, "--closed", "--twist", "360", "--height", "8", "--components", "16"}}) {
        std::vector<std::string> a = args;
        a.insert(a.end(), {"-o", out, "--json"});
        const result ok = run("curve_patterns", a);
        INFO(ok.err);
        REQUIRE(ok.code == 0);
        const json j = json::parse(ok.out);
        CHECK(std::to_string(j.at("components").get<int>()) == args.back());
        const fabsynth::triangle_mesh m = fabsynth::io::read_mesh((work_dir / "cp3d_out.stl").string());
        CHECK(fabsynth::analyze_topology(m).is_watertight());
        CHECK(fs::exists(work_dir / "cp3d_out.png"));
    }
}

TEST_CASE("curve_patterns on a surface (--mesh, --points, --emboss, --carve)", "[cli][curve_patterns]") {
    const std::string vec = (data_dir / "vector").string();
    const std::string vase = (data_dir / "meshes" / "vase.obj").string(), holes = (data_dir / "meshes" / "three_holes.obj").string();
    const std::string out = (work_dir / "cps_out.svg").string();
    fs::remove(out);
    std::string loop;  // 8 points around the vase's belly, on its profile r(z) = 20 + 9 sin(pi z / 70)
    for (int i = 0; i < 8; ++i) {
        const double a = 2 * 3.141592653589793 * i / 8, z = 45 + 6 * std::sin(2 * a), r = 20 + 9 * std::sin(3.141592653589793 * z / 70);
        loop += std::to_string(r * std::cos(a)) + "," + std::to_string(r * std::sin(a)) + "," + std::to_string(z) + "\n";
    }
    const std::string loop_csv = write_file("vase_loop.csv", loop), far_csv = write_file("vase_far.csv", "0,0,45\n30,0,45\n0,30,45\n");
    const std::vector<std::string> base{"--exemplar", vec + "/disks.svg", "--height", "12", "-o", out};
    const auto with = [&](std::vector<std::string> extra) {
        extra.insert(extra.end(), base.begin(), base.end());
        return extra;
    };
    for (const cli_case& c : std::vector<cli_case>{
             {"neither emboss nor carve", with({"--mesh", vase, "--points", loop_csv, "--closed"}), 2, "--emboss"},
             {"points without a mesh", with({"--points", loop_csv, "--carve", "2"}), 2, "mesh"},
             {"emboss and carve", with({"--mesh", vase, "--points", loop_csv, "--emboss", "1", "--carve", "2"}), 2, "carve"},
             {"a closed mesh of genus 3", with({"--mesh", holes, "--points", loop_csv, "--carve", "2"}), 2, "disk"},
             {"memory above the limit", with({"--mesh", vase, "--points", loop_csv, "--closed", "--carve", "2", "--max-memory", "0.01"}), 2, "--max-memory"},
             {"a point off the mesh", with({"--mesh", vase, "--points", far_csv, "--closed", "--carve", "2"}), 2, "from the mesh"},
             {"a negative relief", with({"--mesh", vase, "--points", loop_csv, "--closed", "--emboss", "-1"}), 2, "--emboss"},
         })
        check_case("curve_patterns", c);
    CHECK_FALSE(fs::exists(out));
    for (const char* mode : {"--emboss", "--carve"}) {
        INFO(mode);
        const result ok = run("curve_patterns", with({"--mesh", vase, "--points", loop_csv, "--closed", mode, "1.5", "--cell", "0.6", "--json"}));
        INFO(ok.err);
        REQUIRE(ok.code == 0);
        const json j = json::parse(ok.out);
        const fabsynth::triangle_mesh m = fabsynth::io::read_mesh((work_dir / "cps_out.stl").string());
        const auto info = fabsynth::analyze_topology(m);
        CHECK(info.is_watertight());
        CHECK(j.at("solid_components").get<std::size_t>() == info.components);
        CHECK(info.components == 1);  // separate disks: a relief on the shell, or windows in it
        CHECK(info.genus == (std::string(mode) == "--carve" ? j.at("components").get<long long>() : 0));
        CHECK(j.at("edge_crossings").get<std::size_t>() > 100);
        CHECK(fs::exists(work_dir / "cps_out.png"));
    }
    // a closed mesh (the bundled unit icosphere scaled to 30 mm) is cut open away from the points
    std::ifstream in(data_dir / "meshes" / "icosphere.obj");
    std::string sphere_obj, line;
    while (std::getline(in, line)) {
        double x, y, z;
        if (std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z) == 3) line = "v " + std::to_string(30 * x) + " " + std::to_string(30 * y) + " " + std::to_string(30 * z);
        sphere_obj += line + "\n";
    }
    std::string equator;
    for (int i = 0; i < 6; ++i) equator += std::to_string(30 * std::cos(i * 3.141592653589793 / 3)) + "," + std::to_string(30 * std::sin(i * 3.141592653589793 / 3)) + ",0\n";
    const std::string sphere_path = write_file("sphere30.obj", sphere_obj), equator_csv = write_file("equator.csv", equator);
    const result ok = run("curve_patterns", with({"--mesh", sphere_path, "--points", equator_csv, "--closed", "--carve", "2", "--cell", "0.6", "--json"}));
    INFO(ok.err);
    REQUIRE(ok.code == 0);
    const json j = json::parse(ok.out);
    const auto info = fabsynth::analyze_topology(fabsynth::io::read_mesh((work_dir / "cps_out.stl").string()));
    CHECK(info.is_watertight());
    CHECK(info.components == 1);  // a hollow ball with a window per disk
    CHECK(info.genus == j.at("components").get<long long>() - 1);
    CHECK(j.at("shape").get<std::string>().find("cut open") != std::string::npos);
}

namespace {
// Pixel size (mm) from a PNG's pHYs chunk, read from the bytes (no PNG library): pixels per metre
// in x, as the chunk stores it; 0 if the file has no pHYs chunk in metres.
double png_pixel_mm(const std::string& png) {
    const std::size_t at = png.find("pHYs");
    if (at == std::string::npos || at + 13 > png.size()) return 0;
    auto u8 = [&](std::size_t i) { return static_cast<unsigned>(static_cast<unsigned char>(png[i])); };
    const unsigned long ppm = (u8(at + 4) << 24) | (u8(at + 5) << 16) | (u8(at + 6) << 8) | u8(at + 7);
    return u8(at + 12) == 1 && ppm > 0 ? 1000.0 / static_cast<double>(ppm) : 0;
}
}  // namespace

TEST_CASE("foam_slicer follows the tool convention", "[cli][foam_slicer]") {
    const std::string mesh = (data_dir / "meshes/bunny_lowres.obj").string();
    const std::string dir = (work_dir / "fs_out").string();
    fs::remove_all(dir);
    const std::string bad_points = write_file("bad_points.csv", "1,2,3\n1.2.3,4\n");
    const std::string points = write_file("points.csv", "1,2,3\n0,0,0\n");
    const std::string eval_out = (work_dir / "eval_out.txt").string();
    fs::remove(eval_out);
    for (const cli_case& c : std::vector<cli_case>{
             {"malformed point", {"eval", "--points", bad_points, "--out", eval_out}, 5, "bad_points.csv:2"},
             {"empty seed box", {"seeds", "--box", "0", "0", "0", "0", "1", "1", "--out", eval_out}, 2, "--box"},
             {"negative slice count", {"slice", mesh, "--out-dir", dir, "--size", "20", "--slices", "-3"}, 2, "--slices"},
             {"NaN size", {"slice", mesh, "--out-dir", dir, "--size", "nan"}, 2, "--size"},
             {"fractional field axis", {"slice", mesh, "--out-dir", dir, "--size", "20", "--field-axis", "1.7", "0.1", "0.2", "0", "1"}, 2, "AXIS"},
             {"inverted stl box", {"slice", mesh, "--out-dir", dir, "--size", "20", "--stl-box", "5", "5", "5", "1", "1", "1"}, 2, "--stl-box"},
         })
        check_case("foam_slicer", c);
    CHECK_FALSE(fs::exists(dir));  // every option is checked before the first file is written
    CHECK_FALSE(fs::exists(eval_out));
    check_common("foam_slicer", {"slice", mesh, "--out-dir", dir, "--size", "nan"}, 2);

    const result ev = run("foam_slicer", {"eval", "--points", points, "--out", eval_out, "--json"});
    REQUIRE(ev.code == 0);
    CHECK(json::parse(ev.out).at("points") == 2);
    CHECK(slurp(eval_out).size() == 4);

    const result ok = run("foam_slicer", {"slice", mesh, "--y-up", "--size", "20", "--out-dir", dir, "--pixel", "0.1", "--slices", "3",
                                          "--radius", "0.25", "--density", "0.3", "--json"});
    REQUIRE(ok.code == 0);
    const json j = json::parse(ok.out);
    CHECK(j.at("slices") == 3);
    const json manifest = json::parse(slurp(j.at("manifest").get<std::string>()));
    CHECK(manifest.at("pixel_mm") == 0.1);
    REQUIRE(manifest.at("count") == 3);
    for (const auto& s : manifest.at("slices")) {
        const std::string png = slurp(fs::path(dir) / s.at("file").get<std::string>());
        CHECK(png_pixel_mm(png) == Approx(0.1).epsilon(1e-5));
    }
}

TEST_CASE("foam_fit follows the tool convention", "[cli][foam_fit]") {
    const std::string csv = (work_dir / "fit.csv").string(), header = (work_dir / "fit.hpp").string();
    fs::remove(csv);
    fs::remove(header);
    for (const cli_case& c : std::vector<cli_case>{
             {"no densities", {"--rho-count", "0", "--csv", csv}, 2, "--rho-count"},
             {"bad pair", {"--pairs", "0.1-0.2", "--csv", csv}, 2, "RHO:TAU"},
             {"header from too few samples", {"--pairs", "0.05:0.25", "--seeds", "1", "--header", header, "--csv", csv}, 2, "--header"},
         })
        check_case("foam_fit", c);
    CHECK_FALSE(fs::exists(csv));
    CHECK_FALSE(fs::exists(header));
    check_common("foam_fit", {"--rho-count", "0"}, 2);

    const result ok = run("foam_fit", {"--pairs", "1:0.25", "--seeds", "1", "--elements", "8", "--supersample", "1", "--csv", csv, "--json"});
    REQUIRE(ok.code == 0);
    const json j = json::parse(ok.out);
    CHECK(j.at("samples") == 1);
    CHECK(j.at("polynomial").empty());
    CHECK(j.at("max_deviation").is_null());
    CHECK(fs::exists(csv));
}

TEST_CASE("no tool overwrites one of its inputs or writes two outputs to one file", "[cli][clobber]") {
    const std::string exemplar = write_file("own_exemplar.svg", slurp(data_dir / "vector/greek_key.svg"));
    const std::string points = write_file("own_points.csv", "1,2,3\n");
    const std::string cache = write_file("own_cache.txt", "");
    std::string block = "# vtk DataFile Version 3.0\nblock\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nORIGIN 0 0 0\n"
                        "SPACING 1 1 1\nPOINT_DATA 8\nSCALARS density double 1\nLOOKUP_TABLE default\n1\n1\n1\n1\n1\n1\n1\n1\n";
    const std::string grid = write_file("own_grid.vtk", block);
    const std::string mesh_dir = (work_dir / "own_mesh_dir").string();
    fs::create_directories(mesh_dir);
    const std::string mesh = (fs::path(mesh_dir) / "solid.stl").string();
    fs::copy_file(data_dir / "meshes/cube_ascii.stl", mesh, fs::copy_options::overwrite_existing);
    fs::copy_file(data_dir / "meshes/cube_ascii.stl", fs::path(mesh_dir) / "pattern.stl", fs::copy_options::overwrite_existing);
    const std::string element = (work_dir / "own_spiral.svg").string();
    fs::copy_file(data_dir / "filigree/spiral.svg", element, fs::copy_options::overwrite_existing);
    struct row {
        std::string tool;
        std::vector<std::string> args;
        std::string input;
    };
    for (const row& r : std::vector<row>{
             {"filigree", {"--element", element, "--rect", "50", "50", "--scale", "20", "--width", "0.8", "-o", element}, element},
             {"curve_patterns", {"--exemplar", exemplar, "--line", "100", "--height", "10", "-o", exemplar}, exemplar},
             {"curve_patterns", {"--exemplar", exemplar, "--line", "100", "--height", "10", "-o", (work_dir / "x.stl").string()}, exemplar},
             {"foam_slicer", {"eval", "--points", points, "--out", points}, points},
             {"homogenize", {grid, "--preview", grid}, grid},
             {"foam_fit", {"--pairs", "1:0.25", "--seeds", "1", "--cache", cache, "--csv", cache}, cache},
             {"voxelize", {mesh, "-o", mesh_dir, "-r", "8"}, mesh},
             {"surface_patterns",
              {(fs::path(mesh_dir) / "pattern.stl").string(), "--exemplar", (data_dir / "exemplars/spots.png").string(), "--size", "20",
               "--thickness", "1", "--feature", "4", "--no-structure", "-o", mesh_dir},
              (fs::path(mesh_dir) / "pattern.stl").string()},
         }) {
        const std::string before = slurp(r.input);
        check_case(r.tool, {"output names an input or another output", r.args, 2, ""});
        CHECK(slurp(r.input) == before);
    }
    CHECK_FALSE(fs::exists(work_dir / "x.stl"));
}

TEST_CASE("surface_patterns follows the tool convention and writes the same files for 1 and 2 threads", "[cli][surface_patterns]") {
    const std::string out = (work_dir / "sp_out").string();
    fs::remove_all(out);
    const std::string bunny = (data_dir / "meshes/bunny_lowres.obj").string(), mask = (data_dir / "exemplars/hooks.png").string();
    const std::string nan_obj = write_file("sp_nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n");
    const std::string no_faces = write_file("sp_empty.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    const std::string not_png = write_file("sp_not.png", "this is not a PNG file");
    const std::string bad_loads = write_file("sp_loads_bad.txt", "# x y z fx fy fz radius\n20 20 20 0 -1 0 5\n20 20 0 -1\n");
    const std::string nan_loads = write_file("sp_loads_nan.txt", "20 20 20 0 nan 0\n");
    const std::string no_loads = write_file("sp_loads_empty.txt", "# nothing\n\n");
    fabsynth::io::write_png(work_dir / "sp_full.png", fabsynth::image8(16, 16, 1, 255));
    fabsynth::io::write_png(work_dir / "sp_empty.png", fabsynth::image8(16, 16, 1, 0));
    auto args = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = {bunny, "--exemplar", mask, "--size", "40", "--thickness", "1.5", "--feature", "4", "-r", "48", "--no-structure", "-o", out};
        for (auto& e : extra) a.push_back(e);
        return a;
    };
    auto structural = [&](std::vector<std::string> extra) {  // the full loop of Algorithm 1
        std::vector<std::string> a = {bunny, "--exemplar", mask, "--size", "40", "--thickness", "1.5", "--feature", "4", "-r", "48",
                                      "--gravity", "0", "-1", "0", "-o", out};
        for (auto& e : extra) a.push_back(e);
        return a;
    };
    auto with = [&](std::vector<std::string> a, const std::string& key, const std::string& value) {
        for (std::size_t i = 0; i + 1 < a.size(); ++i)
            if (a[i] == key) a[i + 1] = value;
        return a;
    };
    auto mesh_is = [&](const std::string& m) {
        std::vector<std::string> a = args({});
        a[0] = m;
        return a;
    };
    for (const cli_case& c : std::vector<cli_case>{
             {"missing mesh", mesh_is((work_dir / "none.obj").string()), 5, "does not exist"},
             {"NaN vertex", mesh_is(nan_obj), 5, "not finite"},
             {"mesh without faces", mesh_is(no_faces), 5, "no faces"},
             {"unreadable exemplar", with(args({}), "--exemplar", not_png), 5, "sp_not.png"},
             {"exemplar and colour of different sizes", args({"--color", (data_dir / "exemplars/zebra_color.png").string()}), 2, "differ in size"},
             {"full mask", with(args({}), "--exemplar", (work_dir / "sp_full.png").string()), 2, "full mask"},
             {"empty mask", with(args({}), "--exemplar", (work_dir / "sp_empty.png").string()), 2, "empty mask"},
             {"thickness below one voxel", with(args({}), "--thickness", "0.5"), 2, "--thickness"},
             {"feature zero", with(args({}), "--feature", "0"), 2, "--feature"},
             {"feature negative", with(args({}), "--feature", "-3"), 2, "--feature"},
             {"grid too large for memory", with(with(args({"--max-memory", "0.5"}), "-r", "4096"), "--size", "100"), 2, "GiB"},
             {"stages without the optimizer", args({"--stages"}), 2, "--no-structure"},
             {"unknown material", structural({"--material", "wood"}), 2, "material 'wood'"},
             {"zero gravity", structural({"--gravity", "0", "0", "0"}), 2, "--gravity"},
             {"validation too large for memory", structural({"--validate", "--max-memory", "0.001"}), 2, "GiB"},
             {"zero safety factor", structural({"--safety-factor", "0"}), 2, "--safety-factor"},
             {"NaN up", args({"--up", "nan", "0", "1"}), 2, "up"},
             {"support band without a plane", structural({"--support-band", "2"}), 2, "--support-plane"},
             {"support plane with a zero normal", structural({"--support-plane", "0", "0", "0", "0", "0", "0"}), 2, "normal"},
             {"loads line with four numbers", structural({"--loads", bad_loads}), 5, "sp_loads_bad.txt:3"},
             {"loads with NaN", structural({"--loads", nan_loads}), 5, "sp_loads_nan.txt:1"},
             {"loads file without a load", structural({"--loads", no_loads}), 5, "no load"},
             {"loads and a design load", structural({"--loads", (work_dir / "sp_loads_bad.txt").string(), "--design-load", "3"}), 2, "--design-load"},
             {"loads without the optimizer", args({"--loads", bad_loads}), 2, "--no-structure"},
         })
        check_case("surface_patterns", c);
    CHECK_FALSE(fs::exists(out));
    check_common("surface_patterns", with(args({}), "--feature", "0"), 2);

    const result one = run("surface_patterns", args({"--json"}), 1);
    INFO(one.err);
    REQUIRE(one.code == 0);
    const json j = json::parse(one.out);
    CHECK(j.at("status") == "ok");
    CHECK(j.at("watertight") == true);
    std::map<std::string, std::string> first;
    for (const char* f : {"pattern.stl", "shell.vtk", "solid.vtk", "preview.png"}) first[f] = slurp(fs::path(out) / f);
    json report = json::parse(slurp(fs::path(out) / "report.json"));
    CHECK(report.at("levels").size() == 6);
    CHECK(report.at("pattern_watertight") == true);
    CHECK(std::abs(report.at("solid_fraction").get<double>() - report.at("exemplar_solid_fraction").get<double>()) < 0.15);
#if defined(FABSYNTH_HAS_LIB3MF)
    {  // 3MF beside STL: the same mesh, in millimetres (3MF stores decimals of the floats)
        const fabsynth::triangle_mesh stl = fabsynth::io::read_mesh(fs::path(out) / "pattern.stl");
        const fabsynth::triangle_mesh m = fabsynth::io::read_3mf(fs::path(out) / "pattern.3mf");
        REQUIRE(m.faces.size() == stl.faces.size());
        CHECK(m.faces.size() == report.at("pattern_faces").get<std::size_t>());
        double worst = 0;
        for (std::size_t f = 0; f < m.faces.size(); ++f)
            for (std::size_t k = 0; k < 3; ++k)
                worst = std::max(worst, glm::length(m.vertices[m.faces[f][k]] - stl.vertices[stl.faces[f][k]]));
        CHECK(worst < 1e-4);
    }
    {  // with the exemplar's colour image, every triangle of the 3MF carries the colour of the pattern there:
       // on average the colour of the exemplar's solid pixels (red-brown hooks on a light ground)
        const std::string coloured = (work_dir / "sp_colour").string();
        fs::remove_all(coloured);
        const result c = run("surface_patterns", with(args({"--color", (data_dir / "exemplars/hooks_color.png").string(), "--quiet"}), "-o", coloured), 1);
        INFO(c.err);
        REQUIRE(c.code == 0);
        std::vector<std::array<std::uint8_t, 4>> rgba;
        const fabsynth::triangle_mesh m = fabsynth::io::read_3mf(fs::path(coloured) / "pattern.3mf", &rgba);
        REQUIRE(rgba.size() == m.faces.size());
        const fabsynth::image8 col = fabsynth::io::read_png(data_dir / "exemplars/hooks_color.png");
        const fabsynth::image8 msk = fabsynth::io::read_png(data_dir / "exemplars/hooks.png");
        double solid_mean[3] = {0, 0, 0}, face_mean[3] = {0, 0, 0};
        std::size_t solid = 0, uncoloured = 0;
        for (int y = 0; y < col.height; ++y)
            for (int x = 0; x < col.width; ++x)
                if (msk.at(x, y, 0) > 127) {
                    ++solid;
                    for (int k = 0; k < 3; ++k) solid_mean[k] += col.at(x, y, k);
                }
        for (const auto& c4 : rgba) {
            uncoloured += c4[3] != 255;
            for (int k = 0; k < 3; ++k) face_mean[k] += c4[static_cast<std::size_t>(k)];
        }
        CHECK(uncoloured == 0);
        for (int k = 0; k < 3; ++k) {
            INFO("channel " << k << ": faces " << face_mean[k] / rgba.size() << ", solid exemplar pixels " << solid_mean[k] / solid);
            CHECK(std::abs(face_mean[k] / rgba.size() - solid_mean[k] / solid) < 40);
        }
    }
#endif
    CHECK(first["shell.vtk"].find("SCALARS state unsigned_char") != std::string::npos);
    CHECK(first["solid.vtk"].find("SCALARS solid unsigned_char") != std::string::npos);
    const result two = run("surface_patterns", args({"--quiet"}), 2);
    REQUIRE(two.code == 0);
    CHECK(two.err.empty());
    for (const auto& [f, bytes] : first) {
        INFO(f);
        CHECK(slurp(fs::path(out) / f) == bytes);
    }
    // the report differs in its timings only
    auto without_times = [](json r) {
        r.erase("timings");
        for (auto& l : r.at("levels")) l.erase("seconds"), l.erase("candidates_per_second");
        for (auto& m : r.at("meshes")) m.erase("seconds");
        return r;
    };
    CHECK(without_times(json::parse(slurp(fs::path(out) / "report.json"))) == without_times(report));
}

TEST_CASE("surface_patterns with the structural loop: one piece, stages, validation, the same files for 1 and 2 threads",
          "[cli][surface_patterns]") {
    const std::string out = (work_dir / "sp_structure").string();
    fs::remove_all(out);
    // an isotropic exemplar, as in the paper's Table 3
    const std::vector<std::string> a = {(data_dir / "meshes/bunny_lowres.obj").string(), "--exemplar", (data_dir / "exemplars/voronoi_cells.png").string(),
                                        "--size", "40", "--thickness", "1.5", "--feature", "4", "-r", "48", "--gravity", "0", "-1", "0",
                                        "--stages", "--validate", "-o", out};
    auto with_flag = [&](const char* f) {
        std::vector<std::string> b = a;
        b.push_back(f);
        return b;
    };
    const result one = run("surface_patterns", with_flag("--json"), 1);
    INFO(one.err);
    REQUIRE(one.code == 0);
    const json j = json::parse(one.out);
    CHECK(j.at("converged") == true);
    CHECK(j.at("components_26") == 1);
    CHECK(j.at("watertight") == true);
    const json report = json::parse(slurp(fs::path(out) / "report.json"));
    const json& its = report.at("structural").at("iterations");
    REQUIRE_FALSE(its.empty());
    CHECK(its.front().at("components_before").get<int>() > 1);  // the synthesized cells are several pieces
    for (std::size_t k = 1; k < its.size(); ++k)  // no §6.1 round splits the pieces it joined
        CHECK(its[k].at("components_before").get<int>() <= its[k - 1].at("components_before").get<int>());
    CHECK(its.back().at("components_before") == 1);
    // Table 3 (§6.3), judged by the full voxel FEA: the reinforcements cut the 99th percentile of
    // |s1|+|s2|+|s3| under the design load at least 3x (paper: 5x), and under the unexpected
    // (orthogonal) load the geodesic stage is no worse than the force profile alone
    const json& val = report.at("validation");
    auto p99 = [&](const char* stage, const char* load) { return val.at(stage).at(load).at("p99_pa").get<double>(); };
    for (const char* stage : {"connected", "forces", "forces_geodesic"})
        for (const char* load : {"expected", "unexpected"}) {
            INFO(stage << " " << load);
            CHECK(p99(stage, load) > 0);
            CHECK(val.at(stage).at(load).at("unsupported_voxels") == 0);
        }
    INFO("p99 expected: connected " << p99("connected", "expected") << ", forces " << p99("forces", "expected") << ", forces+geodesic "
                                     << p99("forces_geodesic", "expected") << "; unexpected: forces " << p99("forces", "unexpected")
                                     << ", forces+geodesic " << p99("forces_geodesic", "unexpected"));
    CHECK(p99("connected", "expected") >= 5 * p99("forces_geodesic", "expected"));
    // The geodesic stage can only be judged where it laid a bridge (otherwise the forces and
    // forces_geodesic solids are the same voxels): on this case it must, and it must help.
    std::size_t geodesic_bridges = 0;
    for (const json& it : its) geodesic_bridges += it.at("added_geodesic").get<std::size_t>();
    CHECK(geodesic_bridges > 0);
    CHECK(p99("forces_geodesic", "unexpected") < p99("forces", "unexpected"));
    // the stress fields of each solid (Fig. 16) agree with the statistics of its stage: the free
    // elements are the voxels with a positive score, the largest is max_pa, nothing outside the solid
    for (const auto& [file, stage] : {std::pair{"solid.vtk", "forces_geodesic"}, std::pair{"solid_connected.vtk", "connected"},
                                      std::pair{"solid_forces.vtk", "forces"}}) {
        INFO(file);
        const fabsynth::io::structured_points sp = fabsynth::io::read_vtk_structured_points(fs::path(out) / file);
        REQUIRE(sp.fields.size() == 3);
        const auto& solid = sp.fields[0].values;
        for (std::size_t k = 1; k < 3; ++k) {
            const auto& f = sp.fields[k];
            const json& st = val.at(stage).at(k == 1 ? "expected" : "unexpected");
            CHECK(f.name == (k == 1 ? "stress_expected_pa" : "stress_unexpected_pa"));
            std::size_t positive = 0, outside = 0;
            double largest = 0;
            for (std::size_t c = 0; c < f.values.size(); ++c) {
                if (f.values[c] > 0) ++positive, largest = std::max(largest, f.values[c]);
                if (solid[c] == 0 && f.values[c] != 0) ++outside;
            }
            CHECK(outside == 0);
            CHECK(positive == st.at("elements").get<std::size_t>());
            CHECK(largest == Approx(st.at("max_pa").get<double>()).epsilon(1e-6));  // stored as float
        }
    }
    std::map<std::string, std::string> first;
    for (const char* f : {"pattern.stl", "shell.vtk", "solid.vtk", "solid_connected.vtk", "solid_forces.vtk", "preview.png"})
        first[f] = slurp(fs::path(out) / f);
    // reinforcement voxels (state 3) are in the shell: the VTK holds the states as bytes after the header
    CHECK(first["shell.vtk"].find(static_cast<char>(3)) != std::string::npos);
    const result two = run("surface_patterns", with_flag("--quiet"), 2);
    REQUIRE(two.code == 0);
    for (const auto& [f, bytes] : first) {
        INFO(f);
        CHECK(slurp(fs::path(out) / f) == bytes);
    }
}
