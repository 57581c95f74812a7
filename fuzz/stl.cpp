// libFuzzer target: io::parse_stl on arbitrary bytes. Only fabsynth::error may be thrown (and is caught).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fabsynth/io/mesh_stl.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)fabsynth::io::parse_stl(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.stl");
    } catch (const fabsynth::error&) {
    }
    return 0;
}
