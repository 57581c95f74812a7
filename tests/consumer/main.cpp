// Compiles against the installed headers and checks a few values end to end.
#include <fabsynth/core.hpp>

#include <cstdio>

int main() {
    fabsynth::box3 b;
    b.extend({0, 0, 0}).extend({1, 2, 3});
    const double sum = fabsynth::parallel_reduce(
        0, 1000, 0.0, [](std::size_t i) { return fabsynth::hash_uniform(7, i); }, std::plus<>{});
    std::printf("fabsynth %s consumer: box volume %.1f, hash sum %.6f\n", FABSYNTH_VERSION_STRING, b.volume(), sum);
    return (b.volume() == 6.0 && sum > 400 && sum < 600) ? 0 : 1;
}
