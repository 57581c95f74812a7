// SPDX-License-Identifier: MIT
#pragma once
/// @file image.hpp  Raster files: PNG (via libspng) and PGM (P2 ASCII / P5 binary, own parser).
///
/// Images are fabsynth::image8 / image16 (core/image.hpp): row-major from the top-left pixel,
/// `channels` interleaved samples per pixel (1 = grey, 2 = grey+alpha, 3 = RGB, 4 = RGBA).
///
/// PNG: read_png gives 8 bits per sample (16-bit files keep their high byte, 1/2/4-bit grey is
/// scaled to 0..255), read_png16 16 bits (8-bit samples v become 257 v, so 255 -> 65535).
/// Files keep their channel count; palette images read as RGB, or RGBA if they have a tRNS
/// chunk; a tRNS colour key on grey or RGB images adds an alpha channel. Writers take 8- or
/// 16-bit images and can store the physical pixel size as a pHYs chunk, which read_png_info
/// gives back. pHYs holds whole pixels per metre, so the size reads back as 1000 / round(1000 /
/// pixel_mm) mm (0.05 mm exactly; 0.03 mm as 0.0300003 mm).
///
/// Readers refuse images of more than max_image_pixels (2^28) pixels with invalid_input before
/// decoding, and throw io_error naming the file for anything malformed (for PGM with the line of
/// the bad header token or sample, or the byte offset where binary data runs short; for PNG with
/// libspng's reason: bad CRC, truncated or corrupt data, invalid header fields).
///
/// Usage:
///   fabsynth::image8 ex = fabsynth::io::read_png(FABSYNTH_DATA_DIR "/exemplars/zebra.png");
///   fabsynth::io::write_png("slice.png", ex, {.pixel_mm = 0.05});   // 20000 pixels per metre
///   const auto info = fabsynth::io::read_png_info("slice.png");    // info.pixel_mm == vec2(0.05)
#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <spng.h>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/image.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/io/atomic_file.hpp"
#include "fabsynth/io/detail/binary.hpp"
#include "fabsynth/io/detail/read_file.hpp"
#include "fabsynth/io/detail/text.hpp"
#include "fabsynth/io/encoding.hpp"

