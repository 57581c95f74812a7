// libFuzzer target: io::parse_ply on arbitrary bytes. Only fabsynth::error may be thrown (and is caught).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fabsynth/io/mesh_ply.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)fabsynth::io::parse_ply(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.ply");
    } catch (const fabsynth::error&) {
    }
    return 0;
}
