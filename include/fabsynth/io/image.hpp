#pragma once
/// @file image.hpp  Raster files: PNG (via stb) and PGM (P2 ASCII / P5 binary, own parser).
///
/// Images are fabsynth::image8 / image16 (core/image.hpp): row-major from the top-left pixel,
/// `channels` interleaved samples per pixel (1 = grey, 2 = grey+alpha, 3 = RGB, 4 = RGBA).
///
/// Readers refuse images of more than max_image_pixels (2^28) pixels with invalid_input before
/// decoding, and throw io_error naming the file for anything malformed (for PGM with the line of
/// the bad header token or sample, or the byte offset where binary data runs short).
///
/// Usage:
///   fabsynth::image8 ex = fabsynth::io::read_png(FABSYNTH_DATA_DIR "/exemplars/zebra.png");
///   fabsynth::io::write_png("preview.png", ex);
#include <algorithm>
#include <climits>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>

#include <stb_image.h>
#include <stb_image_write.h>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/io/detail/atomic_file.hpp"
#include "fabsynth/io/detail/binary.hpp"
#include "fabsynth/io/detail/read_file.hpp"
#include "fabsynth/io/detail/text.hpp"
#include "fabsynth/io/encoding.hpp"

namespace fabsynth::io {

/// Largest image (width * height) any reader accepts.
inline constexpr std::uint64_t max_image_pixels = std::uint64_t{1} << 28;

// ---------------------------------------------------------------------------------------- PNG

/// Decodes PNG bytes to 8 bits per sample, keeping the file's channel count (16-bit PNGs are
/// reduced to 8 bits by stb). Images larger than `max_pixels` are refused with invalid_input
/// before decoding (the fuzzer passes a smaller bound). `name` prefixes error messages.
inline image8 parse_png(std::string_view bytes, std::string_view name, std::uint64_t max_pixels = max_image_pixels) {
    static constexpr unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (bytes.empty()) throw io_error(name, 0, "file is empty");
    for (std::size_t i = 0; i < 8; ++i)
        if (i >= bytes.size() || static_cast<unsigned char>(bytes[i]) != signature[i])
            throw io_error::at_byte(name, i, "not a PNG file (bad signature)");
    if (bytes.size() > static_cast<std::size_t>(INT_MAX)) throw io_error(name, 0, "PNG file too large for the decoder");
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int len = static_cast<int>(bytes.size());
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(data, len, &w, &h, &comp))
        throw io_error(name, 0, std::string("corrupt PNG header: ") + stbi_failure_reason());
    if (w <= 0 || h <= 0 || comp < 1 || comp > 4)
        throw io_error(name, 0, std::string("PNG has invalid size ") + std::to_string(w) + "x" + std::to_string(h));
    if (static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > max_pixels)
        throw invalid_input(std::string(name) + ": PNG of " + std::to_string(w) + "x" + std::to_string(h) +
                            " pixels exceeds the limit of " + std::to_string(max_pixels) + " pixels");
    int w2 = 0, h2 = 0, comp2 = 0;
    const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(stbi_load_from_memory(data, len, &w2, &h2, &comp2, 0),
                                                           &stbi_image_free);
    if (!pixels) throw io_error(name, 0, std::string("corrupt PNG data: ") + stbi_failure_reason());
    if (w2 != w || h2 != h || comp2 != comp) throw io_error(name, 0, "PNG header and decoded data disagree");
    image8 img(w, h, comp);
    std::copy(pixels.get(), pixels.get() + img.data.size(), img.data.begin());
    return img;
}

/// Reads a PNG file (1..4 channels, 8 bits per sample).
inline image8 read_png(const std::filesystem::path& path) {
    return parse_png(detail::read_file(path), path.string());
}

namespace detail {
inline void check_image_for_writing(int w, int h, int c, std::size_t samples, const std::string& file) {
    if (w <= 0 || h <= 0 || c < 1 || c > 4)
        throw invalid_input(file + ": cannot write an image of size " + std::to_string(w) + "x" + std::to_string(h) +
                            "x" + std::to_string(c));
    if (samples != static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(c))
        throw invalid_input(file + ": image data has " + std::to_string(samples) + " samples, expected width*height*channels");
    if (static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > max_image_pixels)
        throw invalid_input(file + ": image exceeds the limit of " + std::to_string(max_image_pixels) + " pixels");
}
}  // namespace detail

/// PNG bytes of an 8-bit image with 1..4 channels.
inline std::string format_png(const image8& img, std::string_view name = "PNG") {
    detail::check_image_for_writing(img.width, img.height, img.channels, img.data.size(), std::string(name));
    std::string out;
    auto append = [](void* ctx, void* data, int size) {
        static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
    };
    if (!stbi_write_png_to_func(append, &out, img.width, img.height, img.channels, img.data.data(),
                                img.width * img.channels))
        throw io_error(name, 0, "PNG encoding failed");
    return out;
}

/// Writes an 8-bit image with 1..4 channels as PNG (atomically). Throws invalid_input for an
/// empty or inconsistent image, io_error if writing fails.
inline void write_png(const std::filesystem::path& path, const image8& img) {
    detail::atomic_write(path, format_png(img, path.string()));
}

// ---------------------------------------------------------------------------------------- PGM

