// SPDX-License-Identifier: MIT
#pragma once
/// @file near_seeds.hpp  (internal, behind evaluator.hpp) What makes a cold point query cheap: the
/// seeds near q, from a per-thread cache of binned coarse-cell seeds, and a certified test that
/// decides most points from those few seeds without building any Voronoi cell.
///
/// Notation (paper §3.1: F(q) = 1 iff q is within tau of an edge of the Voronoi diagram of the
/// seeds, Algorithm 1's bisector lines): d_j = |q - s_j|, s_1 a seed nearest to q (d_1 <= d_j for
/// all j), and for every other seed j
///     delta_j = (d_j^2 - d_1^2) / (2 |s_j - s_1|) = (s_j - s_1) . ((s_j + s_1) / 2 - q) / |s_j - s_1| >= 0,
/// the distance from q to the bisector plane of s_1 and s_j, H_j = {p : |p - s_j| <= |p - s_1|}
/// being the closed half-space beyond it (q is not in its interior).
///
/// Lemma 1 (edge bound). Let delta_(2) be the second smallest delta_j over all seeds j != s_1.
///   Then dist(q, every Voronoi edge) >= delta_(2).
///   Proof: an edge point e has >= 3 nearest seeds (all at distance r(e)), so >= 2 of them, a != b,
///   differ from s_1. |e - a| = r(e) <= |e - s_1| puts e in H_a, likewise in H_b, so
///   |q - e| >= max(dist(q, H_a), dist(q, H_b)) = max(delta_a, delta_b) >= delta_(2).
///   (Paper Fig. 3: a point near one bisector is not near an edge; this counts two of them.)
/// Lemma 2 (far seeds). A seed with d_j >= D has delta_j >= (D - d_1) / 2.
///   Proof: |s_j - s_1| <= d_j + d_1, so delta_j >= (d_j - d_1)(d_j + d_1) / (2 (d_j + d_1)).
///   Hence with S = every seed within rho = d_1 + 2 tau + 2 m of q (m a rounding margin), every
///   seed outside S has delta_j > tau + m: the seeds of S with delta_j <= tau + m (the candidates
///   C) are the only seeds other than s_1 that an edge point within tau + m of q can have as
///   nearest seeds (Lemma 1's argument, one seed at a time). So:
///   - |C| <= 1: delta_(2) > tau + m, q is empty, certified (no Voronoi cell is built);
/// Lemma 3 (local edges). Every edge point e within tau + m of q has r(e) <= d_1 + tau + m, and
///   every seed at distance r(e) from e lies within d_1 + 2 tau + 2 m of q, i.e. in S. So the
///   edges within tau + m of q are exactly the lines equidistant from triples of C + {s_1}, each
///   clipped to where its three seeds are nearest among S: the distance from q to the edges, when
///   it is <= tau + m, is the minimum over those clipped lines (the construction of
///   tests/foam/reference_voronoi.hpp, restricted to a handful of seeds).
///   - that minimum <= tau - m: solid; > tau + m (or no candidate line): empty;
///   - within m of tau, or a line nearly parallel to a clipping plane: undecided, and the caller
///     answers with the exact query (certificate.hpp + voronoi_edges.hpp).
/// The jittered grid (seeds.hpp: every coarse cell holds >= 1 seed) is used only to bound the
/// search for s_1: the gather below looks at a cube around q until it holds a seed within its
/// half side, so that seed's distance bounds d_1 and the cube holds every seed within it.
///
/// Exactness: a decided answer is the exact one as long as the true distance and the one
/// computed here differ by less than m = 1e-9 (1 + |q|_inf + d_1) mm; both computations are
/// products and sums of a few seed coordinates (relative rounding ~1e-15), and every answer
/// within m of the radius goes to the exact query, whose own rounding (canonical_piece.hpp,
/// ~1e-13 mm) is below m too. So contains() gives the bits of contains_uncached() at every point.
///
/// The seed cache: a thread keeps the seeds of the coarse cells it visited (owner = the foam
/// instance) in two open-addressing tables: raw cells (one coarse cell's seeds, one bin) and
/// extended cells (the seeds within ~1.2 spacings of 2 x 2 x 2 coarse cells, ~2.5 per bin), each
/// cell one allocation (header, bin offsets, seeds), found through slots that hold the key's hash
/// (a probe reads no other cell); past its byte budget a table drops cells in insertion
/// order (a clock hand), remembering the evicted keys (ghosts). When the extended cells thrash
/// (the table full and over a quarter of the recent queries missing on a ghost: a cell the cache
/// held and had to drop), only one miss in 32 builds a cell (a build reads 64 raw cells; one in 8
/// was slower with a working set twice the cache); the others gather from raw cells. Misses on
/// cells never held (a new foam on a cache full of an old one's cells, a new region) always
/// build: counting them too made every cold pass after the first few foams run from raw cells,
/// 0.87 against 1.23 M points/s (benchmarks/README.md).
/// Its contents never change an answer (the seeds of a cell are a function of the foam and the
/// cell, and every path gathers all the seeds Lemma 2 asks for).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/detail/canonical_piece.hpp"
#include "fabsynth/foam/seeds.hpp"

