// The fuzzers' seed files (fuzz/corpus/<name>/) must be valid inputs, so fuzzing starts from
// the accepting paths of each parser.
#include <catch2/catch.hpp>

#include "fabsynth/io.hpp"
#include "io/io_test_util.hpp"

using namespace fabsynth;

TEST_CASE("fuzz seed corpus files parse", "[io][fuzz]") {
    const auto root = std::filesystem::path(FABSYNTH_DATA_DIR) / ".." / "fuzz" / "corpus";
    if (!std::filesystem::exists(root)) return;  // installed tree without fuzzers
    std::size_t seeds = 0;
    auto each = [&](const char* dir, auto&& parse) {
        if (!std::filesystem::exists(root / dir)) return;
        for (const auto& e : std::filesystem::directory_iterator(root / dir)) {
            INFO(e.path().string());
            const std::string bytes = io_test::slurp(e.path());
            CHECK_NOTHROW(parse(bytes, e.path().string()));
            ++seeds;
        }
    };
    each("obj", [](const std::string& b, const std::string& n) { CHECK(io::parse_obj(b, n).num_faces() >= 4); });
    each("stl", [](const std::string& b, const std::string& n) { CHECK(io::parse_stl(b, n).num_vertices() == 4); });
    each("ply", [](const std::string& b, const std::string& n) { CHECK(io::parse_ply(b, n).num_faces() == 4); });
    each("png", [](const std::string& b, const std::string& n) { CHECK(!io::parse_png(b, n).empty()); });
    each("pgm", [](const std::string& b, const std::string& n) { CHECK(io::parse_pgm(b, n).data.size() == 6); });
    each("pgm16", [](const std::string& b, const std::string& n) { CHECK(!io::parse_pgm16(b, n).empty()); });
    each("vtk_structured_points",
         [](const std::string& b, const std::string& n) { CHECK(!io::parse_vtk_structured_points(b, n).fields.empty()); });
    CHECK(seeds >= 12);
}
