// SPDX-License-Identifier: MIT
#pragma once
/// @file block_mask.hpp  Sparse voxel sets with O(1) membership and rank: 8x8x8 bit blocks under a
/// dense directory of block slots.
///
/// Usage:
///   fabsynth::block_mask m(geometry, voxels);   // any order; duplicates are stored once
///   if (m.contains({3, 4, 5})) ...;              // O(1), false outside the grid
///   m.insert({7, 7, 7});                         // O(1) (amortised when a block is allocated)
///   m.update_ranks();                            // after changes, before rank()
///   std::int64_t r = m.rank(p);                  // O(1): 0 .. size() - 1 for members, -1 otherwise
///   m.for_each([](fabsynth::ivec3 p) { ... });   // members in grid-index order (x fastest)
///
/// Layout: the grid is cut into blocks of 8x8x8 voxels (partial blocks at the upper borders).
/// The directory holds one 32-bit slot per block of the whole grid (4 bytes per 512 voxels); a
/// block that holds a member gets a slot with 8 64-bit words, word z of a block being its z-layer
/// (bit x + 8 y). Memory is 4 bytes per 512 grid voxels plus 88 bytes per allocated block, so
/// O(grid / 512 + members) with the constant set by how compact the set is (a thin shell fills
/// about 64 of a block's 512 bits); a dense grid of bytes would need 512 bytes per block.
///
/// Ranks number the members 0 .. size() - 1 in block-slot order (the order in which blocks were
/// first touched), then z, y, x inside a block: a bijection usable as a dense index into per-member
/// arrays (it is not the grid-index order; build a permutation if that order is needed).
/// Insertion order alone fixes slots, so ranks are deterministic. Const members are safe to call
/// concurrently; insert() and erase() are not.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/voxel/grid.hpp"

namespace fabsynth {

/// A set of voxels of one grid (see file comment).
class block_mask {
public:
    /// Voxels per block edge.
    static constexpr int block_edge = 8;
    /// Largest directory accepted (blocks): 2^27, i.e. a 4096^3 index space, as sparse grids.
    static constexpr std::uint64_t max_directory = std::uint64_t{1} << 27;

    /// Empty set on a 1x1x1 grid of 1 mm voxels.
    block_mask() : block_mask(grid_geometry{ivec3(1), vec3(0.0), vec3(1.0)}) {}

    /// Empty set on grid g. Throws invalid_input for an invalid grid or a directory of more than
    /// max_directory blocks.
    explicit block_mask(const grid_geometry& g) : geom_(g) {
        geom_.validate("block_mask: grid");
        blocks_ = (g.dims + (block_edge - 1)) / block_edge;
        const std::uint64_t n = static_cast<std::uint64_t>(blocks_.x) * static_cast<std::uint64_t>(blocks_.y) *
                                static_cast<std::uint64_t>(blocks_.z);
        if (n > max_directory)
            throw invalid_input("block_mask: grid of " + std::to_string(g.count()) + " voxels needs " + std::to_string(n) +
                                " blocks, more than the limit of 2^27");
        directory_.assign(static_cast<std::size_t>(n), npos);
    }

    /// The set of `voxels` on grid g (duplicates stored once; ranks ready). Throws invalid_input for
    /// a voxel outside the grid (naming it) or an invalid grid.
    block_mask(const grid_geometry& g, std::span<const ivec3> voxels) : block_mask(g) {
        for (const ivec3& p : voxels) insert(p);
        update_ranks();
    }

    [[nodiscard]] const grid_geometry& geometry() const noexcept { return geom_; }
    /// Number of members.
    [[nodiscard]] std::uint64_t size() const noexcept { return size_; }
    [[nodiscard]] bool empty() const noexcept { return size_ == 0; }
    /// Number of allocated blocks (blocks that hold or held a member).
    [[nodiscard]] std::size_t block_count() const noexcept { return words_.size() / 8; }
    /// Bytes held by the directory and the blocks (capacity, not size, of the vectors).
    [[nodiscard]] std::size_t memory_bytes() const noexcept {
        return directory_.capacity() * sizeof(std::uint32_t) + words_.capacity() * sizeof(std::uint64_t) +
               base_.capacity() * sizeof(std::uint64_t) + prefix_.capacity() * sizeof(std::uint16_t);
    }

    /// True iff p is a member (false for voxels outside the grid). O(1).
    [[nodiscard]] bool contains(const ivec3& p) const noexcept {
        if (!geom_.contains(p)) return false;
        const std::uint32_t slot = directory_[block_of(p)];
        if (slot == npos) return false;
        return ((words_[word_of(slot, p)] >> bit_of(p)) & 1u) != 0;
    }

    /// Adds p; returns true iff it was not a member. Throws invalid_input for a voxel outside the grid.
    bool insert(const ivec3& p) {
        if (!geom_.contains(p))
            throw invalid_input("block_mask: voxel (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " +
                                std::to_string(p.z) + ") is outside the grid");
        std::uint32_t& slot = directory_[block_of(p)];
        if (slot == npos) {
            if (block_count() >= npos) throw invalid_input("block_mask: more than 2^32 - 1 blocks");
            slot = static_cast<std::uint32_t>(block_count());
            words_.resize(words_.size() + 8, 0);
        }
        std::uint64_t& w = words_[word_of(slot, p)];
        const std::uint64_t bit = std::uint64_t{1} << bit_of(p);
        if (w & bit) return false;
        w |= bit;
        ++size_;
        ranks_valid_ = false;
        return true;
    }

