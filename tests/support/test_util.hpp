#pragma once
// Small helpers shared by the module tests (one place, so unity builds see one definition).
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/geometry/polygon.hpp"

namespace fabsynth::test {

/// Restores the library's thread setting (0 = automatic included) when a test that changes it
/// ends or throws.
struct thread_count_guard {
    unsigned saved = detail::thread_setting();
    thread_count_guard() = default;
    thread_count_guard(const thread_count_guard&) = delete;
    thread_count_guard& operator=(const thread_count_guard&) = delete;
    ~thread_count_guard() { set_num_threads(saved); }
};

/// The axis-aligned rectangle [x0, x1] x [y0, y1] as a counter-clockwise ring.
inline ring2 rect_ring(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

}  // namespace fabsynth::test
