// The filigree tool end to end: the output is one connected piece, counted independently (OUT.svg
// read back and rasterized by a scanline fill and a flood fill written here, no library geometry),
// OUT.stl is watertight, outputs are byte-identical for 1 and 2 threads, and bad input is refused
// with the documented exit code and nothing written.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#if defined(FABSYNTH_HAS_LIB3MF)
#include <fabsynth/io/mesh_3mf.hpp>
#endif

#include "cli_util.hpp"

namespace filigree_cli {

using json = nlohmann::json;

// Every "M x y L x y ... Z" ring of the SVG text (write_svg emits M/L/Z only with spaces).
std::vector<std::vector<std::array<double, 2>>> svg_rings(const std::string& text) {
    std::vector<std::vector<std::array<double, 2>>> rings;
    std::size_t at = 0;
    while ((at = text.find(" d=\"", at)) != std::string::npos) {
        const std::size_t end = text.find('"', at + 4);
        std::istringstream in(text.substr(at + 4, end - at - 4));
        std::string tok;
        std::vector<std::array<double, 2>> cur;
        while (in >> tok) {
            if (tok == "M" || tok == "L") continue;
            if (tok == "Z" || tok == "z") {
                if (!cur.empty()) rings.push_back(cur), cur.clear();
                continue;
            }
            std::replace(tok.begin(), tok.end(), ',', ' ');
            std::istringstream xy(tok);
            double x = 0, y = 0;
            if (xy >> x >> y) cur.push_back({x, y});
            else {  // "x y" as two tokens
                x = std::stod(tok);
                in >> tok;
                y = std::stod(tok);
                cur.push_back({x, y});
            }
        }
        if (!cur.empty()) rings.push_back(cur);
        at = end;
    }
    return rings;
}

// Even-odd scanline fill of all rings at `pixel` mm, then 8-connected solid components.
std::size_t raster_components(const std::vector<std::vector<std::array<double, 2>>>& rings, double pixel) {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const auto& r : rings)
        for (const auto& p : r) x0 = std::min(x0, p[0]), y0 = std::min(y0, p[1]), x1 = std::max(x1, p[0]), y1 = std::max(y1, p[1]);
    const int w = static_cast<int>((x1 - x0) / pixel) + 3, h = static_cast<int>((y1 - y0) / pixel) + 3;
    std::vector<std::uint8_t> on(static_cast<std::size_t>(w) * h, 0);
    for (int j = 0; j < h; ++j) {
        const double y = y0 + (j - 1 + 0.5) * pixel;
        std::vector<double> xs;
        for (const auto& r : rings)
            for (std::size_t i = 0; i < r.size(); ++i) {
                const auto& a = r[i];
                const auto& b = r[(i + 1) % r.size()];
                if ((a[1] <= y) != (b[1] <= y)) xs.push_back(a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]));
            }
        std::sort(xs.begin(), xs.end());
        for (std::size_t k = 0; k + 1 < xs.size(); k += 2)
            for (int i = 0; i < w; ++i) {
                const double x = x0 + (i - 1 + 0.5) * pixel;
                if (x >= xs[k] && x < xs[k + 1]) on[static_cast<std::size_t>(j) * w + i] = 1;
            }
    }
    std::vector<int> stack;
    std::size_t components = 0;
    for (int s = 0; s < w * h; ++s) {
        if (on[s] != 1) continue;
        ++components;
        stack.push_back(s);
        on[s] = 2;
        while (!stack.empty()) {
            const int c = stack.back();
            stack.pop_back();
            const int ci = c % w, cj = c / w;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const int ni = ci + di, nj = cj + dj;
                    if (ni < 0 || nj < 0 || ni >= w || nj >= h) continue;
                    const int n = nj * w + ni;
                    if (on[n] == 1) on[n] = 2, stack.push_back(n);
                }
        }
    }
    return components;
}

