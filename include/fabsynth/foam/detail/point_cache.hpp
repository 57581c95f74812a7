// SPDX-License-Identifier: MIT
#pragma once
/// @file point_cache.hpp  (internal, behind evaluator.hpp) What makes repeated point queries cheap:
/// the Voronoi edge pieces of a block, built once and binned, kept in a per-thread cache.
///
/// A point q is answered from its *block*: the coarse cell k holding q, grown by the foam's
/// maximum radius R on every side. Every edge point within R of q lies in that box, so the edge
/// pieces inside it (voronoi_edges.hpp, the certificate of certificate.hpp applied to the box) are
/// complete for every query of radius <= R whose point lies in cell k. The cell is split into bins
/// of side ~2R; a bin lists, as 16-byte records, the pieces whose segment quantized to 16 bits per
/// coordinate comes within R (plus the quantization's bound) of the bin's box. A query tests its
/// bin's records in float, a test that rejects pieces certainly out of reach (and, for contains,
/// accepts pieces certainly within it), and tests the rest exactly (canonical_piece.hpp's distance2).
///
/// Exactness: a block's pieces depend only on the foam and k, not on the query or on what the
/// cache held before; the float test rejects only pieces farther than the query radius and
/// accepts only pieces nearer than it by more than its error bound; a query's answer is then an
/// exact test or a minimum over the pieces within reach, so a cached and an uncached answer (the
/// pieces of the query's own cube q +- r) are the same bits.
///
/// Memory: a thread's cache keeps blocks while their bytes (pieces, records, bin offsets) stay
/// within its budget, dropping the least recently used first; it holds at most budget + one block.
/// A budget of 0 keeps only the block of the latest build. A missed block is built once it has been
/// missed a number of times (the caller's choice); when the cache is full of blocks in use, only if
/// those misses fell within 4 x that many of the thread's misses (a scan staying in the block). The other
/// misses are answered from the pieces of the query's own small cube, with the same bits at the
/// cost of an uncached query, so points scattered over more blocks than the budget holds do not
/// build a block each. contains() asks for runs only and answers its other misses from the seeds
/// near the point (near_seeds.hpp), whose per-thread seed caches come on top of this budget
/// (extended cells within 1/8 of it, raw cells within another 1/8; foam_options::point_cache_bytes).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/detail/canonical_piece.hpp"
#include "fabsynth/foam/detail/workspace.hpp"

namespace fabsynth::foam::detail {

/// A piece as its computed segment quantized to 16 bits per coordinate over the block's box: a
/// cheap test that rejects the pieces out of reach before the exact one (canonical_piece.hpp).
struct piece_record {
    std::uint16_t a[3], b[3];
    std::uint32_t piece;  ///< index into edge_block::pieces; | exact_only: always tested exactly
    static constexpr std::uint32_t exact_only = 0x80000000u;
};
static_assert(sizeof(piece_record) == 16);

/// Squared distance from q (in quantization units) to the record's segment, in float.
[[nodiscard]] inline float record_distance2(const piece_record& r, float qx, float qy, float qz) noexcept {
    const float ax = r.a[0], ay = r.a[1], az = r.a[2];
    const float dx = float(r.b[0]) - ax, dy = float(r.b[1]) - ay, dz = float(r.b[2]) - az;
    const float wx = qx - ax, wy = qy - ay, wz = qz - az;
    const float dd = dx * dx + dy * dy + dz * dz, wd = wx * dx + wy * dy + wz * dz;
    const float t = dd > 0 ? std::clamp(wd / dd, 0.0f, 1.0f) : 0.0f;
    const float ex = wx - t * dx, ey = wy - t * dy, ez = wz - t * dz;
    return ex * ex + ey * ey + ez * ez;
}

/// The edge pieces of one block, binned (see the file comment).
struct edge_block {
    std::uint64_t owner = 0;  // the foam instance
    i64vec3 key{0};           // the coarse cell
    vec3 lo{0.0};             // the block box's low corner (cell corner - R)
    double inv_step = 1.0;    // quantization units per mm (65535 over the box side)
    vec3 cell_lo{0.0};        // the cell's low corner: the bins tile the cell
    double inv_bin = 1.0;     // 1 / bin side
    int bins = 1;             // bins per axis
    float tol = 0;            // units a record's segment may lie from its exact piece, plus float slack
    std::vector<canonical_piece> pieces;
    std::vector<std::uint32_t> bin_start;  // bins^3 + 1 prefix offsets into records
    std::vector<piece_record> records;     // per bin, the pieces within reach of it
    std::uint64_t last_use = 0;

