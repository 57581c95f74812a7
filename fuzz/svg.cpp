// libFuzzer target for the SVG reader: any input must either parse or throw fabsynth::error.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fabsynth/io/svg.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        // A lower point limit than the default keeps every run fast and small in memory.
        const auto doc = fabsynth::io::parse_svg(text, "fuzz.svg", {.tolerance = 0.01, .max_points = 1'000'000});
        // Whatever was read must be writable and read back identically.
        const std::string again = fabsynth::io::to_svg_string(doc);
        const auto back = fabsynth::io::parse_svg(again, "fuzz-roundtrip.svg", {.tolerance = 0.01, .max_points = 1'000'000});
        if (!(back == doc)) __builtin_trap();
    } catch (const fabsynth::error&) {
    }
    return 0;
}