// Binary STL: every undirected edge (by float coordinates) in exactly two triangles, once each way.
bool stl_watertight(const std::string& bytes) {
    if (bytes.size() < 84) return false;
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    if (bytes.size() != 84 + 50ull * n) return false;
    using key = std::array<float, 3>;
    std::map<std::pair<key, key>, int> directed;
    for (std::uint32_t t = 0; t < n; ++t) {
        key v[3];
        for (int k = 0; k < 3; ++k) std::memcpy(v[k].data(), bytes.data() + 84 + 50ull * t + 12 + 12 * k, 12);
        for (int k = 0; k < 3; ++k) ++directed[{v[k], v[(k + 1) % 3]}];
    }
    for (const auto& [e, c] : directed) {
        if (c != 1) return false;
        const auto r = directed.find({e.second, e.first});
        if (r == directed.end() || r->second != 1) return false;
    }
    return n > 0;
}

}  // namespace filigree_cli

TEST_CASE("filigree: one connected piece (independent raster count), watertight STL, same bytes for 1 and 2 threads", "[cli][filigree]") {
    using namespace filigree_cli;
    const std::string el = (data_dir / "filigree/s_curl.svg").string();
    std::vector<std::string> outputs;
    for (int threads : {1, 2}) {
        std::string name = "filigree_t";  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on literal + string&&
        name += std::to_string(threads);
        name += ".svg";
        const std::string out = (work_dir / name).string();
        const result r = run("filigree", {"--element", el, "--rect", "60", "40", "--scale", "16", "--width", "0.8", "--seed", "5", "-o", out}, threads);
        INFO("stderr: " << r.err);
        REQUIRE(r.code == 0);
        const std::string svg = slurp(out);
        CHECK(raster_components(svg_rings(svg), 0.05) == 1);
        fs::path stl = out;
        stl.replace_extension(".stl");
        CHECK(stl_watertight(slurp(stl)));
        fs::path rep = out;
        rep.replace_extension(".json");
        const json j = json::parse(slurp(rep));
        CHECK(j.at("connected_components") == 1);
        CHECK(j.at("structure").at("analysed") == true);
        // After the structural optimization no node is weak under the stated load case.
        const auto& wf = j.at("structure").at("weak_fraction_phase2");
        REQUIRE_FALSE(wf.empty());
        CHECK(wf.back() == 0.0);
        // Placement does its work: the PME ends at least 10% below the initialization's (a rise is
        // undone by construction, so "not above" could not fail; the main job's runs end 2-50% lower).
        CHECK(j.at("pme").at("final").get<double>() < 0.9 * j.at("pme").at("initial").get<double>());
        fs::path steps = fs::path(out).parent_path() / (fs::path(out).stem().string() + "_steps.png");
        CHECK(fs::file_size(steps) > 0);
        outputs.push_back(svg + slurp(stl));
    }
    CHECK(outputs[0] == outputs[1]);
}

TEST_CASE("filigree: without --width the strips take the SVG's stroke width, scaled with the element", "[cli][filigree]") {
    // An L of 60 + 80 user units (bounding-box diagonal 100) stroked 5 units wide: at --scale 20 the
    // drawing shrinks 5x, so its strips are 1.0 mm wide; --width 0.6 overrides that.
    const std::string el = write_file("filigree_stroked_l.svg",
                                      "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 70 90\"><polyline fill=\"none\" "
                                      "stroke=\"#000\" stroke-width=\"5\" points=\"5,85 65,85 65,5\"/></svg>");
    auto width_of = [&](std::vector<std::string> extra) {
        const std::string out = (work_dir / "filigree_stroked.svg").string();
        std::vector<std::string> a = {"--element", el, "--rect", "50", "40", "--scale", "20", "--no-structure", "-o", out};
        a.insert(a.end(), extra.begin(), extra.end());
        const result r = run("filigree", a);
        INFO("stderr: " << r.err);
        REQUIRE(r.code == 0);
        fs::path rep = out;
        rep.replace_extension(".json");
        return json::parse(slurp(rep)).at("elements").at(0).at("median_strip_width_mm").get<double>();
    };
    CHECK(width_of({}) == Approx(1.0).epsilon(1e-6));
    CHECK(width_of({"--width", "0.6"}) == Approx(0.6).epsilon(1e-9));
}