namespace detail {
template <class T>
image<T> parse_pgm_as(std::string_view bytes, std::string_view name) {
    if (bytes.empty()) throw io_error(name, 0, "file is empty");
    token_cursor c(bytes, name);
    auto header_token = [&](std::string_view what) {
        for (;;) {
            const std::string_view t = c.require(what);
            if (t[0] != '#') return t;
            c.skip_line();  // comment
        }
    };
    const std::string_view magic = c.next();
    const bool ascii = magic == "P2";
    if (!ascii && magic != "P5") c.fail(std::string("not a PGM file (expected magic 'P2' or 'P5', found ") + quote(magic) + ")");
    const auto w = c.integer(header_token("width"), "width", 1, INT_MAX);
    const auto h = c.integer(header_token("height"), "height", 1, INT_MAX);
    const auto maxval = c.integer(header_token("maxval"), "maxval", 1, 65535);
    if (static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > max_image_pixels)
        throw invalid_input(std::string(name) + ": PGM of " + std::to_string(w) + "x" + std::to_string(h) +
                            " pixels exceeds the limit of " + std::to_string(max_image_pixels) + " pixels");
    if (maxval > std::numeric_limits<T>::max())
        c.fail(std::string("maxval ") + std::to_string(maxval) + " needs 16-bit samples (use read_pgm16)");
    const std::size_t count = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    if (ascii) {
        if (count > c.remaining() / 2 + 1)
            c.fail(std::string("file is too short for ") + std::to_string(w) + "x" + std::to_string(h) + " samples");
        image<T> img(static_cast<int>(w), static_cast<int>(h), 1);
        for (std::size_t i = 0; i < count; ++i)
            img.data[i] = static_cast<T>(c.integer(c.require(std::string("pixel value ") + std::to_string(i)), "pixel value", 0, maxval));
        return img;
    }
    // P5: exactly one whitespace byte separates maxval from the raster.
    const std::size_t start = c.offset() + 1;
    if (c.offset() >= bytes.size() || !is_space(bytes[c.offset()]))
        c.fail_at_byte(c.offset(), "expected one whitespace byte before the binary raster");
    const std::size_t bps = maxval > 255 ? 2 : 1;
    if ((bytes.size() - start) / bps < count)
        c.fail_at_byte(bytes.size(), std::string("binary raster truncated: ") + std::to_string(count * bps) + " bytes needed from byte " +
                                         std::to_string(start) + ", " + std::to_string(bytes.size() - start) + " present");
    image<T> img(static_cast<int>(w), static_cast<int>(h), 1);
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t at = start + i * bps;
        const unsigned v = bps == 2 ? load<std::uint16_t>(bytes.data() + at, byte_order::big)
                                    : static_cast<unsigned char>(bytes[at]);
        if (v > static_cast<unsigned>(maxval))
            c.fail_at_byte(at, std::string("sample ") + std::to_string(v) + " exceeds maxval " + std::to_string(maxval));
        img.data[i] = static_cast<T>(v);
    }
    return img;
}

template <class T>
std::string format_pgm_as(const image<T>& img, encoding enc, const std::string& name) {
    detail::check_image_for_writing(img.width, img.height, img.channels, img.data.size(), name);
    if (img.channels != 1) throw invalid_input(name + ": PGM needs a 1-channel image, got " + std::to_string(img.channels));
    const unsigned maxval = sizeof(T) == 1 ? 255u : 65535u;
    std::string out = enc == encoding::ascii ? "P2\n" : "P5\n";
    out += std::to_string(img.width) + " " + std::to_string(img.height) + "\n" + std::to_string(maxval) + "\n";
    if (enc == encoding::binary) {
        for (T v : img.data) {
            if constexpr (sizeof(T) == 1) out += static_cast<char>(v);
            else store(out, static_cast<std::uint16_t>(v), byte_order::big);
        }
        return out;
    }
    for (std::size_t i = 0; i < img.data.size(); ++i) {
        append_number(out, static_cast<std::int64_t>(img.data[i]));
        out += (i + 1) % 12 == 0 || i + 1 == img.data.size() ? '\n' : ' ';  // PGM asks for lines <= 70 chars
    }
    return out;
}
}  // namespace detail

/// Parses P2/P5 bytes with maxval <= 255 (samples kept as stored, not rescaled).
inline image8 parse_pgm(std::string_view bytes, std::string_view name) { return detail::parse_pgm_as<std::uint8_t>(bytes, name); }
/// Parses P2/P5 bytes with any maxval (<= 65535), samples as stored.
inline image16 parse_pgm16(std::string_view bytes, std::string_view name) {
    return detail::parse_pgm_as<std::uint16_t>(bytes, name);
}
/// Reads an 8-bit PGM (P2 or P5, maxval <= 255; a larger maxval is an io_error suggesting read_pgm16).
inline image8 read_pgm(const std::filesystem::path& path) { return parse_pgm(detail::read_file(path), path.string()); }
/// Reads a PGM with up to 16-bit samples.
inline image16 read_pgm16(const std::filesystem::path& path) { return parse_pgm16(detail::read_file(path), path.string()); }

/// Writes a 1-channel image as PGM: P5 (binary, default) or P2, maxval 255. Atomic.
inline void write_pgm(const std::filesystem::path& path, const image8& img, encoding enc = encoding::binary) {
    detail::atomic_write(path, detail::format_pgm_as(img, enc, path.string()));
}
/// Writes a 1-channel 16-bit image as PGM with maxval 65535 (P5 stores big-endian 16-bit samples).
inline void write_pgm(const std::filesystem::path& path, const image16& img, encoding enc = encoding::binary) {
    detail::atomic_write(path, detail::format_pgm_as(img, enc, path.string()));
}

}  // namespace fabsynth::io
