// The tools under careless and hostile use (docs/tools.md, "Limits" and "Outputs"): work beyond
// an estimate refused before it starts, outputs that cannot be written refused before the work,
// and a run killed at any moment leaves the previous outputs whole (or, when it finished first,
// the complete new set), never a truncated or mixed one.
#include <catch2/catch.hpp>
#include <poll.h>
#include <sys/syscall.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "cli_util.hpp"

namespace {

// A cube of n^3 C3D8 elements of 1 mm, the base fixed, a load at the top corner.
std::string block_deck(int n) {
    std::string d = "*NODE\n";
    auto id = [n](int i, int j, int k) { return 1 + i + (n + 1) * (j + (n + 1) * k); };
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) d += std::to_string(id(i, j, k)) + "," + std::to_string(i) + "," + std::to_string(j) + "," + std::to_string(k) + "\n";
    d += "*ELEMENT, TYPE=C3D8, ELSET=E\n";
    int e = 1;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                d += std::to_string(e++);
                for (int v : {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1), id(i + 1, j, k + 1),
                              id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)})
                    d += "," + std::to_string(v);
                d += "\n";
            }
    d += "*NSET, NSET=BASE\n";
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) d += std::to_string(id(i, j, 0)) + "\n";
    d += "*MATERIAL, NAME=M\n*ELASTIC\n1000, 0.3\n*SOLID SECTION, ELSET=E, MATERIAL=M\n*BOUNDARY\nBASE, 1, 3\n*STEP\n*STATIC\n*CLOAD\n" +
         std::to_string(id(n, n, n)) + ", 3, -1\n*END STEP\n";
    return d;
}

// A periodic lattice of n^3 voxels (beams along the three axes, period 8) as VTK POINT_DATA.
std::string lattice_vtk(int n) {
    std::string g = "# vtk DataFile Version 3.0\nlattice\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS " + std::to_string(n) + " " + std::to_string(n) + " " +
                    std::to_string(n) + "\nORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA " + std::to_string(n * n * n) +
                    "\nSCALARS density double 1\nLOOKUP_TABLE default\n";
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) g += ((x % 8 < 3) + (y % 8 < 3) + (z % 8 < 3) >= 2) ? "1\n" : "0\n";
    return g;
}

// Hidden staging directories (examples/common/output_set.hpp) directly in `dir`.
std::vector<std::string> staging_dirs(const fs::path& dir) {
    std::vector<std::string> found;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        if (it->path().filename().string().rfind(".fabsynth-stage-", 0) == 0) found.push_back(it->path().string());
    return found;
}

// "running", "terminated" (a zombie counts: a tool killed with its parent may stay unreaped) or
// "gone": the state of the process that owns staging directory `d`, from a pidfd (no /proc needed).
std::string owner_state(const std::string& d) {
    const long fd = ::syscall(SYS_pidfd_open, static_cast<pid_t>(std::stol(d.substr(d.rfind('-') + 1))), 0u);
    if (fd < 0) return "gone";
    pollfd p{static_cast<int>(fd), POLLIN, 0};
    const bool running = ::poll(&p, 1, 0) == 0;
    ::close(static_cast<int>(fd));
    return running ? "running" : "terminated";
}

// Waits (up to 10 s) until the processes that own the staging directories in `dir` have
// terminated: a SIGKILLed tool may still be tearing down its threads when the shell returns.
void wait_for_owners(const fs::path& dir) {
    for (int i = 0; i < 100; ++i) {
        bool alive = false;
        for (const std::string& d : staging_dirs(dir)) alive = alive || owner_state(d) == "running";
        if (!alive) return;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
}

const std::string old_bytes = "previous run\n";

// A tool run that takes a few seconds, its final output files, and where it stages them.
struct long_run {
    std::string tool;
    std::vector<std::string> args;
    std::vector<fs::path> outputs;
    fs::path anchor;  // the directory that holds the staging directory
};

}  // namespace

