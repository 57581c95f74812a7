// Filigree synthesis in 2D, stage by stage (filigree-synthesis.md Table 2: 20-57 elements, 2-3
// iterations, 6.6-25 s on an i7-4770 for the paper's 2D results). Each benchmark runs one stage on
// the bundled elements in a 90 x 70 mm rectangle (element size 20 mm, strips 0.8 mm) and reports
// the instance count; BM_FiligreePattern is the whole pattern synthesis (initialization,
// placement with smooth connections, boosting, topology cut), BM_FiligreeStructure the shell-FEM
// structural optimization of §5 on its result.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/filigree.hpp"
#include "fabsynth/io/svg.hpp"

namespace {

using namespace fabsynth;
using namespace fabsynth::filigree;

const char* const element_names[] = {"spiral", "s_curl", "c_scroll", "leaf", "heart_curls"};

std::vector<element> load(int which) {
    element_options o;
    o.size_mm = 20;
    o.width_mm = 0.8;
    o.name = element_names[which];
    return {element_from_svg(io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/filigree/" + element_names[which] + ".svg", 0.01), o)};
}

const planar_domain& domain() {
    static const planar_domain d = planar_domain::rectangle(90, 70);
    return d;
}

void label(benchmark::State& state, int which, std::size_t n) {
    state.SetLabel(std::string(element_names[which]) + ", " + std::to_string(n) + " elements");
    state.counters["elements"] = static_cast<double>(n);
}

void BM_FiligreeInitialization(benchmark::State& state) {
    const int which = static_cast<int>(state.range(0));
    const auto cls = load(which);
    const std::vector<double> w{1.0};
    std::size_t n = 0;
    for (auto _ : state) n = initialize(std::span<const element>(cls), w, domain(), constant_field{}).instances.size();
    label(state, which, n);
}
BENCHMARK(BM_FiligreeInitialization)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

void BM_FiligreePlacement(benchmark::State& state) {
    const int which = static_cast<int>(state.range(0));
    set_num_threads(static_cast<unsigned>(state.range(1)));
    const auto cls = load(which);
    const std::vector<double> w{1.0};
    const auto init = initialize(std::span<const element>(cls), w, domain(), constant_field{});
    for (auto _ : state) {
        pattern_state s(cls, init.instances, constant_field{}, domain());
        connection_database D;
        placement_options po;
        po.smooth_connection = make_smooth_connection(0.15);
        benchmark::DoNotOptimize(place_optimize(s, D, po));
    }
    set_num_threads(0);
    label(state, which, init.instances.size());
}
BENCHMARK(BM_FiligreePlacement)->ArgsProduct({{0, 1, 2, 3, 4}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FiligreePattern(benchmark::State& state) {
    const int which = static_cast<int>(state.range(0));
    set_num_threads(static_cast<unsigned>(state.range(1)));
    const auto cls = load(which);
    const std::vector<double> w{1.0};
    synthesis_result r;
    for (auto _ : state) r = synthesize_pattern(std::span<const element>(cls), w, domain(), constant_field{});
    set_num_threads(0);
    label(state, which, r.instances.size());
    state.counters["rounds"] = r.rounds;
    state.counters["init_s"] = r.seconds.initialization;
    state.counters["placement_s"] = r.seconds.placement;
    state.counters["boosting_s"] = r.seconds.boosting;
    state.counters["cut_s"] = r.seconds.topology_cut;
}
BENCHMARK(BM_FiligreePattern)->ArgsProduct({{0, 1, 2, 3, 4}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FiligreeStructure(benchmark::State& state) {
    const int which = static_cast<int>(state.range(0));
    const auto cls = load(which);
    const std::vector<double> w{1.0};
    const synthesis_options so;
    const synthesis_result syn = synthesize_pattern(std::span<const element>(cls), w, domain(), constant_field{}, so);
    reinforcement_result r;
    for (auto _ : state) r = reinforce(std::span<const element>(cls), w, domain(), constant_field{}, so, syn);
    label(state, which, r.instances.size());
    state.counters["fem_nodes"] = static_cast<double>(r.fem_nodes);
    state.counters["thickness_mm"] = r.thickness;
    state.counters["analyses"] = static_cast<double>(r.weak_fraction_phase1.size() + r.weak_fraction_phase2.size());
}
BENCHMARK(BM_FiligreeStructure)->DenseRange(0, 4)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