namespace filigree_cli {
// Width, height and PNG colour type (2: RGB) from the IHDR chunk.
std::array<int, 3> png_header(const std::string& bytes) {
    auto be32 = [&](std::size_t at) {
        return (static_cast<int>(static_cast<unsigned char>(bytes[at])) << 24) | (static_cast<int>(static_cast<unsigned char>(bytes[at + 1])) << 16) |
               (static_cast<int>(static_cast<unsigned char>(bytes[at + 2])) << 8) | static_cast<int>(static_cast<unsigned char>(bytes[at + 3]));
    };
    REQUIRE(bytes.size() > 26);
    REQUIRE(bytes.compare(1, 3, "PNG") == 0);
    return {be32(16), be32(20), static_cast<unsigned char>(bytes[25])};
}
}  // namespace filigree_cli

TEST_CASE("filigree: how the piece is held, its material and a thickness bound act as documented; 3MF and the figures of §5", "[cli][filigree]") {
    using namespace filigree_cli;
    const std::string el = (data_dir / "filigree/s_curl.svg").string();
    auto run_with = [&](const std::string& name, std::vector<std::string> extra) {
        const std::string out = (work_dir / (name + ".svg")).string();
        std::vector<std::string> a = {"--element", el, "--rect", "60", "40", "--scale", "16", "--width", "0.8", "--seed", "5", "-o", out};
        a.insert(a.end(), extra.begin(), extra.end());
        const result r = run("filigree", a);
        INFO("stderr: " << r.err);
        REQUIRE(r.code == 0);
        return json::parse(slurp(work_dir / (name + ".json")));
    };
    // Lying flat, held along the top as drawn (the default), 1 kPa: the piece needs 1.1 mm.
    const json flat = run_with("filigree_flat", {});
    CHECK(flat.at("structure").at("supports").at("side") == "top");
    CHECK(flat.at("thickness_mm").get<double>() > 1.0);
    // Hanging upright from an eyelet with no pressure: its own weight pulls in its plane, a membrane
    // load far below the yield, so the initial 1 mm stays and the peak stress falls by orders of magnitude.
    const json hung = run_with("filigree_hung", {"--hang", "30", "1", "--hang-radius", "6", "--pressure", "0"});
    const json& hs = hung.at("structure");
    CHECK(hs.at("supports").at("hang_mm") == json::array({30.0, 1.0}));
    CHECK(hs.at("supports").at("gravity") == "in the plane, toward the drawing's bottom");
    CHECK(hung.at("thickness_mm") == 1.0);
    CHECK(hs.at("max_von_mises_after_mpa").get<double>() < 0.01 * flat.at("structure").at("max_von_mises_after_mpa").get<double>());
    // A softer material under 30 kPa with a bound of 1.1 mm: reinforcement stops there and says what is still weak.
    const json capped = run_with("filigree_capped", {"--material", "pa12", "--pressure", "30000", "--max-thickness", "1.1"});
    const json& cs = capped.at("structure");
    CHECK(cs.at("material") == "pa12");
    CHECK(cs.at("yield_mpa") == 48.0);
    CHECK(capped.at("thickness_mm").get<double>() <= 1.1);
    CHECK(cs.at("strong") == false);
    CHECK(cs.at("weak_nodes_final").get<std::size_t>() > 0);
    CHECK(capped.at("weak_points_mm").size() == cs.at("weak_nodes_final").get<std::size_t>());
    // The figures: the stress map (RGB, 1600 px across the domain's longer side plus its colour bar)
    // and the histogram (1000 x 600 RGB).
    const auto map = png_header(slurp(work_dir / "filigree_flat_stress.png"));
    CHECK(map[2] == 2);
    CHECK(map[0] > 1600);
    CHECK(png_header(slurp(work_dir / "filigree_flat_histogram.png")) == std::array<int, 3>{1000, 600, 2});
#if defined(FABSYNTH_HAS_LIB3MF)
    // 3MF beside STL: the same triangles, in millimetres.
    const std::string stl = slurp(work_dir / "filigree_flat.stl");
    std::uint32_t stl_triangles = 0;
    std::memcpy(&stl_triangles, stl.data() + 80, 4);
    const fabsynth::triangle_mesh m = fabsynth::io::read_3mf((work_dir / "filigree_flat.3mf").string());
    CHECK(m.faces.size() == stl_triangles);
#endif
}

