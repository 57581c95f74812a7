// The .inp reader against CalculiX's own test suite (Debian calculix-ccx-test, 355 decks nobody
// here wrote) and against ccx itself: every deck is either solved as ccx solves it or refused with
// file:line and the keyword; and variants of a suite deck, made with the keyword forms the suite's
// other decks use, are either solved as ccx solves them or refused naming the parameter or column,
// never accepted with something ignored.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "fabsynth/fem/inp.hpp"
#include "fabsynth/fem/solve_context.hpp"
#include "support/ccx.hpp"

using namespace fabsynth;
using namespace fabsynth::fem;
namespace fs = std::filesystem;

namespace {
const fs::path suite_dir = "/usr/share/doc/calculix-ccx-test/examples/test";

std::string read_deck(const fs::path& p) {
    if (p.extension() == ".gz") {  // the package compresses its larger decks
        std::string text;
        const std::string cmd = "zcat '" + p.string() + "'";
        FILE* pipe = popen(cmd.c_str(), "r");
        REQUIRE(pipe);
        char buf[1 << 16];
        for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) text.append(buf, n);
        REQUIRE(pclose(pipe) == 0);
        return text;
    }
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}
std::string deck_name(const fs::path& p) { return p.extension() == ".gz" ? p.stem().string() : p.filename().string(); }
std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream s(text);
    for (std::string l; std::getline(s, l);) out.push_back(l);
    return out;
}
std::string upper_str(std::string s) {
    for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return s;
}
// "*KEYWORD" of the block line `line` (1-based) belongs to, "" before any keyword.
std::string governing_keyword(const std::vector<std::string>& lines, std::size_t line) {
    for (std::size_t i = std::min(line, lines.size()); i-- > 0;) {
        std::string t = lines[i];
        t.erase(0, t.find_first_not_of(" \t"));
        if (t.starts_with('*') && !t.starts_with("**")) {
            const std::string kw = t.substr(1, t.find(',') == std::string::npos ? std::string::npos : t.find(',') - 1);
            return "*" + upper_str(kw.substr(0, kw.find_last_not_of(" \t\r") + 1));
        }
    }
    return "";
}

// Largest difference of fem's displacements to ccx's, relative to the largest |u|.
double difference_to_ccx(const inp_deck& d, const fs::path& dat) {
    const auto ccx = test::read_ccx_displacements(dat);
    REQUIRE(ccx.size() == d.model.nodes.size());
    const static_result r = solve_linear_static(d.model, d.loads);
    double umax = 0, err = 0;
    for (std::size_t i = 0; i < d.model.nodes.size(); ++i) {
        const vec3 u = r.displacement(i);
        const auto& c = ccx.at(static_cast<long>(d.model.node_ids[i]));
        umax = std::max(umax, glm::length(u));
        for (int k = 0; k < 3; ++k) err = std::max(err, std::abs(u[k] - c[static_cast<std::size_t>(k)]));
    }
    REQUIRE(umax > 0);
    return err / umax;
}
}  // namespace