    [[nodiscard]] std::size_t bytes() const noexcept {
        return sizeof(*this) + pieces.capacity() * sizeof(canonical_piece) + bin_start.capacity() * sizeof(std::uint32_t) +
               records.capacity() * sizeof(piece_record);
    }
    /// Whether some piece lies within t (<= the block's R) of q (q in the block's cell).
    [[nodiscard]] bool any_within(const vec3& q, double t) const noexcept {
        const auto [first, last] = bin_of(q);
        const vec3 u = (q - lo) * inv_step;
        const float qx = static_cast<float>(u.x), qy = static_cast<float>(u.y), qz = static_cast<float>(u.z);
        const float reach = static_cast<float>(t * inv_step) + tol, reach2 = reach * reach * 1.00001f;
        // a record this near is certainly within t: its exact piece lies within 2 x the deviation
        // bound of it (a vertex end may sit that far from the record's end), plus float slack
        const float sure = static_cast<float>(t * inv_step) - 2 * tol, sure2 = sure > 0 ? sure * sure * 0.99999f : -1.0f;
        const double t2 = t * t;
        for (const piece_record* r = first; r != last; ++r) {
            if (r->piece & piece_record::exact_only) {
                if (distance2(pieces[r->piece & ~piece_record::exact_only], q) <= t2) return true;
                continue;
            }
            const float d2 = record_distance2(*r, qx, qy, qz);
            if (d2 <= sure2) return true;
            if (d2 <= reach2 && distance2(pieces[r->piece], q) <= t2) return true;
        }
        return false;
    }
    /// The least squared distance from q to a piece if it is <= r^2 (r <= the block's R), else
    /// +infinity.
    [[nodiscard]] double nearest2(const vec3& q, double r) const noexcept {
        const auto [first, last] = bin_of(q);
        const vec3 u = (q - lo) * inv_step;
        const float qx = static_cast<float>(u.x), qy = static_cast<float>(u.y), qz = static_cast<float>(u.z);
        double best = r * r;
        bool found = false;
        float reach = static_cast<float>(r * inv_step) + tol, reach2 = reach * reach * 1.00001f;
        for (const piece_record* rec = first; rec != last; ++rec) {
            if (!(rec->piece & piece_record::exact_only) && record_distance2(*rec, qx, qy, qz) > reach2) continue;
            const double d2 = distance2(pieces[rec->piece & ~piece_record::exact_only], q);
            if (d2 <= best) {
                best = d2, found = true;
                reach = static_cast<float>(std::sqrt(d2) * inv_step) + tol, reach2 = reach * reach * 1.00001f;
            }
        }
        return found ? best : std::numeric_limits<double>::infinity();
    }

private:
    [[nodiscard]] std::pair<const piece_record*, const piece_record*> bin_of(const vec3& q) const noexcept {
        const vec3 t = (q - cell_lo) * inv_bin;
        const int i = std::clamp(static_cast<int>(std::floor(t.x)), 0, bins - 1), j = std::clamp(static_cast<int>(std::floor(t.y)), 0, bins - 1),
                  k = std::clamp(static_cast<int>(std::floor(t.z)), 0, bins - 1);
        const std::size_t b = (static_cast<std::size_t>(k) * static_cast<std::size_t>(bins) + static_cast<std::size_t>(j)) * static_cast<std::size_t>(bins) +
                              static_cast<std::size_t>(i);
        return {records.data() + bin_start[b], records.data() + bin_start[b + 1]};
    }
};

/// The box of block k: coarse cell k grown by r (and 1e-9 cell, for a point that floor(q / cell)
/// puts in cell k but rounding puts a hair outside it).
[[nodiscard]] inline box3 block_box(const i64vec3& k, double cell, double r) {
    const vec3 lo = vec3(static_cast<double>(k.x), static_cast<double>(k.y), static_cast<double>(k.z)) * cell;
    const double grow = r + 1e-9 * cell;
    return {lo - vec3(grow), lo + vec3(cell + grow)};
}

namespace point_cache_detail {
// Whether segment [p, q] meets box [lo, hi] (slab clipping).
[[nodiscard]] inline bool segment_meets_box(const vec3& p, const vec3& q, const vec3& lo, const vec3& hi) noexcept {
    double t0 = 0, t1 = 1;
    for (int a = 0; a < 3; ++a) {
        const double d = q[a] - p[a];
        if (d == 0) {
            if (p[a] < lo[a] || p[a] > hi[a]) return false;
            continue;
        }
        double ta = (lo[a] - p[a]) / d, tb = (hi[a] - p[a]) / d;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta), t1 = std::min(t1, tb);
        if (t0 > t1) return false;
    }
    return true;
}
}  // namespace point_cache_detail

