// A bundled filigree element (data/filigree/NAME.svg) scaled to `size` mm with strips `width` mm
// wide (the set-up of the filigree tests).
#pragma once

#include <filesystem>
#include <string>

#include "fabsynth/filigree/element.hpp"
#include "fabsynth/io/svg.hpp"

namespace fabsynth::test {

inline filigree::element filigree_element(const std::string& name, double size = 20, double width = 0.8) {
    filigree::element_options o;
    o.size_mm = size;
    o.width_mm = width;
    o.name = name;
    return filigree::element_from_svg(io::read_svg(std::filesystem::path(FABSYNTH_DATA_DIR) / "filigree" / (name + ".svg"), 0.01), o);
}

}  // namespace fabsynth::test
