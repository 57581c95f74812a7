// SPDX-License-Identifier: MIT
#pragma once
/// @file descriptor.hpp  Topology descriptors of sliced patterns (Zhou et al. 2014, §3.4).
///
/// A pattern (one piece, or a run of pieces joined left to right) is cut by its left and right
/// sides into *portals*: segments where the pattern interior meets the side. Its descriptor stores
///   - for each side, one component id per portal (top to bottom): equal ids = the two portals are
///     connected through the pattern;
///   - `enclosed`: the number of connected components with no portal left (finished components);
///   - `holes`: the number of holes (bounded complement regions) already closed inside.
///
/// Ids are canonical: renumbered 0, 1, 2... in order of first appearance, left side top to bottom
/// and then right side top to bottom, so equal topologies compare and hash equal.
///
/// merge(a, b) is the descriptor of b glued to the right of a: portal k of a's right side is glued
/// to portal k of b's left side. Counting uses the Euler characteristic (chi = components - holes;
/// gluing two regions along a segment lowers chi by one): a glue that joins two different
/// components merges them, a glue that joins a component to itself closes one hole. This is the
/// paper's rule ("two left portals with the same id merged with two right portals with the same id
/// add a hole") made exact for any chain of glues. merge is associative: (a+b)+c == a+(b+c).
///
/// close_loop(d) glues d's right side back onto its own left side, as when a pattern runs along a
/// closed curve (§3.6.3, Fig. 6). It tells apart a component that winds around the loop (the
/// pattern is *closed*, a ring) from one that is merely connected end to end.
///
/// descriptor_policy and constraints plug descriptors into dp::solve_sequence (dp/sequence_solver.hpp).
///
/// Usage:
///   using fabsynth::topology::descriptor;
///   descriptor a({0, 1}, {0, 2, 2, 3});      // left ids, right ids (any labels)
///   descriptor b({0, 1, 1, 1}, {0});
///   descriptor ab = merge(a, b);              // ab.enclosed() == 1, ab.holes() == 1
#include <algorithm>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/union_find.hpp"

namespace fabsynth::topology {

/// Canonical component id of a portal.
using portal_id = std::uint16_t;

/// Topology of a pattern between its two sides (see the file comment). Always canonical.
class descriptor {
public:
    /// Most portals one side may hold.
    static constexpr std::size_t max_portals = 32767;

    /// The empty pattern: no portal, nothing enclosed.
    descriptor() = default;

    /// From arbitrary component labels (equal labels = connected), top to bottom per side.
    /// Throws invalid_input if a side holds more than max_portals portals.
    descriptor(std::span<const std::uint32_t> left, std::span<const std::uint32_t> right,
               std::uint32_t enclosed = 0, std::uint32_t holes = 0)
        : enclosed_(enclosed), holes_(holes) {
        if (left.size() > max_portals || right.size() > max_portals)
            throw invalid_input("topology descriptor: a side has " + std::to_string(std::max(left.size(), right.size())) +
                                " portals, more than the limit " + std::to_string(max_portals));
        std::vector<std::uint32_t> labels(left.begin(), left.end());
        labels.insert(labels.end(), right.begin(), right.end());
        canonicalise(labels, left.size());
    }
    descriptor(std::initializer_list<std::uint32_t> left, std::initializer_list<std::uint32_t> right,
               std::uint32_t enclosed = 0, std::uint32_t holes = 0)
        : descriptor(std::span<const std::uint32_t>(left.begin(), left.size()),
                     std::span<const std::uint32_t>(right.begin(), right.size()), enclosed, holes) {}

    /// Component id of each left / right portal, top to bottom.
    [[nodiscard]] std::span<const portal_id> left() const noexcept { return {ids_.data(), num_left_}; }
    [[nodiscard]] std::span<const portal_id> right() const noexcept {
        return {ids_.data() + num_left_, ids_.size() - num_left_};
    }
    /// Components with no portal left (they can no longer change).
    [[nodiscard]] std::uint32_t enclosed() const noexcept { return enclosed_; }
    /// Holes closed so far.
    [[nodiscard]] std::uint32_t holes() const noexcept { return holes_; }
    /// Components that still touch a portal.
    [[nodiscard]] std::size_t open_components() const noexcept { return num_ids_; }
    /// Number of portals on both sides.
    [[nodiscard]] std::size_t open_portals() const noexcept { return ids_.size(); }
    /// True iff no portal remains: the counters are the final topology.
    [[nodiscard]] bool finished() const noexcept { return ids_.empty(); }
    /// The same portal structure with both counters zero.
    [[nodiscard]] descriptor shape() const {
        descriptor d = *this;
        d.enclosed_ = d.holes_ = 0;
        return d;
    }