/// Bins per axis of a block: bins of about two radii keep a query's records few (about 8 in the
/// graded benchmark foam) at about 9 records per piece; four radii halve the records' memory but
/// test 22 per query, and were slower in row order and at random (benchmarks/README.md).
inline constexpr double bin_side_in_radii = 2.0;

/// Fills blk with the edge pieces of block k (radius R) of the foam whose for_each_piece is given,
/// and bins them.
template <class ForEachPiece>
void build_edge_block(edge_block& blk, std::uint64_t owner, const i64vec3& k, double cell, double R, foam_workspace& ws, ForEachPiece&& for_each_piece) {
    const box3 b = block_box(k, cell, R);
    blk.owner = owner, blk.key = k, blk.lo = b.lo;
    blk.cell_lo = vec3(static_cast<double>(k.x), static_cast<double>(k.y), static_cast<double>(k.z)) * cell;
    const double side = b.hi.x - b.lo.x;
    blk.inv_step = 65535.0 / side;
    blk.pieces.clear();
    std::vector<piece_record> recs;
    std::vector<double> dev;  // units from a record's segment to its exact piece
    for_each_piece(b, ws, [&](const canonical_piece& p, const vec3& a, const vec3& e) {
        piece_record r{};
        vec3 qa{0.0}, qe{0.0};  // the quantized ends, back in mm
        for (int c = 0; c < 3; ++c) {
            const auto quant = [&](double x) { return static_cast<std::uint16_t>(std::clamp(std::round((x - b.lo[c]) * blk.inv_step), 0.0, 65535.0)); };
            r.a[c] = quant(a[c]), r.b[c] = quant(e[c]);
            qa[c] = b.lo[c] + r.a[c] / blk.inv_step, qe[c] = b.lo[c] + r.b[c] / blk.inv_step;
        }
        // Hausdorff bound between the record's segment and every point distance2() measures to
        const vec3 lo_line = p.c + p.lo * p.u, hi_line = p.c + p.hi * p.u, lo_end = end_point(p, false), hi_end = end_point(p, true);
        const auto off = [](const vec3& x, const vec3& y, const vec3& z) { return std::max(glm::length(x - y), glm::length(x - z)); };
        const double d = std::min(std::max(off(qa, lo_line, lo_end), off(qe, hi_line, hi_end)), std::max(off(qe, lo_line, lo_end), off(qa, hi_line, hi_end)));
        if (blk.pieces.size() >= piece_record::exact_only) throw invalid_input("foam point cache: a block holds too many edge pieces");
        r.piece = static_cast<std::uint32_t>(blk.pieces.size());
        blk.pieces.push_back(p);
        recs.push_back(r);
        dev.push_back(d * blk.inv_step);
        return true;
    });
    // A record may lie 2 units from its piece (rounding to the 16-bit grid moves an end by <= 0.87);
    // farther ones (degenerate seeds) are always tested exactly. One more unit covers the float
    // test's rounding and a query a hair outside the cell.
    constexpr double dev_limit = 2.0;
    blk.tol = static_cast<float>(dev_limit + 1.0);
    for (std::size_t i = 0; i < recs.size(); ++i)
        if (!(dev[i] <= dev_limit)) recs[i].piece |= piece_record::exact_only;
    blk.bins = std::clamp(static_cast<int>(std::floor(cell / (bin_side_in_radii * R))), 1, 32);
    const int n = blk.bins;
    const double bin = cell / n;
    blk.inv_bin = 1.0 / bin;
    const double reach_units = R * blk.inv_step + blk.tol;
    auto for_bins_of = [&](std::size_t ri, auto&& visit) {  // bins whose box grown by the reach meets the record
        const piece_record& r = recs[ri];
        const double reach = (reach_units + (r.piece & piece_record::exact_only ? dev[ri] : 0.0)) / blk.inv_step;
        vec3 p, q;
        for (int c = 0; c < 3; ++c) p[c] = b.lo[c] + r.a[c] / blk.inv_step, q[c] = b.lo[c] + r.b[c] / blk.inv_step;
        const vec3 lo = (glm::min(p, q) - vec3(reach) - blk.cell_lo) * blk.inv_bin, hi = (glm::max(p, q) + vec3(reach) - blk.cell_lo) * blk.inv_bin;
        const int i0 = std::max(0, static_cast<int>(std::floor(lo.x))), i1 = std::min(n - 1, static_cast<int>(std::floor(hi.x)));
        const int j0 = std::max(0, static_cast<int>(std::floor(lo.y))), j1 = std::min(n - 1, static_cast<int>(std::floor(hi.y)));
        const int k0 = std::max(0, static_cast<int>(std::floor(lo.z))), k1 = std::min(n - 1, static_cast<int>(std::floor(hi.z)));
        for (int z = k0; z <= k1; ++z)
            for (int y = j0; y <= j1; ++y)
                for (int x = i0; x <= i1; ++x) {
                    const vec3 bl = blk.cell_lo + vec3(x, y, z) * bin;
                    if (point_cache_detail::segment_meets_box(p, q, bl - vec3(reach), bl + vec3(bin + reach)))
                        visit((static_cast<std::size_t>(z) * n + y) * n + x);
                }
    };
    std::vector<std::uint32_t> count(static_cast<std::size_t>(n) * n * n + 1, 0);
    for (std::size_t ri = 0; ri < recs.size(); ++ri) for_bins_of(ri, [&](std::size_t bi) { ++count[bi + 1]; });
    for (std::size_t i = 1; i < count.size(); ++i) count[i] += count[i - 1];
    blk.bin_start = count;
    blk.records.assign(count.back(), piece_record{});
    for (std::size_t ri = 0; ri < recs.size(); ++ri) for_bins_of(ri, [&](std::size_t bi) { blk.records[count[bi]++] = recs[ri]; });
    blk.pieces.shrink_to_fit();
}

