// SPDX-License-Identifier: MIT
#pragma once
/// @file atomic_file.hpp  Whole-file output that never leaves a half-written file behind.
///
/// Every writer of io/ goes through it, and so can a driver's own text outputs (reports, CSV):
///   fabsynth::io::atomic_write("report.json", text);
///
/// atomic_write(path, bytes) writes to a temporary file in the target's directory and renames it
/// over the target only after every byte was written and the stream closed without error. A
/// failure (disk full, bad directory, permission) removes the temporary and throws io_error; the
/// previous content of the target, if any, is untouched. rename() within one directory is atomic
/// on POSIX file systems, so a reader sees either the old file or the complete new one.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"

namespace fabsynth::io {

namespace detail {

/// A temporary path next to `target` that no other call (in this or, very likely, another
/// process) uses at the same time. Not reproducible on purpose: it never reaches any result.
inline std::filesystem::path temporary_sibling(const std::filesystem::path& target) {
    static std::atomic<std::uint64_t> counter{0};
    const auto now = static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
    const auto self = static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(&counter));
    const std::uint64_t tag = hash64(now, self, counter.fetch_add(1));
    std::filesystem::path tmp = target;
    tmp += std::string(".fabsynth-tmp-") + std::to_string(tag % 1000000000000ULL);
    return tmp;
}

}  // namespace detail

/// Writes `bytes` to `target` atomically (see file comment). Throws invalid_input for an empty
/// path, io_error naming the target when the directory is missing or any write step fails.
inline void atomic_write(const std::filesystem::path& target, std::string_view bytes) {
    namespace fs = std::filesystem;
    if (target.empty()) throw invalid_input("output path is empty");
    const std::string name = target.string();
    std::error_code ec;
    if (fs::is_directory(target, ec)) throw io_error(name, 0, "cannot write: the path is a directory");
    const fs::path dir = target.parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw io_error(name, 0, std::string("cannot write: directory ") + dir.string() + " does not exist");
    const fs::path tmp = detail::temporary_sibling(target);
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw io_error(name, 0, std::string("cannot create temporary file ") + tmp.string());
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.flush();
        out.close();
        if (!out) {
            fs::remove(tmp, ec);
            throw io_error(name, 0, std::string("writing ") + std::to_string(bytes.size()) + " bytes failed (disk full?)");
        }
    }
    fs::rename(tmp, target, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw io_error(name, 0, std::string("cannot move temporary file into place: ") + ec.message());
    }
}

}  // namespace fabsynth::io