    friend bool operator==(const descriptor& a, const descriptor& b) noexcept {
        return a.num_left_ == b.num_left_ && a.enclosed_ == b.enclosed_ && a.holes_ == b.holes_ && a.ids_ == b.ids_;
    }

    /// 64-bit hash (equal descriptors hash equal).
    [[nodiscard]] std::uint64_t hash() const noexcept {
        std::uint64_t h = hash64(0x70706f6c, num_left_, ids_.size(), enclosed_, holes_);
        for (portal_id id : ids_) h = mix64(h ^ (id + golden_gamma));
        return h;
    }

private:
    friend descriptor merge(const descriptor&, const descriptor&);

    // Renumbers labels (left side first) in first-appearance order; labels.size() <= 2 * max_portals.
    void canonicalise(std::span<const std::uint32_t> labels, std::size_t num_left) {
        num_left_ = num_left;
        ids_.resize(labels.size());
        std::vector<std::pair<std::uint32_t, portal_id>> seen;  // label -> id, tiny: linear scan
        std::unordered_map<std::uint32_t, portal_id> big;       // used only for many portals
        const bool use_map = labels.size() > 32;
        for (std::size_t k = 0; k < labels.size(); ++k) {
            const std::uint32_t l = labels[k];
            portal_id id = 0;
            if (use_map) {
                auto [it, inserted] = big.try_emplace(l, static_cast<portal_id>(big.size()));
                id = it->second;
            } else {
                auto it = std::find_if(seen.begin(), seen.end(), [l](const auto& p) { return p.first == l; });
                if (it == seen.end()) {
                    id = static_cast<portal_id>(seen.size());
                    seen.emplace_back(l, id);
                } else {
                    id = it->second;
                }
            }
            ids_[k] = id;
        }
        num_ids_ = use_map ? big.size() : seen.size();
    }