TEST_CASE("filigree --labels: each element keeps to the regions of its grey levels", "[cli][filigree]") {
    using namespace filigree_cli;
    const std::string labels = (data_dir / "filigree/three_regions.png").string();  // grey 0 | 128 | 255 in vertical thirds
    const std::string out = (work_dir / "filigree_regions.svg").string();
    const result r = run("filigree", {"--element", (data_dir / "filigree/spiral.svg").string() + "@0", "--element",
                                      (data_dir / "filigree/leaf.svg").string() + "@128,255", "--labels", labels, "--rect", "60", "40",
                                      "--scale", "16", "--width", "0.8", "--no-structure", "--seed", "2", "-o", out});
    INFO("stderr: " << r.err);
    REQUIRE(r.code == 0);
    const json j = json::parse(slurp(work_dir / "filigree_regions.json"));
    CHECK(j.at("field") == "constant");
    const json& e = j.at("elements");
    CHECK(e.at(0).at("labels") == json::array({0}));
    CHECK(e.at(1).at("labels") == json::array({128, 255}));
    // a third of the area takes spirals, two thirds leaves: both classes are there, and each
    // class's share follows its region (spirals cover at most about half of the instances)
    const int spirals = e.at(0).at("instances"), leaves = e.at(1).at("instances");
    INFO("spirals " << spirals << ", leaves " << leaves);
    CHECK(spirals >= 3);
    CHECK(leaves > spirals);
    CHECK(j.at("connected_components") == 1);
    const std::string el = (data_dir / "filigree/spiral.svg").string();
    for (const cli_case& c : std::vector<cli_case>{
             {"labels without --labels", {"--element", el + "@0", "--rect", "50", "50", "--scale", "16", "-o", out}, 2, "--labels"},
             {"--labels without labelled elements", {"--element", el, "--labels", labels, "--rect", "50", "50", "--scale", "16", "-o", out}, 2,
              "E.svg@G1,G2"},
             {"a grey level the picture lacks", {"--element", el + "@7", "--labels", labels, "--rect", "50", "50", "--scale", "16", "-o", out}, 2,
              "grey level 7"},
         })
        check_case("filigree", c);
}

