// SPDX-License-Identifier: MIT
#pragma once
/// @file chunked_store.hpp  Internal: append-only array in fixed-size chunks.
///
/// Unlike std::vector it never over-allocates by up to 2x nor copies on growth, so a DP table's
/// memory is its size rounded up to one chunk. Each element is a row of `row` values of T.
#include <cstddef>
#include <vector>

namespace fabsynth::dp::detail {

template <class T, unsigned ChunkBits = 13>
class chunked_store {
public:
    /// row = values per element; chunks hold 2^ChunkBits elements (a power of two: index math is shifts).
    explicit chunked_store(std::size_t row = 1) : row_(row) {}

    /// Appends one element (row values of `fill`); returns its index.
    std::size_t push_back(const T& fill) {
        if (size_ % chunk_ == 0) {
            chunks_.emplace_back();
            chunks_.back().reserve(chunk_ * row_);
        }
        chunks_.back().insert(chunks_.back().end(), row_, fill);
        return size_++;
    }
    /// First value of element i's row.
    [[nodiscard]] T* operator[](std::size_t i) noexcept { return chunks_[i / chunk_].data() + (i % chunk_) * row_; }
    [[nodiscard]] const T* operator[](std::size_t i) const noexcept {
        return chunks_[i / chunk_].data() + (i % chunk_) * row_;
    }
    [[nodiscard]] std::size_t size() const noexcept { return size_; }
    [[nodiscard]] std::size_t memory_bytes() const noexcept {
        return chunks_.size() * chunk_ * row_ * sizeof(T) + chunks_.capacity() * sizeof(std::vector<T>);
    }

private:
    static constexpr std::size_t chunk_ = std::size_t{1} << ChunkBits;
    std::size_t row_;
    std::size_t size_ = 0;
    std::vector<std::vector<T>> chunks_;
};

}  // namespace fabsynth::dp::detail