namespace fabsynth::foam::detail {

/// An extended cell covers E^3 coarse cells, E = 2^extended_shift (see make_extended_cell): 2 x 2 x 2
/// (4 x 4 x 4 was slower cold in the benchmark cube: a build reads 216 raw cells).
inline constexpr int extended_shift = 1;
inline constexpr std::int64_t extended_span = std::int64_t(1) << extended_shift;
static_assert(extended_span * extended_span * extended_span <= 64);

/// Seeds of a box, binned (g bins per axis over the box): the seeds of one coarse cell (a "raw"
/// cell), or every seed within a margin of 2 x 2 x 2 of them (an "extended" cell, which answers
/// most queries of those cells alone). One allocation: this header, then the g^3 + 1 bin offsets, then the seeds
/// sorted by bin (a query touches the header, its bins' offsets and their seeds, nothing else).
struct seed_cell {
    std::uint64_t owner = 0;
    i64vec3 key{0};
    int g = 1;
    std::uint32_t n = 0;    // seeds
    double inv_bin = 1.0;   // bins per mm
    vec3 lo{0.0}, hi{0.0};  // the box
    // extended cells: per coarse cell (extended_index), a distance (mm) within which most of its points have a seed
    float guess[extended_span * extended_span * extended_span] = {};
    std::size_t size = 0;   // bytes of the allocation