/// A thread's blocks (see the file comment), found through an open-addressing table.
class edge_block_cache {
public:
    /// Sets the byte budget (the foams of one type share a thread's cache: the one that asks last
    /// sets it), dropping the least recently used blocks beyond it.
    void set_budget(std::size_t budget) {
        if (budget == budget_) return;
        budget_ = budget;
        while (!blocks_.empty() && bytes_ > budget_) evict_oldest();
    }

    /// The held block (owner, k), or null.
    [[nodiscard]] const edge_block* find(std::uint64_t owner, const i64vec3& k) noexcept {
        ++clock_;
        if (last_ && last_->owner == owner && last_->key == k) {
            last_->last_use = clock_;
            return last_;
        }
        if (table_.empty()) return nullptr;
        const std::size_t mask = table_.size() - 1;
        for (std::size_t i = hash64(owner, k.x, k.y, k.z) & mask; table_[i]; i = (i + 1) & mask) {
            edge_block* b = table_[i];
            if (b->owner == owner && b->key == k) {
                b->last_use = clock_;
                return last_ = b;
            }
        }
        return nullptr;
    }
    /// Whether a miss on block (owner, k) should build it (see the file comment): once it has been
    /// missed `repeat` times, within the last 4 x repeat misses of this thread when the cache is
    /// full: has no room for `typical` more bytes and its least recently used block was used
    /// within the last 2^18 queries (older blocks are stale: evicting them costs nothing).
    /// `scattered` > `repeat` (callers whose misses are cheap): the window always applies, and a
    /// block missed `scattered` times in all is built too (building then costs about what its
    /// misses did).
    /// Starts loading the tally of (owner, k) that worth_building() will read (a random line of
    /// a 384 KB table: a cache miss that other work can hide).
    void prefetch_tally(std::uint64_t owner, const i64vec3& k) const noexcept {
        if (!tally_.empty()) __builtin_prefetch(&tally_[hash64(owner, k.x, k.y, k.z) & 16383]);
    }
    [[nodiscard]] bool worth_building(std::uint64_t owner, const i64vec3& k, std::size_t budget, std::size_t typical, int repeat, int scattered) {
        ++misses_;
        const bool full = bytes_ + typical > budget && !blocks_.empty() && clock_ - blocks_[oldest()]->last_use < (std::uint64_t(1) << 18);
        // a direct-mapped tally: a block sharing the slot restarts the count (answers never
        // depend on it)
        const std::uint64_t key = hash64(owner, k.x, k.y, k.z);
        if (tally_.empty()) tally_.resize(16384);
        tally& t = tally_[key & 16383];
        if (t.key != key) t = {0, 0, misses_, key};
        if (t.run == 0 || ((full || scattered > repeat) && misses_ - t.since > 4 * static_cast<std::uint64_t>(repeat))) t.run = 0, t.since = misses_;
        if (t.total < scattered) ++t.total;  // (saturates: never wraps)
        if (++t.run < repeat && t.total < scattered) return false;
        t = {};
        return true;
    }
    /// The block (owner, k), built by build(blk) when it is not held. `budget`: bytes to keep.
    template <class Build>
    const edge_block& get(std::uint64_t owner, const i64vec3& k, std::size_t budget, Build&& build) {
        if (const edge_block* b = find(owner, k)) return *b;
        auto blk = std::make_unique<edge_block>();
        build(*blk);
        blk->last_use = clock_;
        const std::size_t need = blk->bytes();
        while (!blocks_.empty() && bytes_ + need > budget) evict_oldest();
        bytes_ += need;
        blocks_.push_back(std::move(blk));
        if (2 * blocks_.size() > table_.size()) reindex();
        else insert(blocks_.back().get());
        return *(last_ = blocks_.back().get());
    }
    [[nodiscard]] std::size_t bytes() const noexcept { return bytes_; }
    [[nodiscard]] std::size_t size() const noexcept { return blocks_.size(); }
    [[nodiscard]] std::size_t largest_block_bytes() const noexcept {
        std::size_t most = 0;
        for (const auto& b : blocks_) most = std::max(most, b->bytes());
        return most;
    }

private:
    void insert(edge_block* b) noexcept {
        const std::size_t mask = table_.size() - 1;
        std::size_t i = hash64(b->owner, b->key.x, b->key.y, b->key.z) & mask;
        while (table_[i]) i = (i + 1) & mask;
        table_[i] = b;
    }
    // Rebuilds the table at a load of at most 1/2 (an eviction costs O(blocks), a build far more).
    void reindex() {
        std::size_t n = 16;
        while (n < 2 * blocks_.size()) n *= 2;
        table_.assign(2 * n, nullptr);
        for (const auto& b : blocks_) insert(b.get());
    }
    [[nodiscard]] std::size_t oldest() const noexcept {
        std::size_t o = 0;
        for (std::size_t i = 1; i < blocks_.size(); ++i)
            if (blocks_[i]->last_use < blocks_[o]->last_use) o = i;
        return o;
    }
    void evict_oldest() {
        const std::size_t o = oldest();
        if (last_ == blocks_[o].get()) last_ = nullptr;
        bytes_ -= blocks_[o]->bytes();
        std::swap(blocks_[o], blocks_.back());
        blocks_.pop_back();
        reindex();
    }

    struct tally {
        int run = 0, total = 0;  // misses in the current run (window), and in all
        std::uint64_t since = 0;  // this thread's miss count at the block's first counted miss
        std::uint64_t key = 0;    // hash of (owner, block)
    };
    std::uint64_t misses_ = 0;
    std::vector<tally> tally_;  // misses per block, direct-mapped by hash
    std::size_t budget_ = SIZE_MAX;
    std::vector<std::unique_ptr<edge_block>> blocks_;
    std::vector<edge_block*> table_;  // open addressing, linear probing; null = empty
    edge_block* last_ = nullptr;
    std::size_t bytes_ = 0;
    std::uint64_t clock_ = 0;  // queries (find calls) so far
};

}  // namespace fabsynth::foam::detail
