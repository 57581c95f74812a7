// libFuzzer target: io::parse_pgm16 (16-bit samples, big-endian P5 path).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fabsynth/io/image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)fabsynth::io::parse_pgm16(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.pgm");
    } catch (const fabsynth::error&) {
    }
    return 0;
}