    [[nodiscard]] std::size_t bytes() const noexcept { return size; }
    [[nodiscard]] const std::uint32_t* start() const noexcept { return reinterpret_cast<const std::uint32_t*>(this + 1); }
    [[nodiscard]] const vec3* seeds() const noexcept {
        return reinterpret_cast<const vec3*>(reinterpret_cast<const std::byte*>(this + 1) + offsets_bytes(g));
    }
    [[nodiscard]] static std::size_t offsets_bytes(int g) noexcept {
        const std::size_t b = (static_cast<std::size_t>(g) * static_cast<std::size_t>(g) * static_cast<std::size_t>(g) + 1) * sizeof(std::uint32_t);
        return (b + 7) & ~std::size_t(7);
    }
    /// The bin index range [b0, b1] per axis of the bins meeting [a, b] (clamped to the grid).
    void bin_range(const vec3& a, const vec3& b, int b0[3], int b1[3]) const noexcept {
        // clamped to [-1, g] first (a query box may reach far beyond the cell, or be not finite),
        // then floored without the library call (std::floor is one on baseline x86-64)
        const double top = static_cast<double>(g);
        const auto bin = [&](double u) {
            u = u >= -1.0 ? (u <= top ? u : top) : -1.0;  // NaN -> -1
            const int i = static_cast<int>(u);
            return std::clamp(i - (u < i), 0, g - 1);
        };
        for (int i = 0; i < 3; ++i) {
            b0[i] = bin((a[i] - lo[i]) * inv_bin);
            b1[i] = bin((b[i] - lo[i]) * inv_bin);
        }
    }
    /// Calls f(seed) for the seeds of the bins [b0, b1].
    template <class F>
    void for_bins(const int b0[3], const int b1[3], F&& f) const {
        const std::uint32_t* st = start();
        const vec3* sd = seeds();
        for (int bz = b0[2]; bz <= b1[2]; ++bz)
            for (int by = b0[1]; by <= b1[1]; ++by) {
                const std::size_t row = static_cast<std::size_t>((bz * g + by) * g);
                const std::uint32_t e = st[row + static_cast<std::size_t>(b1[0]) + 1];
                for (std::uint32_t i = st[row + static_cast<std::size_t>(b0[0])]; i < e; ++i) f(sd[i]);
            }
    }
    /// Calls f(seed) for the seeds of the bins that meet the ball of radius h around q (rows of
    /// bins cut to the ball's chord; q inside the box).
    template <class F>
    void for_ball(const vec3& q, double h, F&& f) const {
        const std::uint32_t* st = start();
        const vec3* sd = seeds();
        const double bin = 1.0 / inv_bin, h2 = h * h, hb = h * inv_bin;
        const vec3 u = (q - lo) * inv_bin;  // in [0, g] (q inside the box)
        // floor of x >= -1 - g (the bins are few); std::floor is a library call on baseline x86-64
        const auto fl = [](double x) { const int i = static_cast<int>(x); return i - (x < i); };
        const int z0 = std::max(0, fl(u.z - hb)), z1 = std::min(g - 1, fl(u.z + hb));
        const int y0 = std::max(0, fl(u.y - hb)), y1 = std::min(g - 1, fl(u.y + hb));
        const int qy = fl(u.y), qz = fl(u.z);
        for (int bz = z0; bz <= z1; ++bz) {
            const double dz = bz < qz ? q.z - (lo.z + (bz + 1) * bin) : bz > qz ? lo.z + bz * bin - q.z : 0.0;
            for (int by = y0; by <= y1; ++by) {
                const double dy = by < qy ? q.y - (lo.y + (by + 1) * bin) : by > qy ? lo.y + by * bin - q.y : 0.0;
                const double r2 = h2 - dy * dy - dz * dz;
                if (r2 < 0) continue;
                const double r = std::sqrt(r2) * (1 + 1e-12) * inv_bin;
                const int x0 = std::max(0, fl(u.x - r)), x1 = std::min(g - 1, fl(u.x + r));
                const std::size_t row = static_cast<std::size_t>((bz * g + by) * g);
                const std::uint32_t e = st[row + static_cast<std::size_t>(x1) + 1];
                for (std::uint32_t i = st[row + static_cast<std::size_t>(x0)]; i < e; ++i) f(sd[i]);
            }
        }
    }
};
static_assert(sizeof(seed_cell) % 8 == 0);

struct seed_cell_free {
    void operator()(seed_cell* c) const noexcept { ::operator delete(static_cast<void*>(c)); }
};
using seed_cell_ptr = std::unique_ptr<seed_cell, seed_cell_free>;

/// A cell of box [lo, hi] holding the n seeds `raw` (all inside the box) in g^3 bins.
[[nodiscard]] inline seed_cell_ptr bin_seeds(const vec3& lo, const vec3& hi, int g, const vec3* raw, std::size_t n) {
    const std::size_t bins = static_cast<std::size_t>(g) * static_cast<std::size_t>(g) * static_cast<std::size_t>(g);
    const std::size_t size = sizeof(seed_cell) + seed_cell::offsets_bytes(g) + n * sizeof(vec3);
    seed_cell_ptr c(new (::operator new(size)) seed_cell{});
    c->g = g, c->n = static_cast<std::uint32_t>(n), c->size = size;
    c->lo = lo, c->hi = hi;
    c->inv_bin = g / (hi.x - lo.x);
    auto* st = const_cast<std::uint32_t*>(c->start());
    if (g == 1) {  // a raw cell: the seeds as given
        st[0] = 0, st[1] = static_cast<std::uint32_t>(n);
        std::uninitialized_copy(raw, raw + n, const_cast<vec3*>(c->seeds()));
        return c;
    }
    thread_local std::vector<std::uint32_t> bin_of;
    bin_of.resize(n);
    std::fill(st, st + bins + 1, 0u);
    for (std::size_t i = 0; i < n; ++i) {
        int b[3];
        for (int a = 0; a < 3; ++a) b[a] = std::clamp(static_cast<int>((raw[i][a] - lo[a]) * c->inv_bin), 0, g - 1);  // >= 0: truncation floors
        bin_of[i] = static_cast<std::uint32_t>((b[2] * g + b[1]) * g + b[0]);
        ++st[bin_of[i] + 1];
    }
    for (std::size_t i = 1; i <= bins; ++i) st[i] += st[i - 1];
    auto* sd = const_cast<vec3*>(c->seeds());
    for (std::size_t i = 0; i < n; ++i) new (sd + st[bin_of[i]]++) vec3(raw[i]);
    for (std::size_t i = bins; i > 0; --i) st[i] = st[i - 1];  // the fill moved each offset one bin on
    st[0] = 0;
    return c;
}

/// A thread's binned seed boxes keyed by (owner, coarse cell) (see the file comment).
class seed_cell_cache {
public:
    /// The hash of a key (the table's probe start, and what a slot compares before it reads a cell).
    [[nodiscard]] static std::uint64_t key_hash(std::uint64_t owner, const i64vec3& k) noexcept { return hash64(owner, k.x, k.y, k.z) | 1; }  // 0: empty slot
    /// The entry (owner, k) if held, else null.
    [[nodiscard]] const seed_cell* find(std::uint64_t owner, const i64vec3& k) noexcept {
        if (last_ && last_->owner == owner && last_->key == k) return last_;
        if (table_.empty()) return nullptr;
        const std::uint64_t h = key_hash(owner, k);
        const std::size_t mask = table_.size() - 1;
        // a slot's hash is compared first: a probe reads no cell but the one it returns (a cell
        // header read on a wrong slot is a cache miss; a full 64-bit match is checked on the cell)
        for (std::size_t i = h & mask;; i = (i + 1) & mask) {
            const slot& sl = table_[i];
            if (!sl.cell) return nullptr;
            if (sl.hash == h && sl.cell->owner == owner && sl.cell->key == k) return last_ = sl.cell;
        }
    }
    /// Whether a new entry of `need` bytes would evict one (budget: bytes to keep).
    [[nodiscard]] bool full(std::size_t need, std::size_t budget) const noexcept { return !cells_.empty() && bytes_ + need > budget; }
    /// The entry (owner, k), made by fill() (returning a seed_cell_ptr) when not held. `budget`:
    /// bytes to keep (the entry returned stays valid until the next call).
    template <class Fill>
    const seed_cell& get(std::uint64_t owner, const i64vec3& k, std::size_t budget, Fill&& fill) {
        if (const seed_cell* c = find(owner, k)) return *c;
        seed_cell_ptr cell = fill();
        cell->owner = owner, cell->key = k;
        const std::size_t need = cell->bytes();
        while (!cells_.empty() && bytes_ + need > budget) evict_one();
        bytes_ += need;
        cells_.push_back(std::move(cell));
        if (2 * cells_.size() > table_.size()) reindex();
        else insert(cells_.back().get());
        return *(last_ = cells_.back().get());
    }
    [[nodiscard]] std::size_t bytes() const noexcept { return bytes_; }
    [[nodiscard]] std::size_t size() const noexcept { return cells_.size(); }
    /// Whether (owner, k) was evicted lately (a "ghost": its key's hash is remembered in a
    /// direct-mapped table of ~8 slots per cell held, so a later eviction may overwrite it).
    /// A miss on a ghost is a re-reference the cache could not keep, the sign of a working set
    /// larger than the budget; a miss on a key never held (a new foam, a new region) is not.
    [[nodiscard]] bool evicted_lately(std::uint64_t owner, const i64vec3& k) const noexcept {
        if (ghosts_.empty()) return false;
        const std::uint64_t h = key_hash(owner, k);
        return ghosts_[h & (ghosts_.size() - 1)] == h;
    }

private:
    struct slot {
        std::uint64_t hash = 0;
        seed_cell* cell = nullptr;  // null: empty
    };
    void insert(seed_cell* c) noexcept {
        const std::uint64_t h = key_hash(c->owner, c->key);
        const std::size_t mask = table_.size() - 1;
        std::size_t i = h & mask;
        while (table_[i].cell) i = (i + 1) & mask;
        table_[i] = {h, c};
    }
    void reindex() {
        std::size_t n = 64;
        while (n < 4 * cells_.size()) n *= 2;
        table_.assign(n, slot{});
        for (const auto& c : cells_) insert(c.get());
        // ~8 slots per cell held: an evicted key survives the next ~8x-cells evictions with
        // probability ~e^-1, so a working set several times the cache is seen (at 2 slots per cell,
        // a working set 4x the cache showed 22% of its misses as ghosts and was not seen)
        ghosts_.resize(2 * n, 0);  // grows with the cells held (old ghosts keep their slots or are lost: a hint only)
    }
    // Removes c (of hash h) from the table (backward-shift deletion keeps every probe chain unbroken).
    void erase(const seed_cell* c, std::uint64_t h) noexcept {
        const std::size_t mask = table_.size() - 1;
        std::size_t i = h & mask;
        while (table_[i].cell != c) i = (i + 1) & mask;
        for (std::size_t j = (i + 1) & mask; table_[j].cell; j = (j + 1) & mask) {
            const std::size_t home = table_[j].hash & mask;
            // table_[j] may move to the hole i unless its home lies cyclically in (i, j]
            if (((j - home) & mask) >= ((j - i) & mask)) {
                table_[i] = table_[j];
                i = j;
            }
        }
        table_[i] = slot{};
    }
    // Drops the cell at the clock hand (a cell of the older insertions), remembering its key as a ghost.
    void evict_one() {
        if (hand_ >= cells_.size()) hand_ = 0;
        const seed_cell* c = cells_[hand_].get();
        if (last_ == c) last_ = nullptr;
        bytes_ -= c->bytes();
        const std::uint64_t h = key_hash(c->owner, c->key);
        ghosts_[h & (ghosts_.size() - 1)] = h;
        erase(c, h);
        std::swap(cells_[hand_], cells_.back());
        cells_.pop_back();
        ++hand_;
    }