TEST_CASE("every tool refuses work beyond its estimate before it starts", "[cli][limits]") {
    const std::string bunny = (data_dir / "meshes/bunny_lowres.obj").string();
    const std::string deck = write_file("limits_block.inp", block_deck(6));
    const std::string grid = write_file("limits_lattice.vtk", lattice_vtk(16));
    const fs::path out = work_dir / "limits_out";
    fs::remove_all(out);
    struct row {
        std::string tool;
        cli_case c;
    };
    for (const row& r : std::vector<row>{
             {"voxelize", {"a 2048 grid in 0.5 GiB", {bunny, "-r", "2048", "--max-memory", "0.5", "-o", out.string()}, 2, "GiB"}},
             {"fem_solve", {"LDLT above the flop limit", {deck, "-o", out.string(), "--solver", "ldlt", "--max-factor-flops", "1000"}, 2, "--max-factor-flops"}},
             {"fem_solve", {"CHOLMOD factor above the memory limit", {deck, "-o", out.string(), "--solver", "cholmod", "--max-memory", "1e-6"}, 2, "GiB"}},
             {"homogenize", {"six solves above the memory limit", {grid, "--max-memory", "1e-6", "--preview", (out / "h.png").string()}, 2, "GiB"}},
             {"foam_fit", {"the largest accepted grid", {"--elements", "256", "--supersample", "16", "--csv", (out / "f.csv").string()}, 2, "--max-hours"}},
             {"foam_fit", {"256^3 elements in 8 GiB", {"--elements", "256", "--max-memory", "8", "--csv", (out / "f.csv").string()}, 2, "GiB"}},
             {"foam_slicer",
              {"a 0.003 mm pixel over a 40 mm object", {"slice", bunny, "--size", "40", "--pixel", "0.003", "--out-dir", out.string()}, 2, "--max-pixels"}},
             {"foam_slicer",
              {"more slices than layers", {"slice", bunny, "--size", "20", "--slices", "100000000", "--out-dir", out.string()}, 2, "slices asked for"}},
             {"foam_slicer",
              {"a seed box beyond memory", {"seeds", "--box", "0", "0", "0", "1e4", "1e4", "1e4", "--density", "1", "--out", (out / "s.csv").string()}, 2, "GiB"}},
             {"filigree",
              {"a 10 m square of 2 mm elements",
               {"--element", (data_dir / "filigree/spiral.svg").string(), "--rect", "10000", "10000", "--scale", "2", "--width", "0.1", "-o",
                (out / "f.svg").string()},
               2,
               "--max-elements"}},
         })
        check_case(r.tool, r.c);
    CHECK_FALSE(fs::exists(out));
    CHECK(staging_dirs(work_dir).empty());
}

TEST_CASE("an output that cannot be written is refused before the work, naming it", "[cli][io]") {
    const std::string bunny = (data_dir / "meshes/bunny_lowres.obj").string();
    const std::string blocker = write_file("blocker", "a file where a directory is expected\n");
    const std::string under = (fs::path(blocker) / "out").string();
    const std::string deck = (data_dir / "fem/cantilever_c3d8.inp").string();
    const std::string grid = write_file("io_lattice.vtk", lattice_vtk(8));
    struct row {
        std::string tool;
        std::vector<std::string> args;
    };
    for (const row& r : std::vector<row>{
             {"voxelize", {bunny, "-r", "16", "-o", under}},
             {"fem_solve", {deck, "-o", under}},
             {"homogenize", {grid, "--preview", under + ".png"}},
             {"foam_fit", {"--pairs", "1:0.25", "--seeds", "1", "--elements", "8", "--supersample", "1", "--csv", under + ".csv"}},
             {"foam_slicer", {"slice", bunny, "--size", "10", "--slices", "2", "--out-dir", under}},
             {"foam_slicer", {"eval", "--points", write_file("io_points.csv", "1,2,3\n"), "--out", under + ".txt"}},
             {"curve_patterns", {"--exemplar", (data_dir / "vector/greek_key.svg").string(), "--line", "100", "--height", "10", "-o", under + ".svg"}},
             {"surface_patterns",
              {bunny, "--exemplar", (data_dir / "exemplars/spots.png").string(), "--size", "20", "--thickness", "1", "--feature", "4", "-r", "32",
               "--no-structure", "-o", under}},
             {"filigree",
              {"--element", (data_dir / "filigree/spiral.svg").string(), "--rect", "50", "50", "--scale", "20", "--width", "0.8", "--no-structure",
               "-o", under + ".svg"}},
         }) {
        check_case(r.tool, {"output below a regular file", r.args, 5, "blocker"});
        CHECK(slurp(blocker) == "a file where a directory is expected\n");
    }
    CHECK(staging_dirs(work_dir).empty());
}