TEST_CASE("filigree: bad input is refused with the documented exit code and nothing written", "[cli][filigree]") {
    const std::string el = (data_dir / "filigree/spiral.svg").string();
    const std::string out = (work_dir / "filigree_bad.svg").string();
    for (const char* ext : {".svg", ".stl", ".png", ".json", "_steps.png"}) fs::remove(work_dir / (std::string("filigree_bad") + ext));
    const std::string blank = write_file("filigree_blank.svg", "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 10\"><rect width=\"5\" height=\"5\" fill=\"none\"/></svg>");
    const std::string nan_svg =
        write_file("filigree_nan.svg", "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 10\"><polyline fill=\"none\" stroke=\"#000\" points=\"0,0 NaN,1\"/></svg>");
    const std::string flat = write_file("filigree_flat.svg", "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 10\"><polygon fill=\"#000\" points=\"0,0 5,0 10,0\"/></svg>");
    auto args = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = {"--element", el, "--scale", "20", "--width", "0.8", "-o", out};
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    for (const cli_case& c : std::vector<cli_case>{
             {"an SVG with no usable stroke or fill", {"--element", blank, "--rect", "50", "50", "--scale", "20", "--width", "0.8", "-o", out}, 2,
              "no stroked path or filled shape"},
             {"NaN coordinates", {"--element", nan_svg, "--rect", "50", "50", "--scale", "20", "--width", "0.8", "-o", out}, 5, "filigree_nan.svg"},
             {"an element larger than the domain", args({"--rect", "5", "5"}), 3, "larger than the domain"},
             {"a domain of zero area", args({"--domain", flat}), 2, "zero area"},
             {"width < 0", args({"--rect", "50", "50", "--width", "-0.5"}), 2, "--width"},
             {"crossing penalty < 0", args({"--rect", "50", "50", "--crossing-penalty", "-1"}), 2, "--crossing-penalty"},
             {"max bridge < -1", args({"--rect", "50", "50", "--max-bridge", "-2"}), 2, "--max-bridge"},
             {"width NaN", args({"--rect", "50", "50", "--width", "nan"}), 2, "--width"},
             {"no domain", args({}), 2, "--rect"},
             {"field image without scales", args({"--rect", "50", "50", "--field-image", (data_dir / "filigree/gradient_field.png").string()}), 2,
              "--field-scale"},
             {"unknown material", args({"--rect", "50", "50", "--material", "gold"}), 2, "--material"},
             {"unknown support edge", args({"--rect", "50", "50", "--support-edge", "middle"}), 2, "--support-edge"},
             {"support box and hang", args({"--rect", "50", "50", "--support-box", "0", "0", "5", "5", "--hang", "1", "1"}), 2, "--hang"},
             {"inverted support box", args({"--rect", "50", "50", "--support-box", "5", "0", "0", "5"}), 2, "--support-box"},
             {"hang radius without hang", args({"--rect", "50", "50", "--hang-radius", "2"}), 2, "--hang"},
             {"max thickness below the thickness", args({"--rect", "50", "50", "--max-thickness", "0.5"}), 2, "--max-thickness"},
             {"support without structure", args({"--rect", "50", "50", "--no-structure", "--upright"}), 2, "--no-structure"},
             {"rotation image without range", args({"--rect", "50", "50", "--rotation-image", (data_dir / "filigree/gradient_field.png").string()}), 2,
              "--rotation-range"},
             {"a hanging point off the piece", args({"--rect", "50", "50", "--hang", "500", "500"}), 2, "hanging point"},
         })
        check_case("filigree", c);
    CHECK_FALSE(fs::exists(out));
    CHECK_FALSE(fs::exists(work_dir / "filigree_bad.stl"));
    CHECK_FALSE(fs::exists(work_dir / "filigree_bad.json"));
}