    std::vector<portal_id> ids_;  // left ids then right ids
    std::size_t num_left_ = 0;
    std::size_t num_ids_ = 0;     // distinct ids = open components
    std::uint32_t enclosed_ = 0;
    std::uint32_t holes_ = 0;
};

/// Descriptor of b glued to the right of a (portal k of a.right() onto portal k of b.left()).
/// Throws invalid_input if the portal counts differ. O(n alpha(n)) for n portals.
[[nodiscard]] inline descriptor merge(const descriptor& a, const descriptor& b) {
    const auto ar = a.right(), bl = b.left();
    if (ar.size() != bl.size())
        throw invalid_input("topology merge: left pattern has " + std::to_string(ar.size()) +
                            " portals on its right side but the right pattern has " + std::to_string(bl.size()) +
                            " on its left side");
    const std::size_t na = a.open_components(), nb = b.open_components();
    potential_union_find uf(na + nb);
    std::uint64_t holes = std::uint64_t{a.holes()} + b.holes();
    for (std::size_t k = 0; k < ar.size(); ++k)
        if (uf.link(ar[k], static_cast<std::uint32_t>(na + bl[k]))) ++holes;  // same component: a hole closes

    const auto al = a.left(), br = b.right();
    std::vector<std::uint32_t> labels;
    labels.reserve(al.size() + br.size());
    std::vector<std::uint8_t> still_open(na + nb, 0);
    for (portal_id id : al) labels.push_back(uf.find(id)), still_open[labels.back()] = 1;
    for (portal_id id : br) labels.push_back(uf.find(static_cast<std::uint32_t>(na + id))), still_open[labels.back()] = 1;
    // Every id of a and b touches some portal; a root that touches none of the remaining ones is finished.
    std::uint64_t enclosed = std::uint64_t{a.enclosed()} + b.enclosed();
    for (std::uint32_t x = 0; x < na + nb; ++x)
        if (uf.find(x) == x && !still_open[x]) ++enclosed;
    if (enclosed > std::numeric_limits<std::uint32_t>::max() || holes > std::numeric_limits<std::uint32_t>::max())
        throw invalid_input("topology merge: component or hole counter overflows 32 bits");

    descriptor r;
    r.enclosed_ = static_cast<std::uint32_t>(enclosed);
    r.holes_ = static_cast<std::uint32_t>(holes);
    r.canonicalise(labels, al.size());
    return r;
}

/// Topology of a pattern whose right side is glued back onto its left side (a closed curve).
struct loop_closure {
    std::uint32_t components = 0;  ///< connected components of the whole loop
    std::uint32_t holes = 0;       ///< holes inside the band (not counting the openings a ring surrounds)
    std::uint32_t rings = 0;       ///< components that wind once around the loop
    /// True iff some component winds all the way around the loop (Fig. 6, top): what the
    /// vector-pattern API calls `closed_loop` (a closed *curve* is just `closed`).
    [[nodiscard]] bool winds() const noexcept { return rings > 0; }
    friend bool operator==(const loop_closure&, const loop_closure&) = default;
};

/// Self-merge that closes a loop (Fig. 6): right portal k is glued onto left portal k.
/// Throws invalid_input if the two sides hold different numbers of portals.
///
/// Counting, with the band mapped onto an annulus: every glue joining a component to itself lowers
/// the Euler characteristic, adding one bounded complement region. A component winds around the
/// loop iff it contains a cycle crossing the seam a non-zero net number of times (tracked with
/// potentials in the union-find). Each winding component surrounds one region that is not a hole of
/// the band (the loop's inside, or the ring-shaped gap between two nested rings), so those regions
/// are subtracted: holes = d.holes() + self-glues - rings. The paper only says the descriptor is
/// "merged with itself"; this is the exact version of that rule.
[[nodiscard]] inline loop_closure close_loop(const descriptor& d) {
    const auto l = d.left(), r = d.right();
    if (l.size() != r.size())
        throw invalid_input("topology loop closing: the pattern has " + std::to_string(l.size()) +
                            " portals on its left side but " + std::to_string(r.size()) + " on its right side");
    const std::size_t n = d.open_components();
    potential_union_find uf(n);
    std::uint64_t self_glues = 0;
    for (std::size_t k = 0; k < l.size(); ++k)
        if (uf.link(r[k], l[k], 1)) ++self_glues;  // crossing the seam moves one turn around the loop
    std::uint64_t roots = 0, rings = 0;
    for (std::uint32_t x = 0; x < n; ++x)
        if (uf.find(x) == x) ++roots, rings += uf.winds(x) ? 1 : 0;
    loop_closure c;
    const std::uint64_t comps = d.enclosed() + roots, holes = d.holes() + self_glues - rings;
    if (comps > std::numeric_limits<std::uint32_t>::max() || holes > std::numeric_limits<std::uint32_t>::max())
        throw invalid_input("topology loop closing: component or hole counter overflows 32 bits");
    c.components = static_cast<std::uint32_t>(comps);
    c.holes = static_cast<std::uint32_t>(holes);
    c.rings = static_cast<std::uint32_t>(rings);
    return c;
}

/// Hash functor for unordered containers.
struct descriptor_hash {
    std::size_t operator()(const descriptor& d) const noexcept { return static_cast<std::size_t>(d.hash()); }
};

// ---------------------------------------------------------------------------------------------
// Plugging descriptors into the DP sequence solver (dp::sequence_state_policy).

struct constraints;

/// Which counters descriptor_policy states carry.
struct descriptor_counting {
    bool components = true;  ///< enclosed components
    bool holes = true;       ///< holes
};

/// State policy for dp::solve_sequence: the state of a run of pieces is its descriptor, stored as
/// an interned portal structure ("shape") plus the two counters. Merges are memoised per
/// (shape, piece), so after warm-up a transition costs one array lookup; the number of distinct
/// shapes is small in practice (§3.6.2: "only a small number of topology descriptors may be reached").
/// Memory: O(shapes * pieces) memo entries of 12 bytes.
///
/// Counters that no constraint reads only multiply the DP states (runs differing only in their
/// hole count would be kept apart), so they can be switched off: an uncounted counter stays 0 in
/// every state. for_constraints() counts exactly what the constraints need.
class descriptor_policy {
public:
    using counting = descriptor_counting;

