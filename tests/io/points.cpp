// io/points.hpp and io/numbers.hpp: strict point and number lists, against hand-written expectations.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "fabsynth/io/numbers.hpp"
#include "fabsynth/io/points.hpp"

using namespace fabsynth;
using Catch::Matchers::Contains;

TEST_CASE("points: commas, blanks, comments, CRLF and signs", "[io][points]") {
    const auto p = io::parse_points_csv("# x,y,z\n1,2,3\r\n\n  -4.5e1 +6\t7\n8 , 9,10\n", "p.csv");
    REQUIRE(p.size() == 3);
    CHECK(p[0] == vec3(1, 2, 3));
    CHECK(p[1] == vec3(-45, 6, 7));
    CHECK(p[2] == vec3(8, 9, 10));
}

TEST_CASE("points: malformed numbers are refused with their line, never read partly", "[io][points]") {
    CHECK_THROWS_WITH(io::parse_points_csv("1,2,3\n1.2.3,4\n", "p.csv"), Contains("p.csv:2") && Contains("'1.2.3' is not a number"));
    CHECK_THROWS_WITH(io::parse_points_csv("1,2\n", "p.csv"), Contains("p.csv:1") && Contains("found 2"));
    CHECK_THROWS_WITH(io::parse_points_csv("1,2,3,4\n", "p.csv"), Contains("found 4"));
    CHECK_THROWS_WITH(io::parse_points_csv("1,2,4x\n", "p.csv"), Contains("'4x'"));
    CHECK_THROWS_WITH(io::parse_points_csv("1,2,nan\n", "p.csv"), Contains("not finite"));
    CHECK_THROWS_WITH(io::parse_points_csv("1,2,1e999\n", "p.csv"), Contains("1e999"));
    CHECK_THROWS_AS(io::parse_points_csv("1,,2\n3", "p.csv"), io_error);
}

TEST_CASE("points: format -> parse round trip is exact", "[io][points]") {
    const std::vector<vec3> pts{{0.1, -2.5e-300, 1e300}, {1.0 / 3.0, std::nextafter(1.0, 2.0), -0.0}};
    const auto back = io::parse_points_csv(io::format_points_csv(pts), "rt");
    REQUIRE(back.size() == 2);
    for (std::size_t i = 0; i < 2; ++i)
        for (int a = 0; a < 3; ++a) CHECK(back[i][a] == pts[i][a]);
}

TEST_CASE("numbers: any count per line, the same strict tokens as points", "[io][numbers]") {
    CHECK(io::parse_numbers("# ids\n0 1 2\r\n\n  7,8\t+9\n-1.5e1\n", "n.txt") == std::vector<double>{0, 1, 2, 7, 8, 9, -15});
    CHECK(io::parse_numbers("", "n.txt").empty());
    CHECK_THROWS_WITH(io::parse_numbers("1 2\n3 4x\n", "n.txt"), Contains("n.txt:2") && Contains("'4x' is not a number"));
    CHECK_THROWS_WITH(io::parse_numbers("0x10\n", "n.txt"), Contains("n.txt:1") && Contains("'0x10'"));
    CHECK_THROWS_WITH(io::parse_numbers("1\n\ninf\n", "n.txt"), Contains("n.txt:3") && Contains("not finite"));
    CHECK_THROWS_WITH(io::read_numbers("/nonexistent/n.txt"), Contains("/nonexistent/n.txt") && Contains("does not exist"));
}