namespace filigree_cli {

// The faces of data/meshes/vase.obj whose centroid lies between z0 and z1 mm (read here from the OBJ).
std::string vase_band(double z0, double z1) {
    std::istringstream in(slurp(data_dir / "meshes/vase.obj"));
    std::vector<std::array<double, 3>> v;
    std::ostringstream ids;
    std::string line;
    std::size_t face = 0;
    while (std::getline(in, line)) {
        std::istringstream l(line);
        std::string tag;
        l >> tag;
        if (tag == "v") {
            std::array<double, 3> p{};
            l >> p[0] >> p[1] >> p[2];
            v.push_back(p);
        } else if (tag == "f") {
            std::size_t a = 0, b = 0, c = 0;
            l >> a >> b >> c;
            const double z = (v[a - 1][2] + v[b - 1][2] + v[c - 1][2]) / 3;
            if (z >= z0 && z <= z1) ids << face << "\n";
            ++face;
        }
    }
    return ids.str();
}

// A closed loop on the side of data/meshes/vase.obj as CSV: angle 0.5 cos t rad around z, height
// 45 + 15 sin t mm, at the mean radius of the OBJ's vertices within 1 mm of that height. `area`:
// the loop's developed area (an ellipse of semi-axes 0.5 r(45) and 15 mm).
std::string vase_loop(double& area) {
    std::istringstream in(slurp(data_dir / "meshes/vase.obj"));
    std::vector<std::array<double, 3>> v;
    for (std::string line; std::getline(in, line);)
        if (line.rfind("v ", 0) == 0) {
            std::istringstream l(line.substr(2));
            std::array<double, 3> p{};
            l >> p[0] >> p[1] >> p[2];
            v.push_back(p);
        }
    auto radius = [&](double z) {
        double sum = 0;
        int n = 0;
        for (const auto& p : v)
            if (std::abs(p[2] - z) < 1) sum += std::hypot(p[0], p[1]), ++n;
        return sum / n;
    };
    std::ostringstream csv;
    csv.precision(10);
    for (int k = 0; k < 32; ++k) {
        const double t = 2 * std::numbers::pi * k / 32, a = 0.5 * std::cos(t), z = 45 + 15 * std::sin(t), r = radius(z);
        csv << r * std::cos(a) << "," << r * std::sin(a) << "," << z << "\n";
    }
    area = std::numbers::pi * 0.5 * radius(45) * 15;
    return csv.str();
}

}  // namespace filigree_cli

TEST_CASE("filigree --mesh --region-curve: the region a loop on the vase encloses", "[cli][filigree][surface]") {
    using namespace filigree_cli;
    double loop_area = 0;
    const std::string curve = write_file("filigree_vase_loop.csv", vase_loop(loop_area));
    const std::string out = (work_dir / "filigree_vase_loop.stl").string();
    const result r = run("filigree", {"--element", (data_dir / "filigree/c_scroll.svg").string(), "--mesh", (data_dir / "meshes/vase.obj").string(),
                                      "--region-curve", curve, "--up", "0", "0", "1", "--scale", "8", "--width", "0.8", "--rounds", "1",
                                      "--no-structure", "-o", out});
    INFO("stderr: " << r.err);
    REQUIRE(r.code == 0);
    fs::path rep = out;
    rep.replace_extension(".json");
    const json j = json::parse(slurp(rep));
    const double area = j.at("mesh").at("region_area_mm2").get<double>();
    INFO("region " << area << " mm^2, loop " << loop_area << " mm^2");
    CHECK(area > 0.8 * loop_area);  // the band along the loop is about one face (2-3 mm) wide
    CHECK(area < 1.25 * loop_area);
    CHECK(j.at("instances").get<int>() >= 3);
    CHECK(j.at("stl_components") == 1);  // the patch prints as one piece
}