    struct state {
        std::uint32_t shape = 0;       ///< interned portal structure (see shape_of)
        std::uint32_t enclosed = 0;    ///< finished components
        std::uint32_t holes = 0;       ///< closed holes
        friend bool operator==(const state&, const state&) = default;
    };
    using cycle_summary = loop_closure;

    /// pieces[i] = descriptor of piece i (its own enclosed components and holes included).
    explicit descriptor_policy(std::vector<descriptor> pieces, counting count = {})
        : pieces_(std::move(pieces)), count_(count) {
        piece_shape_.reserve(pieces_.size());
        for (const descriptor& p : pieces_) piece_shape_.push_back(intern(p.shape()));
    }
    /// A policy counting only the counters `want` constrains.
    static descriptor_policy for_constraints(std::vector<descriptor> pieces, const constraints& want);

    /// Counters carried by the states.
    [[nodiscard]] counting counts() const noexcept { return count_; }

    [[nodiscard]] std::size_t num_pieces() const noexcept { return pieces_.size(); }
    [[nodiscard]] const descriptor& piece(std::size_t i) const { return pieces_.at(i); }

    /// State of the one-piece run.
    [[nodiscard]] std::optional<state> start(std::size_t piece) const {
        check_piece(piece);
        return state{piece_shape_[piece], count_.components ? pieces_[piece].enclosed() : 0u,
                     count_.holes ? pieces_[piece].holes() : 0u};
    }
    /// State after appending `piece`; nullopt if the portal counts do not match.
    [[nodiscard]] std::optional<state> extend(const state& s, std::size_t piece) {
        check_piece(piece);
        const std::size_t slot = static_cast<std::size_t>(s.shape) * pieces_.size() + piece;
        FABSYNTH_ASSERT(slot < memo_.size());  // s must come from this policy
        if (memo_[slot].shape == unknown) {
            // The memo may grow while we intern a new shape, so compute first and store after.
            memo_entry e{incompatible, 0, 0};
            const descriptor& a = shapes_[s.shape];
            if (a.right().size() == pieces_[piece].left().size()) {
                const descriptor m = merge(a, pieces_[piece]);
                e = memo_entry{intern(m.shape()), count_.components ? m.enclosed() : 0u, count_.holes ? m.holes() : 0u};
            }
            memo_[slot] = e;
        }
        const memo_entry e = memo_[slot];
        if (e.shape == incompatible) return std::nullopt;
        return state{e.shape, s.enclosed + e.enclosed, s.holes + e.holes};
    }
    /// Topology once the run's right side is glued back onto its left side; nullopt if the counts
    /// differ. (With a counter switched off, the matching field only counts what the loop closing adds.)
    [[nodiscard]] std::optional<loop_closure> close(const state& s) {
        const descriptor& d = shapes_.at(s.shape);
        if (d.left().size() != d.right().size()) return std::nullopt;
        loop_closure c = close_loop(d);
        c.components += s.enclosed;
        c.holes += s.holes;
        return c;
    }
    [[nodiscard]] std::uint64_t hash(const state& s) const noexcept { return hash64(0x746f706f, s.shape, s.enclosed, s.holes); }

