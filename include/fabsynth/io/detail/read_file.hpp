// SPDX-License-Identifier: MIT
#pragma once
/// @file read_file.hpp  Reads a whole file into memory (the readers then parse from memory).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "fabsynth/core/error.hpp"

namespace fabsynth::io::detail {

/// Largest file the readers accept (4 GiB): larger inputs are refused before any allocation.
inline constexpr std::uintmax_t max_file_bytes = std::uintmax_t{1} << 32;

/// The bytes of `path`. Throws io_error naming the file if it is missing, a directory,
/// unreadable or larger than max_file_bytes.
inline std::string read_file(const std::filesystem::path& path) {
    namespace fs = std::filesystem;
    const std::string name = path.string();
    std::error_code ec;
    if (!fs::exists(path, ec)) throw io_error(name, 0, "file does not exist");
    if (fs::is_directory(path, ec)) throw io_error(name, 0, "is a directory, not a file");
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec) throw io_error(name, 0, std::string("cannot determine file size: ") + ec.message());
    if (size > max_file_bytes)
        throw io_error(name, 0, std::string("file has ") + std::to_string(size) + " bytes, more than the limit of " +
                                    std::to_string(max_file_bytes));
    std::ifstream in(path, std::ios::binary);
    if (!in) throw io_error(name, 0, "cannot open for reading");
    std::string bytes(static_cast<std::size_t>(size), '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(size));
    if (static_cast<std::uintmax_t>(in.gcount()) != size) throw io_error(name, 0, "read failed");
    return bytes;
}

}  // namespace fabsynth::io::detail
