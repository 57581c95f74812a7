// Compiles against the installed headers and checks a few values end to end.
#include <fabsynth/core.hpp>
#include <fabsynth/geometry/medial_axis.hpp>  // needs Boost headers through the package config
#include <fabsynth/sampling.hpp>

#include <cstdio>
#include <vector>

int main() {
    fabsynth::box3 b;
    b.extend({0, 0, 0}).extend({1, 2, 3});
    const double sum = fabsynth::parallel_reduce(
        0, 1000, 0.0, [](std::size_t i) { return fabsynth::hash_uniform(7, i); }, std::plus<>{});
    const auto skeleton = fabsynth::medial_axis({{{0, 0}, {10, 0}, {10, 4}, {0, 4}}, {}}, {.prune_length = 3.0});
    const std::vector<fabsynth::vec2> pts{{0, 0}, {0.5, 0}, {2, 0}};
    const auto samples = fabsynth::sampling::poisson_disk(pts, 1.0);
    std::printf("fabsynth %s consumer: box volume %.1f, hash sum %.6f, skeleton edges %zu, samples %zu\n",
                FABSYNTH_VERSION_STRING, b.volume(), sum, skeleton.edges.size(), samples.size());
    return (b.volume() == 6.0 && sum > 400 && sum < 600 && skeleton.edges.size() == 1 && samples.size() == 2) ? 0 : 1;
}