namespace fabsynth::io {

/// Largest image (width * height) any reader accepts.
inline constexpr std::uint64_t max_image_pixels = std::uint64_t{1} << 28;

// ---------------------------------------------------------------------------------------- PNG

/// What a PNG header says, without decoding the pixels.
struct png_info {
    int width = 0;
    int height = 0;
    int channels = 0;   ///< as read_png returns them (palette: 3, or 4 with tRNS; a tRNS key adds alpha)
    int bit_depth = 0;  ///< bits per sample in the file: 1, 2, 4, 8 or 16
    /// Physical pixel size (mm, x and y) from a pHYs chunk in pixels per metre; empty if the file
    /// has none, or one with unit "unknown" (an aspect ratio only).
    std::optional<vec2> pixel_mm;
};

/// Options of the PNG writers.
struct png_options {
    /// Physical size of one (square) pixel in mm, stored as a pHYs chunk of round(1000 / pixel_mm)
    /// pixels per metre; 0 writes no pHYs. Must be finite and give 1 .. 2^31-1 pixels per metre.
    double pixel_mm = 0;
};

namespace detail {

struct spng_ctx_deleter {
    void operator()(spng_ctx* c) const noexcept { spng_ctx_free(c); }
};
using spng_ctx_ptr = std::unique_ptr<spng_ctx, spng_ctx_deleter>;

/// A decoder over `bytes` with the header read and checked; what to decode it to.
struct png_decoder {
    spng_ctx_ptr ctx;
    spng_ihdr ihdr{};
    png_info info;
    int fmt = SPNG_FMT_RAW;  // libspng output format for decode_image
    int flags = 0;           // SPNG_DECODE_TRNS where a tRNS chunk becomes alpha
    int sample_bytes = 1;    // 1 or 2 in the decoded buffer
    bool big_endian = false; // SPNG_FMT_RAW is big-endian, the other 16-bit formats host order
};

inline png_decoder open_png(std::string_view bytes, std::string_view name, std::uint64_t max_pixels) {
    static constexpr unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (bytes.empty()) throw io_error(name, 0, "file is empty");
    for (std::size_t i = 0; i < 8; ++i)
        if (i >= bytes.size() || static_cast<unsigned char>(bytes[i]) != signature[i])
            throw io_error::at_byte(name, i, "not a PNG file (bad signature)");
    // The size limit is checked on the raw IHDR fields first, before libspng allocates anything
    // (and before its CRC check, so a forged size is reported as a size).
    if (bytes.size() >= 24 && bytes.substr(12, 4) == "IHDR") {
        const std::uint64_t w = load<std::uint32_t>(bytes.data() + 16, byte_order::big);
        const std::uint64_t h = load<std::uint32_t>(bytes.data() + 20, byte_order::big);
        if (w * h > max_pixels)
            throw invalid_input(std::string(name) + ": PNG of " + std::to_string(w) + "x" + std::to_string(h) +
                                " pixels exceeds the limit of " + std::to_string(max_pixels) + " pixels");
    }
    png_decoder d;
    d.ctx.reset(spng_ctx_new(0));
    if (!d.ctx) throw std::bad_alloc();
    // No chunk can be longer than the file; decompressed ancillary data (text, ICC) is capped.
    spng_set_chunk_limits(d.ctx.get(), bytes.size(), std::size_t{1} << 26);
    if (int r = spng_set_png_buffer(d.ctx.get(), bytes.data(), bytes.size()))
        throw io_error(name, 0, std::string("cannot read PNG: ") + spng_strerror(r));
    if (int r = spng_get_ihdr(d.ctx.get(), &d.ihdr)) throw io_error(name, 0, std::string("corrupt PNG header: ") + spng_strerror(r));
    const std::uint64_t w = d.ihdr.width, h = d.ihdr.height;
    if (w == 0 || h == 0 || w > INT_MAX || h > INT_MAX)
        throw io_error(name, 0, std::string("PNG has invalid size ") + std::to_string(w) + "x" + std::to_string(h));
    if (w * h > max_pixels)
        throw invalid_input(std::string(name) + ": PNG of " + std::to_string(w) + "x" + std::to_string(h) +
                            " pixels exceeds the limit of " + std::to_string(max_pixels) + " pixels");
    spng_trns trns{};
    const int trns_state = spng_get_trns(d.ctx.get(), &trns);
    if (trns_state && trns_state != SPNG_ECHUNKAVAIL)
        throw io_error(name, 0, std::string("corrupt PNG: ") + spng_strerror(trns_state));
    const bool has_trns = trns_state == 0;
    const bool deep = d.ihdr.bit_depth == 16;
    d.info.width = static_cast<int>(w);
    d.info.height = static_cast<int>(h);
    d.info.bit_depth = d.ihdr.bit_depth;
    d.sample_bytes = deep ? 2 : 1;
    switch (d.ihdr.color_type) {
        case SPNG_COLOR_TYPE_GRAYSCALE:
            if (has_trns) {
                d.info.channels = 2, d.fmt = deep ? SPNG_FMT_GA16 : SPNG_FMT_GA8, d.flags = SPNG_DECODE_TRNS;
            } else {
                d.info.channels = 1, d.fmt = d.ihdr.bit_depth >= 8 ? SPNG_FMT_RAW : SPNG_FMT_G8;
                d.big_endian = d.fmt == SPNG_FMT_RAW;  // SPNG_FMT_G8 scales 1/2/4-bit grey to 0..255
            }
            break;
        case SPNG_COLOR_TYPE_TRUECOLOR:
            if (has_trns) d.info.channels = 4, d.fmt = deep ? SPNG_FMT_RGBA16 : SPNG_FMT_RGBA8, d.flags = SPNG_DECODE_TRNS;
            else d.info.channels = 3, d.fmt = SPNG_FMT_RAW, d.big_endian = true;
            break;
        case SPNG_COLOR_TYPE_INDEXED:
            d.info.channels = has_trns ? 4 : 3, d.fmt = has_trns ? SPNG_FMT_RGBA8 : SPNG_FMT_RGB8;
            d.flags = has_trns ? SPNG_DECODE_TRNS : 0, d.sample_bytes = 1;
            break;
        case SPNG_COLOR_TYPE_GRAYSCALE_ALPHA: d.info.channels = 2, d.fmt = SPNG_FMT_RAW, d.big_endian = true; break;
        case SPNG_COLOR_TYPE_TRUECOLOR_ALPHA: d.info.channels = 4, d.fmt = SPNG_FMT_RAW, d.big_endian = true; break;
        default: throw io_error(name, 0, "PNG has invalid colour type " + std::to_string(d.ihdr.color_type));
    }
    spng_phys phys{};
    const int phys_state = spng_get_phys(d.ctx.get(), &phys);
    if (phys_state && phys_state != SPNG_ECHUNKAVAIL)
        throw io_error(name, 0, std::string("corrupt PNG: ") + spng_strerror(phys_state));
    if (phys_state == 0 && phys.unit_specifier == 1 && phys.ppu_x > 0 && phys.ppu_y > 0)
        d.info.pixel_mm = vec2(1000.0 / phys.ppu_x, 1000.0 / phys.ppu_y);
    return d;
}

template <class T>
image<T> decode_png(std::string_view bytes, std::string_view name, std::uint64_t max_pixels) {
    static_assert(std::is_same_v<T, std::uint8_t> || std::is_same_v<T, std::uint16_t>);
    png_decoder d = open_png(bytes, name, max_pixels);
    const std::size_t samples = static_cast<std::size_t>(d.info.width) * static_cast<std::size_t>(d.info.height) *
                                static_cast<std::size_t>(d.info.channels);
    std::size_t size = 0;
    if (int r = spng_decoded_image_size(d.ctx.get(), d.fmt, &size))
        throw io_error(name, 0, std::string("corrupt PNG header: ") + spng_strerror(r));
    if (size != samples * static_cast<std::size_t>(d.sample_bytes)) throw io_error(name, 0, "PNG header and decoded size disagree");
    std::vector<unsigned char> buf(size);
    if (int r = spng_decode_image(d.ctx.get(), buf.data(), buf.size(), d.fmt, d.flags))
        throw io_error(name, 0, std::string("corrupt PNG data: ") + spng_strerror(r));
    image<T> img(d.info.width, d.info.height, d.info.channels);
    const auto* p = reinterpret_cast<const char*>(buf.data());
    const auto order = d.big_endian ? byte_order::big : (std::endian::native == std::endian::little ? byte_order::little : byte_order::big);
    for (std::size_t i = 0; i < samples; ++i) {
        const unsigned v = d.sample_bytes == 2 ? load<std::uint16_t>(p + 2 * i, order) : static_cast<unsigned char>(p[i]);
        if constexpr (sizeof(T) == 1)
            img.data[i] = static_cast<T>(d.sample_bytes == 2 ? v >> 8 : v);
        else
            img.data[i] = static_cast<T>(d.sample_bytes == 2 ? v : v * 257u);
    }
    return img;
}

inline void check_image_for_writing(int w, int h, int c, std::size_t samples, const std::string& file) {
    if (w <= 0 || h <= 0 || c < 1 || c > 4)
        throw invalid_input(file + ": cannot write an image of size " + std::to_string(w) + "x" + std::to_string(h) +
                            "x" + std::to_string(c));
    if (samples != static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(c))
        throw invalid_input(file + ": image data has " + std::to_string(samples) + " samples, expected width*height*channels");
    if (static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > max_image_pixels)
        throw invalid_input(file + ": image exceeds the limit of " + std::to_string(max_image_pixels) + " pixels");
}

template <class T>
std::string encode_png(const image<T>& img, const png_options& opt, std::string_view name) {
    const std::string file(name);
    check_image_for_writing(img.width, img.height, img.channels, img.data.size(), file);
    std::uint32_t ppm = 0;
    if (opt.pixel_mm != 0) {
        const double per_metre = 1000.0 / opt.pixel_mm;
        if (!(std::isfinite(opt.pixel_mm) && opt.pixel_mm > 0 && per_metre >= 0.5 && per_metre < 2147483647.5))
            throw invalid_input(file + ": PNG pixel size " + std::to_string(opt.pixel_mm) +
                                " mm must be > 0 and give 1 .. 2^31-1 pixels per metre");
        ppm = static_cast<std::uint32_t>(std::llround(per_metre));
    }
    spng_ctx_ptr ctx(spng_ctx_new(SPNG_CTX_ENCODER));
    if (!ctx) throw std::bad_alloc();
    auto check = [&](int r, const char* step) {
        if (r) throw io_error(name, 0, std::string("PNG encoding failed (") + step + "): " + spng_strerror(r));
    };
    check(spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1), "buffer");
    static constexpr std::uint8_t colour_type[5] = {0, SPNG_COLOR_TYPE_GRAYSCALE, SPNG_COLOR_TYPE_GRAYSCALE_ALPHA,
                                                    SPNG_COLOR_TYPE_TRUECOLOR, SPNG_COLOR_TYPE_TRUECOLOR_ALPHA};
    spng_ihdr ihdr{};
    ihdr.width = static_cast<std::uint32_t>(img.width);
    ihdr.height = static_cast<std::uint32_t>(img.height);
    ihdr.bit_depth = sizeof(T) * 8;
    ihdr.color_type = colour_type[img.channels];
    check(spng_set_ihdr(ctx.get(), &ihdr), "header");
    if (ppm) {
        spng_phys phys{ppm, ppm, 1};
        check(spng_set_phys(ctx.get(), &phys), "pHYs");
    }
    int r = 0;
    if constexpr (sizeof(T) == 1) {
        r = spng_encode_image(ctx.get(), img.data.data(), img.data.size(), SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
    } else {  // SPNG_FMT_RAW: samples in PNG (big-endian) order
        std::string be;
        be.reserve(2 * img.data.size());
        for (std::uint16_t v : img.data) store(be, v, byte_order::big);
        r = spng_encode_image(ctx.get(), be.data(), be.size(), SPNG_FMT_RAW, SPNG_ENCODE_FINALIZE);
    }
    check(r, "image");
    std::size_t len = 0;
    int err = 0;
    const std::unique_ptr<void, void (*)(void*)> png(spng_get_png_buffer(ctx.get(), &len, &err), &std::free);
    if (!png || err) throw io_error(name, 0, std::string("PNG encoding failed: ") + spng_strerror(err));
    return {static_cast<const char*>(png.get()), len};
}

}  // namespace detail

/// Decodes PNG bytes to 8 bits per sample, keeping the file's channel count (16-bit samples keep
/// their high byte, 1/2/4-bit grey is scaled to 0..255). Images larger than `max_pixels` are
/// refused with invalid_input before decoding (the fuzzer passes a smaller bound). `name`
/// prefixes error messages.
inline image8 parse_png(std::string_view bytes, std::string_view name, std::uint64_t max_pixels = max_image_pixels) {
    return detail::decode_png<std::uint8_t>(bytes, name, max_pixels);
}
/// Decodes PNG bytes to 16 bits per sample (lower depths scaled to 0..65535; see parse_png).
inline image16 parse_png16(std::string_view bytes, std::string_view name, std::uint64_t max_pixels = max_image_pixels) {
    return detail::decode_png<std::uint16_t>(bytes, name, max_pixels);
}
/// Size, channels, bit depth and pixel size (pHYs) of PNG bytes, without decoding the pixels.
inline png_info parse_png_info(std::string_view bytes, std::string_view name, std::uint64_t max_pixels = max_image_pixels) {
    return detail::open_png(bytes, name, max_pixels).info;
}

/// Reads a PNG file (1..4 channels, 8 bits per sample).
inline image8 read_png(const std::filesystem::path& path) { return parse_png(detail::read_file(path), path.string()); }
/// Reads a PNG file (1..4 channels, 16 bits per sample).
inline image16 read_png16(const std::filesystem::path& path) { return parse_png16(detail::read_file(path), path.string()); }
/// Reads the header and pHYs chunk of a PNG file (see png_info).
inline png_info read_png_info(const std::filesystem::path& path) { return parse_png_info(detail::read_file(path), path.string()); }

/// PNG bytes of an 8-bit image with 1..4 channels.
inline std::string format_png(const image8& img, std::string_view name = "PNG") { return detail::encode_png(img, {}, name); }
/// PNG bytes of an 8-bit image with 1..4 channels, with the options' pHYs chunk.
inline std::string format_png(const image8& img, const png_options& opt, std::string_view name = "PNG") {
    return detail::encode_png(img, opt, name);
}
/// PNG bytes of a 16-bit image with 1..4 channels (stored at 16 bits per sample).
inline std::string format_png(const image16& img, const png_options& opt = {}, std::string_view name = "PNG") {
    return detail::encode_png(img, opt, name);
}

/// Writes an 8-bit image with 1..4 channels as PNG (atomically), e.g.
/// write_png("slice.png", img, {.pixel_mm = 0.05}). Throws invalid_input for an empty or
/// inconsistent image or a bad pixel size, io_error if writing fails.
inline void write_png(const std::filesystem::path& path, const image8& img, const png_options& opt = {}) {
    atomic_write(path, detail::encode_png(img, opt, path.string()));
}
/// Writes a 16-bit image with 1..4 channels as a 16-bit PNG (atomically); see above.
inline void write_png(const std::filesystem::path& path, const image16& img, const png_options& opt = {}) {
    atomic_write(path, detail::encode_png(img, opt, path.string()));
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
    atomic_write(path, detail::format_pgm_as(img, enc, path.string()));
}
/// Writes a 1-channel 16-bit image as PGM with maxval 65535 (P5 stores big-endian 16-bit samples).
inline void write_pgm(const std::filesystem::path& path, const image16& img, encoding enc = encoding::binary) {
    atomic_write(path, detail::format_pgm_as(img, enc, path.string()));
}

}  // namespace fabsynth::io