TEST_CASE("a run killed at any moment leaves the previous outputs whole", "[cli][kill]") {
    const fs::path root = work_dir / "kill";
    fs::remove_all(root);
    fs::create_directories(root);
    const std::string bunny = (data_dir / "meshes/bunny_lowres.obj").string();
    const std::string deck = write_file("kill/block.inp", block_deck(16));
    const std::string grid = write_file("kill/lattice.vtk", lattice_vtk(40));
    const fs::path vox = root / "vox", fem = root / "fem", fs_dir = root / "slices", sp = root / "sp";
    const std::vector<long_run> runs = {
        {"voxelize", {bunny, "-r", "300", "-o", vox.string()}, {vox / "shell.vtk", vox / "solid.stl", vox / "slices.png"}, vox},
        {"fem_solve", {deck, "--solver", "ldlt", "-o", fem.string()}, {fem / "displacements.csv", fem / "stresses.csv", fem / "result.vtk"}, fem},
        {"homogenize", {grid, "--preview", (root / "lattice.png").string()}, {root / "lattice.png"}, root},
        {"foam_fit",
         {"--pairs", "1:0.25", "--seeds", "1", "--elements", "32", "--supersample", "8", "--csv", (root / "fit.csv").string(), "--plot",
          (root / "fit.png").string()},
         {root / "fit.csv", root / "fit.png"},
         root},
        {"foam_slicer",
         {"slice", bunny, "--size", "40", "--pixel", "0.05", "--slices", "60", "--out-dir", fs_dir.string()},
         {fs_dir / "slices.json", fs_dir / "preview.png"},
         fs_dir},
        {"curve_patterns",
         {"--exemplar", (data_dir / "vector/greek_key.svg").string(), "--line", "3000", "--height", "10", "-o", (root / "band.svg").string()},
         {root / "band.svg", root / "band.stl", root / "band.png"},
         root},
        {"surface_patterns",
         {bunny, "--exemplar", (data_dir / "exemplars/spots.png").string(), "--size", "40", "--thickness", "1", "--feature", "4", "-r", "96",
          "--no-structure", "-o", sp.string()},
         {sp / "pattern.stl", sp / "shell.vtk", sp / "solid.vtk", sp / "preview.png", sp / "report.json"},
         sp},
    };
    for (const long_run& r : runs)
        for (const char* signal : {"KILL", "TERM"}) {  // KILL first: the TERM run then also sweeps what KILL left
            INFO(r.tool << " killed by SIG" << signal << " after 1 s");
            for (const fs::path& p : r.outputs) fs::create_directories(p.parent_path()), write_file(fs::relative(p, work_dir).string(), old_bytes);
            if (std::string(signal) == "TERM") wait_for_owners(r.anchor);
            const std::vector<std::string> before = staging_dirs(r.anchor);
            const result res = run(r.tool, r.args, 1, std::string("timeout -s ") + signal + " 1");
            INFO("exit " << res.code << ", stderr: " << res.err);
            int old_files = 0;
            for (const fs::path& p : r.outputs) {
                REQUIRE(fs::exists(p));
                old_files += slurp(p) == old_bytes;
            }
            if (res.code != 0) CHECK(res.code == (std::string(signal) == "KILL" ? 137 : 124));
            // The old set whole, or the new set whole: a signal after commit() (exit code 124/137 with
            // every file new) is the second case.
            if (old_files != static_cast<int>(r.outputs.size())) {
                CHECK(old_files == 0);
                for (const fs::path& p : r.outputs) CHECK(fs::file_size(p) > 0);
            }
            if (std::string(signal) == "TERM")
                for (const std::string& d : staging_dirs(r.anchor)) {
                    // The TERM run removes its own staging directory and sweeps those of dead runs; a
                    // directory may stay only if it was there before and its owner still runs.
                    const bool earlier = std::find(before.begin(), before.end(), d) != before.end();
                    INFO(d << (earlier ? " (left by the KILL run), owner " : " (made by the TERM run), owner ") << owner_state(d));
                    CHECK((earlier && owner_state(d) == "running"));
                }
        }
    // The slice stack the manifest describes is complete: every listed file exists.
    const json manifest = json::parse(slurp(fs_dir / "slices.json"), nullptr, false);
    if (!manifest.is_discarded())
        for (const auto& s : manifest.at("slices")) CHECK(fs::exists(fs_dir / s.at("file").get<std::string>()));
}

