// SPDX-License-Identifier: MIT
#pragma once
/// @file union_find.hpp  Disjoint sets (union-find), plain and with integer potentials.
///
/// Usage:
///   fabsynth::union_find uf(n);                    // n singletons 0..n-1
///   if (uf.unite(a, b)) ...;                       // true iff two sets merged
///   uf.find(a) == uf.find(b);  uf.sets();          // same set? number of sets
///
///   fabsynth::potential_union_find loops(n);       // loop winding (topology/descriptor.hpp)
///   loops.link(x, y, +1);                          // records pos(y) = pos(x) + 1
///   loops.winds(x);                                // a cycle with non-zero total shift?
///
/// Determinism: the smaller root id always becomes the root of a merged set, so find() results
/// depend only on which sets were merged, never on the order of the unite() calls or their
/// arguments. Path compression is iterative (no recursion on long chains); with union by index
/// and path compression the amortised cost is O(log n) per call, O(alpha(n)) in practice.
///
/// Potentials: each element x carries an integer pos(x) relative to its root. link(x, y, s) records
/// pos(y) = pos(x) + s. Linking two elements already in one set closes a cycle; the cycle winds
/// (non-zero total shift) iff pos(y) != pos(x) + s, and the set is then flagged as winding. With
/// s = 0 everywhere it is a plain union-find.
///
/// One class template, two instantiations: the plain one compiles the potentials out (4 bytes per
/// element instead of 13) while both share one find() and one merge rule.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "fabsynth/core/error.hpp"

namespace fabsynth {

/// Union-find over elements 0..n-1 (n < 2^32). WithPotentials adds link/potential/winds.
template <bool WithPotentials>
class basic_union_find {
public:
    using id = std::uint32_t;

    /// n singletons. Throws invalid_input if n >= 2^32.
    explicit basic_union_find(std::size_t n = 0) {
        if (n >= std::numeric_limits<id>::max())
            throw invalid_input("union_find: " + std::to_string(n) + " elements exceed the limit of 2^32 - 1");
        parent_.resize(n);
        for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<id>(i);
        if constexpr (WithPotentials) pot_.assign(n, 0), winds_.assign(n, 0);
        sets_ = n;
    }

    /// Number of elements.
    [[nodiscard]] std::size_t size() const noexcept { return parent_.size(); }
    /// Number of disjoint sets.
    [[nodiscard]] std::size_t sets() const noexcept { return sets_; }

    /// Root of x (the smallest id of its set); compresses the path. x < size().
    id find(id x) {
        FABSYNTH_ASSERT(x < parent_.size());
        id r = x;
        if constexpr (WithPotentials) {
            std::int64_t sum = 0;
            while (parent_[r] != r) sum += pot_[r], r = parent_[r];
            // Second pass: point every node on the path at r with its full potential.
            while (parent_[x] != r && parent_[x] != x) {
                const id next = parent_[x];
                const std::int64_t p = pot_[x];
                parent_[x] = r;
                pot_[x] = sum;
                sum -= p;
                x = next;
            }
        } else {
            while (parent_[r] != r) r = parent_[r];
            while (parent_[x] != r && parent_[x] != x) {
                const id next = parent_[x];
                parent_[x] = r;
                x = next;
            }
        }
        return r;
    }
    /// True iff a and b are in one set.
    bool same(id a, id b) { return find(a) == find(b); }

    /// Merges the sets of a and b (potentials: pos(b) = pos(a)). Returns true iff they were
    /// different sets (something merged).
    bool unite(id a, id b) {
        if constexpr (WithPotentials) {
            return !link(a, b, 0);
        } else {
            const id ra = find(a), rb = find(b);
            if (ra == rb) return false;
            parent_[std::max(ra, rb)] = std::min(ra, rb);
            --sets_;
            return true;
        }
    }

    /// Potential pos(x) relative to its root (0 for a root).
    std::int64_t potential(id x)
        requires WithPotentials
    {
        find(x);
        return parent_[x] == x ? 0 : pot_[x];
    }
    /// Records pos(y) = pos(x) + shift. Returns true iff x and y were already in one set (the link
    /// closes a cycle; the set winds from now on if the cycle's total shift is non-zero).
    bool link(id x, id y, std::int64_t shift = 0)
        requires WithPotentials
    {
        const id rx = find(x), ry = find(y);
        const std::int64_t px = potential(x), py = potential(y);
        if (rx == ry) {
            if (py != px + shift) winds_[rx] = 1;
            return true;
        }
        if (rx < ry) {
            parent_[ry] = rx;
            pot_[ry] = px + shift - py;
            winds_[rx] |= winds_[ry];
        } else {
            parent_[rx] = ry;
            pot_[rx] = py - shift - px;
            winds_[ry] |= winds_[rx];
        }
        --sets_;
        return false;
    }
    /// True iff the set of x contains a cycle with non-zero total shift.
    bool winds(id x)
        requires WithPotentials
    {
        return winds_[find(x)] != 0;
    }

private:
    struct none {};
    std::vector<id> parent_;
    [[no_unique_address]] std::conditional_t<WithPotentials, std::vector<std::int64_t>, none> pot_;
    [[no_unique_address]] std::conditional_t<WithPotentials, std::vector<std::uint8_t>, none> winds_;
    std::size_t sets_ = 0;
};

/// Plain union-find: find, unite, same, sets.
using union_find = basic_union_find<false>;
/// Union-find with integer potentials and winding flags (adds link, potential, winds).
using potential_union_find = basic_union_find<true>;

}  // namespace fabsynth