TEST_CASE("filigree --mesh: a band of the vase, watertight solid, report, same bytes for 1 and 2 threads", "[cli][filigree][surface]") {
    using namespace filigree_cli;
    const std::string el = (data_dir / "filigree/c_scroll.svg").string();
    const std::string region = write_file("filigree_vase_band.txt", vase_band(4, 40));
    std::vector<std::string> outputs;
    for (int threads : {1, 2}) {
        std::string name = "filigree_vase_t";
        name += std::to_string(threads);
        name += ".stl";
        const std::string out = (work_dir / name).string();
        const result r = run("filigree", {"--element", el, "--mesh", (data_dir / "meshes/vase.obj").string(), "--region", region, "--up", "0", "0", "1",
                                          "--scale", "14", "--width", "0.8", "--rounds", "2", "--seed", "3", "-o", out},
                             threads);
        INFO("stderr: " << r.err);
        REQUIRE(r.code == 0);
        CHECK(stl_watertight(slurp(out)));
        fs::path rep = out, obj = out, png = out;
        rep.replace_extension(".json"), obj.replace_extension(".obj"), png.replace_extension(".png");
        const json j = json::parse(slurp(rep));
        CHECK(j.at("mode") == "surface");
        CHECK(j.at("stl_components") == 1);
        CHECK(j.at("instances").get<int>() >= 10);
        CHECK(j.at("structure").at("analysed") == true);
        CHECK(j.at("structure").at("weak_fraction_phase2").back() == 0.0);
        // Placement does its work: the PME ends at least 10% below the initialization's (a rise is
        // undone by construction, so "not above" could not fail; the main job's runs end 2-50% lower).
        CHECK(j.at("pme").at("final").get<double>() < 0.9 * j.at("pme").at("initial").get<double>());
        CHECK(fs::file_size(obj) > 0);
        CHECK(fs::file_size(png) > 0);
        outputs.push_back(slurp(out) + slurp(obj));
    }
    CHECK(outputs[0] == outputs[1]);
}

TEST_CASE("filigree --mesh --directions: user directions at vertices turn the elements", "[cli][filigree][surface]") {
    using namespace filigree_cli;
    const std::string el = (data_dir / "filigree/c_scroll.svg").string();
    const std::string region = write_file("filigree_vase_band_dirs.txt", vase_band(4, 40));
    // a dozen vertices of the vase near z = 20 mm ask for horizontal elements (the tangent around z)
    std::ostringstream rows;
    {
        std::istringstream in(slurp(data_dir / "meshes/vase.obj"));
        std::size_t id = 0, n = 0;
        for (std::string line; std::getline(in, line) && n < 12;)
            if (line.rfind("v ", 0) == 0) {
                std::istringstream l(line.substr(2));
                double x = 0, y = 0, z = 0;
                l >> x >> y >> z;
                if (std::abs(z - 20) < 0.6) rows << id << " " << -y << " " << x << " 0\n", ++n;
                ++id;
            }
    }
    const std::string dirs = write_file("filigree_vase_dirs.txt", rows.str());
    auto run_band = [&](const std::string& name, std::vector<std::string> extra) {
        const std::string out = (work_dir / name).string();
        std::vector<std::string> a = {"--element", el, "--mesh", (data_dir / "meshes/vase.obj").string(), "--region", region, "--scale", "14",
                                      "--width", "0.8", "--rounds", "2", "--seed", "3", "--no-structure", "-o", out};
        a.insert(a.end(), extra.begin(), extra.end());
        const result r = run("filigree", a);
        INFO("stderr: " << r.err);
        REQUIRE(r.code == 0);
        fs::path rep = out;
        rep.replace_extension(".json");
        return std::make_pair(slurp(out), json::parse(slurp(rep)));
    };
    const auto [up_stl, up_json] = run_band("filigree_vase_up.stl", {});
    const auto [dir_stl, dir_json] = run_band("filigree_vase_dirs.stl", {"--directions", dirs});
    CHECK(up_json.at("direction_constraints") == 0);
    CHECK(dir_json.at("direction_constraints") == 12);
    CHECK(dir_stl != up_stl);  // the layout follows the field
    CHECK(stl_watertight(dir_stl));
    const std::string bad = write_file("filigree_vase_dirs_bad.txt", "999999 1 0 0\n");
    check_case("filigree", {"a direction at a vertex the mesh does not have",
                            {"--element", el, "--mesh", (data_dir / "meshes/vase.obj").string(), "--directions", bad, "--scale", "14", "-o",
                             (work_dir / "filigree_vase_dirs_bad.stl").string()},
                            2, "filigree_vase_dirs_bad.txt"});
    check_case("filigree", {"--directions without --mesh", {"--element", el, "--rect", "50", "50", "--directions", dirs, "--scale", "14", "-o",
                                                            (work_dir / "filigree_vase_dirs_bad.svg").string()},
                            2, "--mesh"});
}

