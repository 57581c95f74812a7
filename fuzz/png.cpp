// libFuzzer target: io::parse_png, parse_png16 and parse_png_info (libspng from memory behind our
// signature and size checks). The pixel limit is lowered to 2^22 so a forged header cannot
// exhaust the fuzzer's memory.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fabsynth/io/image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    constexpr std::uint64_t limit = std::uint64_t{1} << 22;
    try {
        (void)fabsynth::io::parse_png_info(bytes, "fuzz.png", limit);
    } catch (const fabsynth::error&) {
    }
    try {
        // Decoding the same bytes at both depths must agree (16-bit samples keep their high byte).
        const fabsynth::image8 a = fabsynth::io::parse_png(bytes, "fuzz.png", limit);
        const fabsynth::image16 b = fabsynth::io::parse_png16(bytes, "fuzz.png", limit);
        if (a.width != b.width || a.height != b.height || a.channels != b.channels || a.data.size() != b.data.size())
            __builtin_trap();
        for (std::size_t i = 0; i < a.data.size(); ++i)
            if (a.data[i] != (b.data[i] >> 8)) __builtin_trap();
    } catch (const fabsynth::error&) {
    }
    return 0;
}
