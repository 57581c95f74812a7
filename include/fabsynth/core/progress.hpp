// SPDX-License-Identifier: MIT
#pragma once
/// @file progress.hpp  Progress reporting for long computations.
///
/// A progress callback is called as `cb(fraction, stage)` with fraction in [0,1] and a short
/// stage name. If it returns bool, returning false cancels the work (the library throws
/// fabsynth::cancelled). Drivers render it on stderr; library code never prints.
///
/// An entry point hands each of its phases a progress_span: the phase's share [from, to] of the
/// caller's progress. Long loops inside the phase report through it (fractions of the phase), so a
/// cancellation takes effect inside the loop, not only at the next phase boundary.
#include <algorithm>
#include <concepts>
#include <functional>
#include <string>
#include <string_view>
#include <type_traits>

#include "fabsynth/core/error.hpp"

namespace fabsynth {

/// Anything callable as cb(double fraction, std::string_view stage) returning void or bool.
template <class F>
concept progress_callback =
    std::invocable<F&, double, std::string_view> &&
    (std::is_void_v<std::invoke_result_t<F&, double, std::string_view>> ||
     std::convertible_to<std::invoke_result_t<F&, double, std::string_view>, bool>);

/// The do-nothing callback (default everywhere).
struct no_progress {
    constexpr void operator()(double, std::string_view) const noexcept {}
};

/// Type-erased callback for non-template APIs; an empty function reports nowhere.
using progress_function = std::function<bool(double, std::string_view)>;

/// Calls cb; throws fabsynth::cancelled if it returned false.
template <progress_callback F>
void report_progress(F& cb, double fraction, std::string_view stage) {
    if constexpr (std::is_void_v<std::invoke_result_t<F&, double, std::string_view>>) {
        cb(fraction, stage);
    } else if constexpr (std::is_same_v<std::remove_cvref_t<F>, progress_function>) {
        if (cb && !cb(fraction, stage)) throw cancelled("cancelled by progress callback during " + std::string(stage));
    } else {
        if (!static_cast<bool>(cb(fraction, stage)))
            throw cancelled("cancelled by progress callback during " + std::string(stage));
    }
}

/// One phase's share [from, to] of a caller's progress, for the loops inside the phase. Calling it
/// with a fraction f in [0, 1] of the phase reports from + (to - from) f to the caller's callback
/// and throws fabsynth::cancelled when the callback asks to stop. Call it from one thread only (the
/// serial part of a parallel loop). A default-constructed span reports nowhere and never cancels.
/// The span refers to the caller's callback: it must not outlive it.
class progress_span {
public:
    progress_span() = default;

    template <progress_callback F>
        requires(!std::same_as<std::remove_cvref_t<F>, progress_span>)
    progress_span(F& cb, double from, double to)
        : report_([&cb](double f, std::string_view stage) { report_progress(cb, f, stage); }), from_(from), to_(to) {}

    void operator()(double fraction, std::string_view stage) const {
        if (report_) report_(from_ + (to_ - from_) * std::clamp(fraction, 0.0, 1.0), stage);
    }

    /// The part [a, b] of this span (fractions of it), for a loop nested in a loop.
    [[nodiscard]] progress_span part(double a, double b) const {
        progress_span p = *this;
        p.from_ = from_ + (to_ - from_) * a, p.to_ = from_ + (to_ - from_) * b;
        return p;
    }

private:
    std::function<void(double, std::string_view)> report_;
    double from_ = 0.0, to_ = 1.0;
};

}  // namespace fabsynth