TEST_CASE("every deck of CalculiX's test suite is solved as ccx solves it or refused with file:line and keyword",
          "[fem][inp][ccx][oracle]") {
    if (!fs::is_directory(suite_dir) || !test::have_ccx()) {
        WARN("Debian calculix-ccx-test or ccx not installed: the suite comparison is skipped");
        return;
    }
    std::vector<fs::path> decks;
    for (const auto& e : fs::directory_iterator(suite_dir))
        if (e.path().extension() == ".inp" || e.path().string().ends_with(".inp.gz")) decks.push_back(e.path());
    std::sort(decks.begin(), decks.end());
    REQUIRE(decks.size() >= 300);  // 355 in calculix-ccx-test 2.11
    const std::regex located(R"(^fabsynth: ([^:]+):(\d+): (.*)$)");
    std::size_t solved = 0;
    for (const fs::path& p : decks) {
        const std::string name = deck_name(p), text = read_deck(p);
        INFO(name);
        try {
            const inp_deck d = parse_inp(text, name);
            // accepted: ccx must solve the same deck to the same displacements
            REQUIRE(test::run_ccx(fs::path(FABSYNTH_TEST_TMP) / "ccx_suite", "deck", text));
            CHECK(difference_to_ccx(d, fs::path(FABSYNTH_TEST_TMP) / "ccx_suite" / "deck.dat") < 1e-6);  // ccx prints 7 digits
            ++solved;
        } catch (const io_error& e) {
            const std::string what = e.what();
            INFO(what);
            std::smatch m;
            REQUIRE(std::regex_match(what, m, located));
            CHECK(m[1] == name);
            const auto lines = lines_of(text);
            const std::size_t line = std::stoul(m[2]);
            CHECK(line >= 1);
            CHECK(line <= lines.size());
            const std::string kw = governing_keyword(lines, line);
            if (kw.empty()) CHECK_THAT(what, Catch::Contains("before any keyword"));
            else CHECK_THAT(what, Catch::Contains(kw));
        }
    }
    CHECK(solved >= 1);  // beam8p.inp, the suite's C3D8 cantilever
}

