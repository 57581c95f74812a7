// SPDX-License-Identifier: MIT
#pragma once
/// @file progress.hpp  Progress reporting for long computations.
///
/// A progress callback is called as `cb(fraction, stage)` with fraction in [0,1] and a short
/// stage name. If it returns bool, returning false cancels the work (the library throws
/// fabsynth::cancelled). Drivers render it on stderr; library code never prints.
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

}  // namespace fabsynth