    /// Removes p; returns true iff it was a member (its block stays allocated). Voxels outside the
    /// grid are never members.
    bool erase(const ivec3& p) {
        if (!contains(p)) return false;
        words_[word_of(directory_[block_of(p)], p)] &= ~(std::uint64_t{1} << bit_of(p));
        --size_;
        ranks_valid_ = false;
        return true;
    }

    /// Recomputes the rank tables after insert() / erase(). O(blocks).
    void update_ranks() {
        const std::size_t nb = block_count();
        base_.resize(nb);
        prefix_.resize(8 * nb);
        std::uint64_t total = 0;
        for (std::size_t b = 0; b < nb; ++b) {
            base_[b] = total;
            std::uint16_t in_block = 0;
            for (std::size_t z = 0; z < 8; ++z) {
                prefix_[8 * b + z] = in_block;
                in_block = static_cast<std::uint16_t>(in_block + std::popcount(words_[8 * b + z]));
            }
            total += in_block;
        }
        ranks_valid_ = true;
    }
    /// False after insert() / erase() until update_ranks().
    [[nodiscard]] bool ranks_valid() const noexcept { return ranks_valid_; }

    /// Rank of p among the members (see file comment), or -1 if p is not a member. O(1). Throws
    /// fabsynth::error if the set changed since the last update_ranks().
    [[nodiscard]] std::int64_t rank(const ivec3& p) const {
        if (!ranks_valid_) throw error("block_mask: rank() after a change without update_ranks()");
        if (!geom_.contains(p)) return -1;
        const std::uint32_t slot = directory_[block_of(p)];
        if (slot == npos) return -1;
        const std::size_t wi = word_of(slot, p);
        const std::uint64_t w = words_[wi];
        const int bit = bit_of(p);
        if (((w >> bit) & 1u) == 0) return -1;
        const std::uint64_t below = bit == 0 ? 0 : (w & ((std::uint64_t{1} << bit) - 1));
        return static_cast<std::int64_t>(base_[slot] + prefix_[wi] + static_cast<std::uint64_t>(std::popcount(below)));
    }

    /// Calls f(ivec3) for every member in increasing grid index (x fastest). Time O(members +
    /// grid voxels / 8).
    template <class F>
    void for_each(F&& f) const {
        const ivec3 d = geom_.dims;
        for (int z = 0; z < d.z; ++z)
            for (int y = 0; y < d.y; ++y) {
                const std::size_t row = static_cast<std::size_t>(blocks_.x) *
                                        (static_cast<std::size_t>(y >> 3) + static_cast<std::size_t>(blocks_.y) * static_cast<std::size_t>(z >> 3));
                const int shift = 8 * (y & 7);
                for (int bx = 0; bx < blocks_.x; ++bx) {
                    const std::uint32_t slot = directory_[row + static_cast<std::size_t>(bx)];
                    if (slot == npos) continue;
                    unsigned byte = static_cast<unsigned>((words_[8 * static_cast<std::size_t>(slot) + static_cast<std::size_t>(z & 7)] >> shift) & 0xffu);
                    while (byte) {
                        const int lx = std::countr_zero(byte);
                        f(ivec3(8 * bx + lx, y, z));
                        byte &= byte - 1;
                    }
                }
            }
    }

    /// Members in increasing grid index.
    [[nodiscard]] std::vector<ivec3> voxels() const {
        std::vector<ivec3> out;
        out.reserve(static_cast<std::size_t>(size_));
        for_each([&](const ivec3& p) { out.push_back(p); });
        return out;
    }

private:
    static constexpr std::uint32_t npos = std::numeric_limits<std::uint32_t>::max();

    [[nodiscard]] std::size_t block_of(const ivec3& p) const noexcept {
        return static_cast<std::size_t>(p.x >> 3) +
               static_cast<std::size_t>(blocks_.x) *
                   (static_cast<std::size_t>(p.y >> 3) + static_cast<std::size_t>(blocks_.y) * static_cast<std::size_t>(p.z >> 3));
    }
    [[nodiscard]] static std::size_t word_of(std::uint32_t slot, const ivec3& p) noexcept {
        return 8 * static_cast<std::size_t>(slot) + static_cast<std::size_t>(p.z & 7);
    }
    [[nodiscard]] static int bit_of(const ivec3& p) noexcept { return (p.x & 7) + 8 * (p.y & 7); }

    grid_geometry geom_;
    ivec3 blocks_{0};
    std::vector<std::uint32_t> directory_;  // block -> slot, npos = no block
    std::vector<std::uint64_t> words_;      // 8 per slot
    std::vector<std::uint64_t> base_;       // rank of the first member of each slot
    std::vector<std::uint16_t> prefix_;     // members of the slot below each word
    std::uint64_t size_ = 0;
    bool ranks_valid_ = true;
};

}  // namespace fabsynth
