#pragma once
/// @file union_find.hpp  Internal: union-find with integer potentials (for loop winding).
///
/// Each element x stores its potential relative to its parent; pos(x) = sum of potentials on the
/// path to the root. link(x, y, s) records "pos(y) = pos(x) + s". Linking two elements already in
/// one set closes a cycle; the cycle winds (non-zero total shift) iff pos(y) != pos(x) + s, and the
/// set is then flagged as winding. With s = 0 everywhere this is a plain union-find.
#include <cstdint>
#include <vector>

namespace fabsynth::topology::detail {

class potential_union_find {
public:
    explicit potential_union_find(std::size_t n) : parent_(n), pot_(n, 0), winds_(n, 0) {
        for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<std::uint32_t>(i);
    }

    /// Root of x; compresses the path (iteratively: no recursion depth issue on long chains).
    std::uint32_t find(std::uint32_t x) {
        std::uint32_t r = x;
        std::int64_t sum = 0;
        while (parent_[r] != r) sum += pot_[r], r = parent_[r];
        // Second pass: point every node on the path at r with its full potential.
        while (parent_[x] != r && parent_[x] != x) {
            const std::uint32_t next = parent_[x];
            const std::int64_t p = pot_[x];
            parent_[x] = r;
            pot_[x] = sum;
            sum -= p;
            x = next;
        }
        return r;
    }
    /// Potential of x relative to its root.
    std::int64_t potential(std::uint32_t x) {
        find(x);
        return parent_[x] == x ? 0 : pot_[x];
    }

    /// Records pos(y) = pos(x) + shift. Returns true iff x and y were already in one set
    /// (the link closes a cycle).
    bool link(std::uint32_t x, std::uint32_t y, std::int64_t shift = 0) {
        const std::uint32_t rx = find(x), ry = find(y);
        const std::int64_t px = potential(x), py = potential(y);
        if (rx == ry) {
            if (py != px + shift) winds_[rx] = 1;
            return true;
        }
        // Smaller root index becomes the root: deterministic and independent of call history.
        if (rx < ry) {
            parent_[ry] = rx;
            pot_[ry] = px + shift - py;
            winds_[rx] |= winds_[ry];
        } else {
            parent_[rx] = ry;
            pot_[rx] = py - shift - px;
            winds_[ry] |= winds_[rx];
        }
        return false;
    }
    /// True iff the set of x contains a cycle with non-zero total shift.
    bool winds(std::uint32_t x) { return winds_[find(x)] != 0; }

private:
    std::vector<std::uint32_t> parent_;
    std::vector<std::int64_t> pot_;
    std::vector<std::uint8_t> winds_;
};

}  // namespace fabsynth::topology::detail
