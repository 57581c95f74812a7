// libFuzzer target: io::parse_png (stb_image from memory behind our signature and size checks).
// The pixel limit is lowered to 2^22 so a forged header cannot exhaust the fuzzer's memory.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fabsynth/io/image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)fabsynth::io::parse_png(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.png",
                                      std::uint64_t{1} << 22);
    } catch (const fabsynth::error&) {
    }
    return 0;
}