    /// Full descriptor of a state.
    [[nodiscard]] descriptor to_descriptor(const state& s) const {
        const descriptor& d = shapes_.at(s.shape);
        const std::vector<std::uint32_t> l(d.left().begin(), d.left().end()), r(d.right().begin(), d.right().end());
        return descriptor(l, r, s.enclosed, s.holes);
    }
    /// Interned portal structure of a state (counters zero).
    [[nodiscard]] const descriptor& shape_of(const state& s) const { return shapes_.at(s.shape); }
    [[nodiscard]] std::size_t open_components(const state& s) const { return shapes_.at(s.shape).open_components(); }
    [[nodiscard]] std::size_t open_portals(const state& s) const { return shapes_.at(s.shape).open_portals(); }
    /// Distinct portal structures met so far.
    [[nodiscard]] std::size_t num_shapes() const noexcept { return shapes_.size(); }
    /// Approximate heap bytes held (shapes and memo).
    [[nodiscard]] std::size_t memory_bytes() const noexcept {
        std::size_t b = memo_.capacity() * sizeof(memo_entry) + shapes_.capacity() * sizeof(descriptor);
        for (const descriptor& d : shapes_) b += d.open_portals() * sizeof(portal_id);
        return b + index_.size() * (sizeof(descriptor) + 32);
    }

private:
    static constexpr std::uint32_t unknown = std::numeric_limits<std::uint32_t>::max();
    static constexpr std::uint32_t incompatible = unknown - 1;
    struct memo_entry {
        std::uint32_t shape = unknown;
        std::uint32_t enclosed = 0;
        std::uint32_t holes = 0;
    };

    void check_piece(std::size_t piece) const {
        if (piece >= pieces_.size())
            throw invalid_input("topology descriptor policy: piece " + std::to_string(piece) + " out of range (" +
                                std::to_string(pieces_.size()) + " pieces)");
    }
    std::uint32_t intern(const descriptor& shape) {
        auto it = index_.find(shape);
        if (it != index_.end()) return it->second;
        if (shapes_.size() >= incompatible - 1) throw invalid_input("topology descriptor policy: too many shapes");
        const auto id = static_cast<std::uint32_t>(shapes_.size());
        shapes_.push_back(shape);
        index_.emplace(shape, id);
        memo_.resize(shapes_.size() * pieces_.size());
        return id;
    }

    std::vector<descriptor> pieces_;
    counting count_;
    std::vector<std::uint32_t> piece_shape_;
    std::vector<descriptor> shapes_;
    std::unordered_map<descriptor, std::uint32_t, descriptor_hash> index_;
    std::vector<memo_entry> memo_;
};

/// Constraint policy for dp::solve_sequence over descriptor_policy: exact numbers of components
/// and holes (each optional), and for closed curves optionally a closed (ring) pattern.
/// An open run is accepted only when no portal is left open (§3.5, constraint 1).
struct constraints {
    std::optional<std::uint32_t> components{};  ///< exact number of connected components (>= 1)
    std::optional<std::uint32_t> holes{};       ///< exact number of holes
    bool closed_loop = false;                 ///< closed curves: some component must wind around the loop

    /// Throws invalid_input for a target no pattern can meet (0 components), or when the policy
    /// does not count what is constrained. (dp::solve_sequence calls it before solving.)
    void validate(const descriptor_policy& p) const {
        if (components && *components == 0)
            throw invalid_input("topology constraints: components = 0 asks for an empty pattern; use >= 1");
        if ((components && !p.counts().components) || (holes && !p.counts().holes))
            throw invalid_input("topology constraints: the descriptor policy does not count the constrained "
                                "components/holes (see descriptor_policy::counting)");
    }
    /// False once the run can no longer meet the targets: counters only grow, and open components
    /// will add at least one more component when they finish.
    [[nodiscard]] bool viable(const descriptor_policy& p, const descriptor_policy::state& s) const {
        if (holes && s.holes > *holes) return false;
        if (components && s.enclosed + (p.open_portals(s) > 0 ? 1u : 0u) > *components) return false;
        return true;
    }
    [[nodiscard]] bool accept_open(const descriptor_policy& p, const descriptor_policy::state& s) const {
        if (p.open_portals(s) != 0) return false;
        return (!components || s.enclosed == *components) && (!holes || s.holes == *holes);
    }
    [[nodiscard]] bool accept_cycle(const descriptor_policy&, const loop_closure& c) const {
        return (!components || c.components == *components) && (!holes || c.holes == *holes) &&
               (!closed_loop || c.winds());
    }
};

inline descriptor_policy descriptor_policy::for_constraints(std::vector<descriptor> pieces, const constraints& want) {
    return descriptor_policy(std::move(pieces), counting{.components = want.components.has_value(),
                                                         .holes = want.holes.has_value()});
}

}  // namespace fabsynth::topology