TEST_CASE("filigree --mesh: bad input is refused with the documented exit code and nothing written", "[cli][filigree][surface]") {
    using namespace filigree_cli;
    const std::string el = (data_dir / "filigree/c_scroll.svg").string();
    const std::string out = (work_dir / "filigree_mesh_bad.stl").string();
    const std::string vase = (data_dir / "meshes/vase.obj").string();
    const std::string bad_region = write_file("filigree_bad_region.txt", "0\n1\n999999\n");
    const std::string text_region = write_file("filigree_text_region.txt", "0 1 two\n");
    const std::string short_scale = write_file("filigree_short_scale.txt", "1 1 1\n");
    const std::string broken = write_file("filigree_broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    const std::string tiny_loop = write_file("filigree_tiny_loop.csv", "29,0,45\n29,0.01,45\n29,0,45.01\n");
    const std::string far_loop = write_file("filigree_far_loop.csv", "29,0,45\n60,0,50\n29,0,55\n");
    const std::string halves = (data_dir / "filigree/vase_halves.txt").string();  // 0 below z = 45 mm, 1 above
    const std::string short_labels = write_file("filigree_short_labels.txt", "0\n1\n");
    const std::string big_label = write_file("filigree_big_label.txt", "0\n256\n");
    auto args = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = {"--element", el, "--scale", "14", "--width", "0.8", "-o", out};
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    for (const cli_case& c : std::vector<cli_case>{
             {"a face id out of range", args({"--mesh", vase, "--region", bad_region}), 2, "999999"},
             {"a region file with text", args({"--mesh", vase, "--region", text_region}), 5, "not a number"},
             {"a scale file of the wrong length", args({"--mesh", vase, "--field-scale-file", short_scale}), 2, "3 values for 5977 vertices"},
             {"an up vector of zero", args({"--mesh", vase, "--up", "0", "0", "0"}), 2, "up vector"},
             {"a mesh indexing a missing vertex", args({"--mesh", broken}), 5, "filigree_broken.obj"},
             {"--mesh with --rect", args({"--mesh", vase, "--rect", "10", "10"}), 2, "excludes"},
             {"a region curve that encloses nothing", args({"--mesh", vase, "--region-curve", tiny_loop}), 2, "does not separate"},
             {"a region curve off the mesh", args({"--mesh", vase, "--region-curve", far_loop}), 2, "point 1 lies farther"},
             {"--region with --region-curve", args({"--mesh", vase, "--region", bad_region, "--region-curve", far_loop}), 2, "excludes"},
             {"an element set without --face-labels", {"--element", el + "@0", "--mesh", vase, "--scale", "14", "-o", out}, 2, "--face-labels"},
             {"--face-labels without an element set", args({"--mesh", vase, "--face-labels", halves}), 2, "E.svg@L1,L2"},
             {"--face-labels of the wrong length", {"--element", el + "@0", "--mesh", vase, "--face-labels", short_labels, "--scale", "14", "-o", out}, 2,
              "2 labels for a mesh of 11880 faces"},
             {"a label no face has", {"--element", el + "@7", "--mesh", vase, "--face-labels", halves, "--scale", "14", "-o", out}, 2,
              "no face has label 7"},
             {"a label outside 0-255", {"--element", el + "@0", "--mesh", vase, "--face-labels", big_label, "--scale", "14", "-o", out}, 2,
              "not an integer in 0-255"},
             {"--face-labels without --mesh", {"--element", el + "@0", "--rect", "50", "50", "--face-labels", halves, "--scale", "14", "-o", out}, 2,
              "--mesh"},
         })
        check_case("filigree", c);
    for (const char* ext : {".stl", ".obj", ".png", ".json"}) CHECK_FALSE(fs::exists(work_dir / (std::string("filigree_mesh_bad") + ext)));
}
