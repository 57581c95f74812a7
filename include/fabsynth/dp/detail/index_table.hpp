// SPDX-License-Identifier: MIT
#pragma once
/// @file index_table.hpp  Internal: open-addressing hash set of entry indices (one per DP layer).
///
/// Stores 32-bit entry indices with a 32-bit hash fragment each; the caller compares keys through
/// a callback, so the table itself never copies states. Linear probing, load factor <= 1/2.
#include <cstdint>
#include <utility>
#include <vector>

namespace fabsynth::dp::detail {

class index_table {
public:
    static constexpr std::uint32_t none = 0xffffffffu;

    /// Index stored under a key equal to the probe (eq(index) == true), or `none`.
    template <class Eq>
    [[nodiscard]] std::uint32_t find(std::uint32_t hash, Eq&& eq) const {
        if (slots_.empty()) return none;
        const std::size_t mask = slots_.size() - 1;
        for (std::size_t s = hash & mask;; s = (s + 1) & mask) {
            const slot& sl = slots_[s];
            if (sl.index == none) return none;
            if (sl.hash == hash && eq(sl.index)) return sl.index;
        }
    }
    /// Adds an index whose key is known to be absent.
    void insert(std::uint32_t hash, std::uint32_t index) {
        if (2 * (size_ + 1) > slots_.size()) grow();
        place(hash, index);
        order_.push_back(index);
        ++size_;
    }
    [[nodiscard]] std::size_t size() const noexcept { return size_; }
    void swap(index_table& o) noexcept {
        slots_.swap(o.slots_);
        order_.swap(o.order_);
        std::swap(size_, o.size_);
    }
    [[nodiscard]] std::size_t memory_bytes() const noexcept {
        return slots_.capacity() * sizeof(slot) + order_.capacity() * sizeof(std::uint32_t);
    }
    /// All stored indices in insertion order (ascending when indices are handed out in increasing order).
    [[nodiscard]] const std::vector<std::uint32_t>& indices() const noexcept { return order_; }

private:
    struct slot {
        std::uint32_t hash = 0;
        std::uint32_t index = none;
    };
    void place(std::uint32_t hash, std::uint32_t index) {
        const std::size_t mask = slots_.size() - 1;
        std::size_t s = hash & mask;
        while (slots_[s].index != none) s = (s + 1) & mask;
        slots_[s] = slot{hash, index};
    }
    void grow() {
        std::vector<slot> old;
        old.swap(slots_);
        slots_.assign(old.empty() ? 16 : old.size() * 2, slot{});
        for (const slot& sl : old)
            if (sl.index != none) place(sl.hash, sl.index);
    }

    std::vector<slot> slots_;
    std::vector<std::uint32_t> order_;
    std::size_t size_ = 0;
};

}  // namespace fabsynth::dp::detail
