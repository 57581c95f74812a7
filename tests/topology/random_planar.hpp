#pragma once
// Test helper: random planar piece descriptors and an independent topology oracle.
#include <fabsynth/core/rng.hpp>
#include <fabsynth/topology/descriptor.hpp>

#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

namespace fabsynth_test {

// Labels of a random non-crossing partition of `left` + `right` boundary points. Walking around a
// vertical strip the portals come in the cyclic order L0..L(a-1), R(b-1)..R0; a partition that does
// not cross in this order is realisable by disjoint planar regions inside the strip.
inline fabsynth::topology::descriptor random_planar_piece(fabsynth::counter_rng& rng, std::size_t left,
                                                          std::size_t right, std::uint32_t max_enclosed = 1,
                                                          std::uint32_t max_holes = 1) {
    const std::size_t m = left + right;
    std::vector<std::uint32_t> cyc(m);
    std::vector<std::uint32_t> stack;  // open blocks, innermost last
    std::uint32_t next = 0;
    for (std::size_t k = 0; k < m; ++k) {
        const std::uint64_t choice = rng.uniform_int(stack.size() + 2);
        if (choice == 0 || stack.empty()) {  // new block
            stack.push_back(next++);
        } else {
            stack.resize(std::min<std::size_t>(stack.size(), choice));  // close blocks above the one we join
        }
        cyc[k] = stack.back();
    }
    std::vector<std::uint32_t> l(left), r(right);
    for (std::size_t k = 0; k < left; ++k) l[k] = cyc[k];
    for (std::size_t k = 0; k < right; ++k) r[right - 1 - k] = cyc[left + k];
    const auto enclosed = static_cast<std::uint32_t>(rng.uniform_int(max_enclosed + 1));
    const auto holes = static_cast<std::uint32_t>(rng.uniform_int(max_holes + 1));
    return fabsynth::topology::descriptor(l, r, enclosed, holes);
}

// Oracle: topology of pieces glued left to right (and optionally closed into a loop), computed
// globally on the explicit glue graph by breadth-first search instead of incremental merges.
// Nodes = (piece, local component); edges = glued portal pairs (seam edges shift by one turn).
// components = sum enclosed + graph components; holes = sum holes + cycle rank (- rings on a loop).
struct oracle_topology {
    std::uint64_t components = 0, holes = 0, rings = 0;
    std::vector<std::uint32_t> left_labels, right_labels;  // graph component of each outer portal
};

inline oracle_topology oracle(const std::vector<fabsynth::topology::descriptor>& seq, bool loop) {
    std::vector<std::size_t> base(seq.size() + 1, 0);
    for (std::size_t i = 0; i < seq.size(); ++i) base[i + 1] = base[i] + seq[i].open_components();
    const std::size_t nv = base.back();
    std::vector<std::vector<std::pair<std::size_t, int>>> adj(nv);  // (neighbour, shift)
    std::size_t ne = 0;
    auto add_edge = [&](std::size_t a, std::size_t b, int shift) {
        adj[a].push_back({b, shift});
        adj[b].push_back({a, -shift});
        ++ne;
    };
    oracle_topology o;
    for (const auto& d : seq) o.components += d.enclosed(), o.holes += d.holes();
    for (std::size_t i = 0; i + 1 < seq.size(); ++i)
        for (std::size_t k = 0; k < seq[i].right().size(); ++k)
            add_edge(base[i] + seq[i].right()[k], base[i + 1] + seq[i + 1].left()[k], 0);
    if (loop)
        for (std::size_t k = 0; k < seq.back().right().size(); ++k)
            add_edge(base[seq.size() - 1] + seq.back().right()[k], base[0] + seq.front().left()[k], 1);
    std::vector<std::int64_t> pos(nv, 0);
    std::vector<std::uint32_t> comp(nv, 0xffffffffu);
    std::uint32_t nc = 0;
    for (std::size_t s = 0; s < nv; ++s) {
        if (comp[s] != 0xffffffffu) continue;
        bool winds = false;
        std::deque<std::size_t> queue{s};
        comp[s] = nc;
        while (!queue.empty()) {
            const std::size_t v = queue.front();
            queue.pop_front();
            for (auto [w, sh] : adj[v]) {
                if (comp[w] == 0xffffffffu) {
                    comp[w] = nc, pos[w] = pos[v] + sh, queue.push_back(w);
                } else if (pos[w] != pos[v] + sh) {
                    winds = true;
                }
            }
        }
        o.rings += winds ? 1 : 0;
        ++nc;
    }
    o.components += nc;
    o.holes += ne + nc - nv;  // cycle rank of the glue graph
    o.holes -= o.rings;
    if (!loop) {
        for (auto id : seq.front().left()) o.left_labels.push_back(comp[base[0] + id]);
        for (auto id : seq.back().right()) o.right_labels.push_back(comp[base[seq.size() - 1] + id]);
    }
    return o;
}

}  // namespace fabsynth_test