TEST_CASE("extreme values are refused where they enter, naming the option", "[cli][limits]") {
    const std::string exemplar = (data_dir / "vector/greek_key.svg").string();
    const std::string out = (work_dir / "extreme.svg").string();
    auto band = [&](std::vector<std::string> shape) {
        std::vector<std::string> a = {"--exemplar", exemplar, "-o", out};
        a.insert(a.end(), shape.begin(), shape.end());
        return a;
    };
    for (const cli_case& c : std::vector<cli_case>{
             {"line of 1e300 mm", band({"--line", "1e300", "--height", "10"}), 2, "--line"},
             {"line of 1e6 band heights", band({"--line", "1e6", "--height", "1"}), 2, "--line"},
             {"height of 1e300 mm", band({"--line", "100", "--height", "1e300"}), 2, "--height"},
             {"height of 1e-300 mm", band({"--line", "100", "--height", "1e-300"}), 2, "--height"},
             {"thickness of 1e300 mm", band({"--line", "100", "--height", "10", "--thickness", "1e300"}), 2, "--thickness"},
             {"tolerance of 1e-300 mm", band({"--line", "100", "--height", "10", "--tolerance", "1e-300"}), 2, "--tolerance"},
             {"circle of radius 1e300 mm", band({"--circle", "1e300", "--height", "10"}), 2, "--circle"},
             {"rectangle 1e300 mm wide", band({"--rect", "1e300", "10", "--height", "5"}), 2, "--rect width"},
         })
        check_case("curve_patterns", c);
    CHECK_FALSE(fs::exists(out));
}

TEST_CASE("the last hostile inputs are refused at once, naming the option or file:line, in few digits", "[cli][limits]") {
    const std::string bunny = (data_dir / "meshes/bunny_lowres.obj").string();
    const fs::path out = work_dir / "hostile_out";
    fs::remove_all(out);
    // A lattice grid whose SPACING line (line 7) says 1e300 mm per voxel.
    std::string grid_text = lattice_vtk(8);
    grid_text.replace(grid_text.find("SPACING 1 1 1"), 13, "SPACING 1e300 1 1");
    const std::string huge_spacing = write_file("hostile_spacing.vtk", grid_text);
    const std::string grid = write_file("hostile_lattice.vtk", lattice_vtk(8));
    // An exemplar band whose path (line 3) reaches x = 1e308.
    const std::string far_svg = write_file("hostile_far.svg",
                                           "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"20\" height=\"10\">\n"
                                           "<rect x=\"0\" y=\"0\" width=\"20\" height=\"10\"/>\n"
                                           "<path d=\"M 0 0 L 1e308 0 L 1e308 5 Z\"/>\n</svg>\n");
    // A curve of 30 m: 30 000 band heights of 1 mm (before the --max-heights estimate the run went on
    // for minutes, quadratic in the length).
    const std::string long_curve = write_file("hostile_long_curve.svg",
                                              "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"30000\" height=\"10\">\n"
                                              "<path d=\"M 0 5 L 30000 5\" stroke=\"black\" fill=\"none\"/>\n</svg>\n");
    struct row {
        std::string tool;
        cli_case c;
    };
    for (const row& r : std::vector<row>{
             {"curve_patterns",
              {"a 30 m curve at a 1 mm band height",
               {"--exemplar", (data_dir / "vector/greek_key.svg").string(), "--curve", long_curve, "--height", "1", "-o", (out / "long.svg").string()},
               2,
               "--max-heights"}},
             {"foam_slicer", {"an empty --out-dir", {"slice", bunny, "--size", "20", "--out-dir", ""}, 2, "--out-dir is given an empty value"}},
             {"voxelize", {"an empty -o", {bunny, "-o", ""}, 2, "empty value"}},
             {"foam_fit", {"2e9 densities per tau", {"--rho-count", "2000000000", "--csv", (out / "f.csv").string()}, 2, "--max-hours"}},
             {"homogenize", {"--E 1e308", {grid, "--E", "1e308"}, 2, "--E = 1e+308"}},
             {"homogenize", {"a spacing of 1e300 mm", {huge_spacing}, 5, "hostile_spacing.vtk:7: SPACING 1e+300 is out of range"}},
             {"curve_patterns",
              {"an exemplar coordinate of 1e308", {"--exemplar", far_svg, "--line", "100", "--height", "10", "-o", (out / "c.svg").string()}, 5,
               "hostile_far.svg:3:"}},
         }) {
        // "timeout -s KILL 20": a tool that starts the work instead of refusing it is killed (137)
        const result res = run(r.tool, r.c.args, 1, "timeout -s KILL 20");
        INFO(r.tool << ": " << r.c.what << "\nstderr: " << res.err);
        CHECK(res.code == r.c.code);
        CHECK(res.err.find(r.c.message) != std::string::npos);
        CHECK(res.err.size() < 400);                                             // short
        CHECK_FALSE(std::regex_search(res.err, std::regex("[0-9]{10,}")));      // no 300-digit numbers
    }
    CHECK_FALSE(fs::exists(out));
}