TEST_CASE("variants of a suite deck in the suite's own keyword forms are solved as ccx does or refused by name",
          "[fem][inp][ccx][oracle]") {
    fs::path base_path = suite_dir / "beam8p.inp";
    if (!fs::exists(base_path)) base_path += ".gz";  // compressed in some versions of the package
    if (!fs::exists(base_path) || !test::have_ccx()) {
        WARN("Debian calculix-ccx-test or ccx not installed: the deck variants are skipped");
        return;
    }
    const std::string base = read_deck(base_path);
    struct variant {
        const char* name;
        const char* from;  // text of beam8p.inp replaced ...
        const char* to;    // ... by this
        const char* refusal;  // "" = must be solved as ccx solves it; else a word the refusal names
        const char* at;       // the refusal's line holds this text
    };
    const variant variants[] = {
        // accepted forms (ccx reads them; so must fem)
        {"elastic_type_iso", "*ELASTIC\n", "*ELASTIC, TYPE=ISO\n", "", ""},        // axrad2.inp
        {"elastic_type_isotropic", "*ELASTIC\n", "*ELASTIC,TYPE=ISOTROPIC\n", "", ""},
        {"elastic_one_temperature", "210000.,.3\n", "210000.,.3,294.\n", "", ""},
        {"density_one_temperature", "210000.,.3\n", "210000.,.3\n*DENSITY\n7.8e-9,294.\n", "", ""},
        {"node_empty_z", "   342,    0.000,    0.000,    0.000 ", "   342,    0.000,    0.000,  ,0.000 ", "", ""},  // shellf.inp
        {"node_id_and_x", "   344,    0.250,    0.000,    0.000 ", "   344,    0.250", "", ""},
        {"node_empty_y", "   376,    0.500,    0.000,    0.000 ", "   376,    0.500, ,", "", ""},
        {"step_inc", "*STEP\n", "*STEP,INC=100\n", "", ""},
        {"static_solver", "*STATIC\n", "*STATIC,SOLVER=SPOOLES\n", "", ""},
        {"cload_op_mod", "LAST,2,0.36\n", "LAST,2,0.36\n*CLOAD,OP=MOD\nLAST,1,0.2\n", "", ""},
        {"cload_repeated", "LAST,2,0.36\n", "LAST,2,0.36\n*CLOAD\nLAST,2,0.1\n", "", ""},  // ccx adds them
        {"boundary_op_mod", "*BOUNDARY\n", "*BOUNDARY,OP=MOD\n", "", ""},
        // refused: ccx would read these with an effect fem does not model, or ignore what they say
        {"elastic_temperature_table", "210000.,.3\n", "210000.,.3,0.\n100000.,.3,100.\n", "second row", "100000.,.3,100."},
        {"density_temperature_table", "210000.,.3\n", "210000.,.3\n*DENSITY\n7.8e-9,0.\n7.0e-9,100.\n", "second row", "7.0e-9,100."},
        {"elastic_extra_column", "210000.,.3\n", "210000.,.3,0.,7.\n", "E, nu[, temperature]", "210000.,.3,0.,7."},
        {"elastic_orthotropic", "*ELASTIC\n", "*ELASTIC,TYPE=ORTHO\n", "TYPE=ORTHO", "*ELASTIC,TYPE=ORTHO"},
        {"section_orientation", "*SOLID SECTION,ELSET=Eall,MATERIAL=EL", "*SOLID SECTION,ELSET=Eall,MATERIAL=EL,ORIENTATION=OR1",
         "ORIENTATION", "ORIENTATION=OR1"},
        {"node_fifth_column", "   342,    0.000,    0.000,    0.000 ", "   342,    0.000,    0.000,  ,0.500 ", "column 5", "   342,"},
        {"node_parameter", "*NODE, NSET=Nall", "*NODE, NSET=Nall, SYSTEM=C", "SYSTEM", "SYSTEM=C"},
        {"element_parameter", "*ELEMENT, TYPE=C3D8, ELSET=Eall\n     1,", "*ELEMENT, TYPE=C3D8, ELSET=Eall, OFFSET=1\n     1,", "OFFSET",
         "OFFSET=1"},
        {"material_parameter", "*MATERIAL,NAME=EL", "*MATERIAL,NAME=EL,RESPONSE=1", "RESPONSE", "RESPONSE=1"},
        {"cload_user", "*CLOAD\n", "*CLOAD,USER\n", "USER", "*CLOAD,USER"},               // ccx: zero load
        {"cload_submodel", "*CLOAD\n", "*CLOAD,SUBMODEL\n", "SUBMODEL", "*CLOAD,SUBMODEL"},
        {"cload_amplitude", "*CLOAD\n", "*CLOAD,AMPLITUDE=A1\n", "AMPLITUDE", "*CLOAD,AMPLITUDE"},
        {"cload_op_new", "LAST,2,0.36\n", "LAST,2,0.36\n*CLOAD,OP=NEW\nLAST,1,0.2\n", "OP=NEW", "*CLOAD,OP=NEW"},
        {"boundary_op_new", "*STATIC\n", "*STATIC\n*BOUNDARY,OP=NEW\nFIX,1,1\n", "OP=NEW", "*BOUNDARY,OP=NEW"},
        {"boundary_user", "*BOUNDARY\n", "*BOUNDARY,USER\n", "USER", "*BOUNDARY,USER"},
        {"step_perturbation", "*STEP\n", "*STEP,PERTURBATION\n", "PERTURBATION", "*STEP,PERTURBATION"},
        {"static_time_reset", "*STATIC\n", "*STATIC,TIME RESET\n", "TIME RESET", "*STATIC,TIME RESET"},
    };
    for (const variant& v : variants) {
        INFO("variant " << v.name);
        std::string text = base;
        const auto at = text.find(v.from);
        REQUIRE(at != std::string::npos);
        text.replace(at, std::string_view(v.from).size(), v.to);
        const std::string name = std::string("beam8p_") + v.name + ".inp";
        if (*v.refusal == 0) {
            const inp_deck d = parse_inp(text, name);
            REQUIRE(test::run_ccx(fs::path(FABSYNTH_TEST_TMP) / "ccx_variants", v.name, text));
            CHECK(difference_to_ccx(d, fs::path(FABSYNTH_TEST_TMP) / "ccx_variants" / (std::string(v.name) + ".dat")) < 1e-6);
            continue;
        }
        const auto lines = lines_of(text);
        std::size_t line = 0;
        while (line < lines.size() && lines[line].find(v.at) == std::string::npos) ++line;
        REQUIRE(line < lines.size());
        try {
            (void)parse_inp(text, name);
            FAIL("accepted: " << v.name);
        } catch (const io_error& e) {
            CHECK_THAT(e.what(), Catch::Contains(name + ":" + std::to_string(line + 1) + ":") && Catch::Contains(v.refusal));
        }
    }
}
