// SPDX-License-Identifier: MIT
#pragma once
/// @file huge_pages.hpp  Transparent huge pages for large, freshly allocated arrays.
///
/// A large block from malloc is a fresh anonymous mapping whose pages the kernel supplies one
/// 4 KiB fault at a time on first touch; on virtual machines a fault costs microseconds, so filling
/// a sparse matrix or a Cholesky factor of a few hundred MB can take longer than computing it.
/// Advising the block as MADV_HUGEPAGE (Linux, when /sys/kernel/mm/transparent_hugepage/enabled
/// is "madvise" or "always") lets the kernel map it 2 MiB at a time. Advice is only a hint: where
/// it is unsupported or refused, nothing changes.
///
/// Usage:
///   std::vector<double> v;  v.reserve(n);  fabsynth::advise_huge_pages(v.data(), n * sizeof(double));
///   void* p = fabsynth::malloc_huge(bytes);   // freed with std::free
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace fabsynth {

/// Blocks below this size are left alone (the advice needs whole 2 MiB pages inside the block).
inline constexpr std::size_t huge_page_min_bytes = std::size_t(8) << 20;

/// Advises the whole 2 MiB pages inside [p, p + bytes) as huge pages. Call before first touch.
inline void advise_huge_pages(const void* p, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (!p || bytes < huge_page_min_bytes) return;
    constexpr std::uintptr_t page = std::uintptr_t(2) << 20;
    const auto begin = (reinterpret_cast<std::uintptr_t>(p) + page - 1) & ~(page - 1);
    const auto end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(page - 1);
    if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)p, (void)bytes;
#endif
}

/// std::malloc, advising large blocks as huge pages; free with std::free.
inline void* malloc_huge(std::size_t bytes) noexcept {
    void* p = std::malloc(bytes);
    advise_huge_pages(p, bytes);
    return p;
}

/// std::calloc with the same advice (a fresh mapping is zero without being touched).
inline void* calloc_huge(std::size_t count, std::size_t size) noexcept {
    void* p = std::calloc(count, size);
    if (p && size && count <= SIZE_MAX / size) advise_huge_pages(p, count * size);
    return p;
}

}  // namespace fabsynth