    std::vector<seed_cell_ptr> cells_;
    std::vector<slot> table_;  // open addressing, linear probing
    std::vector<std::uint64_t> ghosts_;  // hashes of evicted keys, direct-mapped; 0 = none
    seed_cell* last_ = nullptr;
    std::size_t bytes_ = 0, hand_ = 0;
};

/// A thread's seed caches for the near-seed test, and its scratch space.
struct near_seeds {
    seed_cell_cache raw;  ///< the seeds of single coarse cells
    seed_cell_cache ext;  ///< the seeds of a coarse cell grown by a margin (extended cells)
    std::vector<vec3> S;     // gathered seeds (the first n; the vectors only grow, so a query
    std::vector<double> d2;  // does not zero-fill them) and their squared distances to q
    std::size_t n = 0;
    std::vector<int> cand;   // indices into S: s_1 first, then the candidates C
    std::vector<vec3> tmp;
    // extended-cell misses while that cache thrashes (see extended_cell)
    std::uint64_t full_misses = 0;
    std::uint32_t recent = 0;     // extended-cell misses per query x 2^16, decaying average
    std::size_t typical_ext = 0;  // bytes of the latest extended cell built
};

/// The seeds of coarse cell k (in one bin). Budget: bytes of raw cells to keep.
template <class Seeds>
const seed_cell& raw_cell(const Seeds& gen, std::uint64_t owner, const i64vec3& k, std::size_t budget, near_seeds& ns) {
    return ns.raw.get(owner, k, budget, [&] {
        const double L = gen.options().cell;
        ns.tmp.clear();
        gen.cell_seeds(k, ns.tmp);
        const vec3 lo = vec3(static_cast<double>(k.x), static_cast<double>(k.y), static_cast<double>(k.z)) * L;
        // one bin: a raw cell is read whole (by extended-cell builds, and by gather_near, where
        // a run of ~25 seeds was faster than rows of bins of ~1 seed: 0.84 -> 1.02 M points/s
        // with a working set twice the cache, and ~3% faster cold; benchmarks/README.md)
        return bin_seeds(lo, lo + vec3(L), 1, ns.tmp.data(), ns.tmp.size());
    });
}

/// Seeds per bin of an extended cell: a query reads the bins meeting a cube of about 2 seed
/// spacings; bins of ~2.5 seeds make that 2-3 bins per axis (fewer, longer runs than 1 seed per bin).
inline constexpr double seeds_per_bin = 2.5;

/// The extended cell holding coarse cell k: floor(k / E) per axis.
[[nodiscard]] inline i64vec3 extended_key(const i64vec3& k) noexcept { return {k.x >> extended_shift, k.y >> extended_shift, k.z >> extended_shift}; }  // floors (C++20 >>)
/// Which of its extended cell's E^3 coarse cells k is (the index of seed_cell::guess).
[[nodiscard]] inline int extended_index(const i64vec3& k) noexcept {
    constexpr std::int64_t m = extended_span - 1;
    return static_cast<int>((((k.z & m) << extended_shift) + (k.y & m)) << extended_shift | (k.x & m));
}

/// Every seed within margin M of the E^3 coarse cells of extended key e (M = 1.2 seed spacings of
/// its sparsest cell + 2 R, at most one cell: about the reach of a query of those cells), binned
/// ~2.5 per bin. Eight cells share one margin: the seeds stored per coarse cell (the box's volume
/// over 8 cells') are about 2.5x fewer than with one cell per box, and a build reads 64 raw cells
/// instead of 8 x 27 (a cold build's time went mostly to writing and reading memory not in cache).
/// Budget: bytes of raw cells to keep.
template <class Seeds>
seed_cell_ptr make_extended_cell(const Seeds& gen, std::uint64_t owner, const i64vec3& e, double R, std::size_t raw_budget, near_seeds& ns) {
    const double L = gen.options().cell;
    constexpr std::int64_t E = extended_span;
    const i64vec3 k0{E * e.x, E * e.y, E * e.z};
    thread_local std::vector<vec3> in;
    in.clear();
    // the E^3 core cells first (all their seeds; their counts set the margin), then the ring of
    // 4^3 - E^3 cells around them (the seeds within the margin)
    double spacing[64], widest = 0;
    for (std::int64_t z = k0.z; z < k0.z + E; ++z)
        for (std::int64_t y = k0.y; y < k0.y + E; ++y)
            for (std::int64_t x = k0.x; x < k0.x + E; ++x) {
                const i64vec3 k{x, y, z};
                const seed_cell& c = raw_cell(gen, owner, k, raw_budget, ns);
                in.insert(in.end(), c.seeds(), c.seeds() + c.n);
                double& sp = spacing[extended_index(k)];
                sp = L / std::cbrt(static_cast<double>(std::max<std::uint32_t>(1, c.n)));
                widest = std::max(widest, sp);
            }
    const double M = std::min(L, 1.2 * widest + 2 * R);
    const vec3 clo = vec3(static_cast<double>(k0.x), static_cast<double>(k0.y), static_cast<double>(k0.z)) * L;
    const vec3 lo = clo - vec3(M), hi = clo + vec3(static_cast<double>(E) * L + M);
    for (std::int64_t z = k0.z - 1; z <= k0.z + E; ++z)
        for (std::int64_t y = k0.y - 1; y <= k0.y + E; ++y)
            for (std::int64_t x = k0.x - 1; x <= k0.x + E; ++x) {
                if (x >= k0.x && x < k0.x + E && y >= k0.y && y < k0.y + E && z >= k0.z && z < k0.z + E) continue;
                const seed_cell& c = raw_cell(gen, owner, {x, y, z}, raw_budget, ns);
                const vec3* sd = c.seeds();
                // written always, kept when inside (no branch per seed)
                std::size_t at = in.size();
                in.resize(at + c.n);
                for (std::uint32_t i = 0; i < c.n; ++i) {
                    const vec3& s = sd[i];
                    in[at] = s;
                    at += (s.x >= lo.x) & (s.y >= lo.y) & (s.z >= lo.z) & (s.x <= hi.x) & (s.y <= hi.y) & (s.z <= hi.z);
                }
                in.resize(at);
            }
    const int g = std::clamp(static_cast<int>(std::ceil(std::cbrt(static_cast<double>(in.size()) / seeds_per_bin))), 1, 48);
    seed_cell_ptr c = bin_seeds(lo, hi, g, in.data(), in.size());
    // most points of each coarse cell (~90% of a uniform process of its density) have a seed
    // within this distance: the first search radius of a query in it
    for (int o = 0; o < E * E * E; ++o) c->guess[o] = static_cast<float>(0.82 * spacing[o]);
    return c;
}

/// The extended cell of coarse cell k (extended_key) from the cache, built when not held; null when
/// the cache thrashes (full, and more than a quarter of the recent queries missed a cell it had
/// evicted): then only one
/// miss in 32 builds a cell and the others are answered from raw cells (cheaper than a build that
/// would be evicted before it is used again). Budgets: bytes of extended and raw cells to keep.
template <class Seeds>
const seed_cell* extended_cell(const Seeds& gen, std::uint64_t owner, const i64vec3& k, double R, std::size_t budget, std::size_t raw_budget, near_seeds& ns) {
    ns.recent -= ns.recent >> 6;  // misses on evicted cells per query, x 2^16, averaged over ~64 queries
    const i64vec3 e = extended_key(k);
    if (const seed_cell* c = ns.ext.find(owner, e)) return c;
    if (ns.ext.evicted_lately(owner, e)) ns.recent += 1024;
    if (ns.ext.full(ns.typical_ext, budget) && ns.recent > (1024 << 6) / 4 && ++ns.full_misses % 32 != 0) return nullptr;
    const seed_cell& c = ns.ext.get(owner, e, budget, [&] { return make_extended_cell(gen, owner, e, R, raw_budget, ns); });
    ns.typical_ext = c.bytes();
    return &c;
}

/// Appends to ns.S (and ns.d2) every seed within h of q, from the raw cells meeting the cube
/// q +- h. Returns the least squared distance seen (+infinity if none).
template <class Seeds>
double gather_near(const vec3& q, double h, const Seeds& gen, std::uint64_t owner, std::size_t raw_budget, near_seeds& ns) {
    const double L = gen.options().cell;
    const double h2 = h * h;
    const i64vec3 lo = coarse_cell_of(q - vec3(h), L), hi = coarse_cell_of(q + vec3(h), L);
    double best = std::numeric_limits<double>::infinity();
    int b0[3], b1[3];
    for (std::int64_t z = lo.z; z <= hi.z; ++z)
        for (std::int64_t y = lo.y; y <= hi.y; ++y)
            for (std::int64_t x = lo.x; x <= hi.x; ++x) {
                const seed_cell& c = raw_cell(gen, owner, {x, y, z}, raw_budget, ns);
                c.bin_range(q - vec3(h), q + vec3(h), b0, b1);
                c.for_bins(b0, b1, [&](const vec3& s) {
                    const vec3 d = s - q;
                    const double e2 = glm::dot(d, d);
                    if (e2 <= h2) {
                        ns.S.push_back(s);
                        ns.d2.push_back(e2);
                        best = std::min(best, e2);
                    }
                });
            }
    return best;
}

/// Answer of the near-seed test.
enum class near_answer { empty, solid, undecided };

/// The certified test of the file comment for the point q of radius t (0 < t <= R <= cell, R the
/// foam's maximum radius). Budgets: bytes of extended and raw cells to keep.
/// kq: the coarse cell of q (coarse_cell_of).
template <class Seeds>
near_answer near_seed_test(const vec3& q, const i64vec3& kq, double t, const Seeds& gen, std::uint64_t owner, double R, std::size_t budget, std::size_t raw_budget,
                           near_seeds& ws) {
    const double L = gen.options().cell;
    const double scale = 1 + std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
    const auto margin = [&](double d) { return 1e-9 * (scale + d); };
    ws.n = 0;
    double d1 = 0, m = 0, rho = 0;
    // 1. S: usually from q's extended cell alone: the seeds within h of q, h first the cell's
    //    guess (+ 2 t and margins); when the nearest of them, d_1, leaves rho = d_1 + 2 t + 2 m
    //    within h, they hold all of S (Lemma 2's S); else h grows to rho (or doubles if none).
    //    The ball q +- h must lie inside the cell's box.
    if (const seed_cell* E = extended_cell(gen, owner, kq, R, budget, raw_budget, ws)) {
        const double slack = 1e-9 * scale;
        const double guess = E->guess[extended_index(kq)];
        double h = guess + 2 * t + 2 * margin(guess) + 2 * slack;
        bool done = false;
        for (int pass = 0; pass < 4 && !done; ++pass) {
            if (!(std::isfinite(h) && glm::all(glm::greaterThanEqual(q - vec3(h), E->lo + vec3(slack))) &&
                  glm::all(glm::lessThanEqual(q + vec3(h), E->hi - vec3(slack)))))
                break;
            const double h2 = h * h;
            // every seed of the bins meeting the cube q +- h is written; those within h are kept
            // (no branch per seed: the bins hold a few seeds each, in runs of unpredictable length)
            int b0[3], b1[3];
            E->bin_range(q - vec3(h), q + vec3(h), b0, b1);
            const std::uint32_t* st = E->start();
            const int g = E->g;
            std::size_t most = 0;
            for (int bz = b0[2]; bz <= b1[2]; ++bz)
                for (int by = b0[1]; by <= b1[1]; ++by) {
                    const std::size_t row = static_cast<std::size_t>((bz * g + by) * g);
                    most += st[row + static_cast<std::size_t>(b1[0]) + 1] - st[row + static_cast<std::size_t>(b0[0])];
                }
            if (ws.S.size() < most) ws.S.resize(most), ws.d2.resize(most);
            std::size_t kept = 0;
            double best = std::numeric_limits<double>::infinity();
            E->for_bins(b0, b1, [&](const vec3& s) {
                const vec3 d = s - q;
                const double e2 = glm::dot(d, d);
                ws.S[kept] = s, ws.d2[kept] = e2;
                kept += e2 <= h2;
                best = std::min(best, e2);
            });
            ws.n = kept;
            if (best <= h2) {
                d1 = std::sqrt(best);
                m = margin(d1);
                rho = d1 + 2 * t + 2 * m;
                if (rho * (1 + 1e-12) + slack <= h) done = true;  // every seed within rho is in S
                else h = rho * (1 + 1e-9) + 2 * slack;
            } else if (std::isfinite(best)) {  // a seed beyond h bounds d_1
                const double d_up = std::sqrt(best);
                h = d_up * (1 + 1e-9) + 2 * t + 2 * margin(d_up) + 2 * slack;
            } else {
                h *= 2;
            }
        }
        if (!done) ws.n = 0;
    }
    // 1'. otherwise from the raw cells: a cube q +- h holding a seed within h (so the nearest seed
    //    is inside it); the first h is about the seed spacing, doubled until then (every coarse
    //    cell holds a seed, so one is within sqrt(3) L).
    if (ws.n == 0) {
        const std::size_t own = raw_cell(gen, owner, coarse_cell_of(q, L), raw_budget, ws).n;
        double h = 0.7 * L / std::cbrt(static_cast<double>(std::max<std::size_t>(1, own))) + 2 * t;
        for (int pass = 0;; ++pass) {
            ws.S.clear(), ws.d2.clear();
            const double best2 = gather_near(q, h, gen, owner, raw_budget, ws);
            ws.n = ws.S.size();
            if (best2 <= h * h) {
                d1 = std::sqrt(best2);
                m = margin(d1);
                rho = d1 + 2 * t + 2 * m;
                if (rho * (1 + 1e-12) <= h) break;  // S holds every seed within rho (Lemma 2's S)
                h = rho * (1 + 1e-9);
            } else {
                h *= 2;
            }
            if (pass > 64) return near_answer::undecided;
        }
    }
    // 2. s_1 and the candidates C (delta_j <= t + m), from the seeds within rho.
    const std::size_t n = ws.n;
    std::size_t i1 = 0;
    for (std::size_t i = 1; i < n; ++i)
        if (ws.d2[i] < ws.d2[i1]) i1 = i;
    const vec3 s1 = ws.S[i1];
    ws.cand.clear();
    ws.cand.push_back(static_cast<int>(i1));
    const double rho2 = rho * rho, reach = t + m;
    for (std::size_t j = 0; j < n; ++j) {
        if (j == i1 || ws.d2[j] > rho2) continue;
        const vec3 dv = ws.S[j] - s1;
        const double len2 = glm::dot(dv, dv);
        if (!(len2 > 0)) return near_answer::undecided;  // coincident seeds
        // delta_j <= reach, i.e. dot <= reach |s_j - s_1| (both sides squared when positive)
        const double dot = glm::dot(dv, 0.5 * (ws.S[j] + s1) - q);
        if (dot <= 0 || dot * dot <= reach * reach * len2) ws.cand.push_back(static_cast<int>(j));
    }
    if (ws.cand.size() < 3) return near_answer::empty;  // Lemmas 1 and 2: delta_(2) > t + m
    // 3. the lines of the candidate triples, clipped by the seeds within rho (Lemma 3)
    const double lo_ok = (t - m) * (t - m), hi_ok = (t + m) * (t + m);
    const double circum_max = d1 + t + 2 * m;  // |e - a| = r(e) <= d_1 + t + m for e within t + m
    bool near_band = false;
    const std::size_t k = ws.cand.size();
    for (std::size_t ia = 0; ia < k; ++ia)
        for (std::size_t ib = ia + 1; ib < k; ++ib)
            for (std::size_t ic = ib + 1; ic < k; ++ic) {
                const int ta = ws.cand[ia], tb = ws.cand[ib], tc = ws.cand[ic];
                std::array<vec3, 3> s{ws.S[static_cast<std::size_t>(ta)], ws.S[static_cast<std::size_t>(tb)], ws.S[static_cast<std::size_t>(tc)]};
                std::sort(s.begin(), s.end(), canonical::before);
                const vec3 e1 = s[1] - s[0], e2 = s[2] - s[0], nrm = glm::cross(e1, e2);
                const double n2 = glm::dot(nrm, nrm);
                if (!(n2 > 0)) continue;  // collinear: no equidistant line (and none within reach)
                const vec3 c0 = s[0] + (glm::dot(e1, e1) * glm::cross(e2, nrm) + glm::dot(e2, e2) * glm::cross(nrm, e1)) / (2.0 * n2);
                const vec3 u = nrm / std::sqrt(n2);
                const vec3 a = s[0];
                // the circumradius |c0 - a| bounds |e - a| from below on the whole line
                const vec3 ca = c0 - a;
                if (glm::dot(ca, ca) > circum_max * circum_max) continue;
                double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
                bool gone = false;
                for (std::size_t j = 0; j < n && !gone; ++j) {
                    if (ws.d2[j] > rho2 || static_cast<int>(j) == ta || static_cast<int>(j) == tb || static_cast<int>(j) == tc) continue;
                    // a nearer than s_j at c0 + l u:  (c0 + l u - mid) . (s_j - a) <= 0
                    const vec3 nj = ws.S[j] - a;
                    const double alpha = glm::dot(u, nj), beta = glm::dot(c0 - 0.5 * (ws.S[j] + a), nj);
                    const double nl = std::sqrt(glm::dot(nj, nj));
                    if (std::abs(alpha) <= 1e-12 * nl) {  // plane parallel to the line
                        if (std::abs(beta) <= 1e-9 * nl * scale) near_band = true;
                        if (beta > 0) gone = true;
                        continue;
                    }
                    const double l = -beta / alpha;
                    if (alpha > 0) hi = std::min(hi, l);
                    else lo = std::max(lo, l);
                    if (lo > hi) gone = true;
                }
                if (gone) continue;
                const double lf = std::clamp(glm::dot(q - c0, u), lo, hi);
                if (!std::isfinite(lf)) continue;  // unbounded towards q's foot: cannot happen within reach
                const vec3 dq = q - (c0 + lf * u);
                const double dd = glm::dot(dq, dq);
                if (dd <= lo_ok) return near_answer::solid;
                if (dd <= hi_ok) near_band = true;
            }
    return near_band ? near_answer::undecided : near_answer::empty;
}

}  // namespace fabsynth::foam::detail
