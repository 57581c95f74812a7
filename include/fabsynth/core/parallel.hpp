#pragma once
/// @file parallel.hpp  Deterministic parallel loops on std::thread.
///
/// Determinism contract: parallel_for calls f(i) exactly once per index; as long as f(i) writes
/// only to data owned by index i, the result does not depend on the thread count. parallel_reduce
/// splits the range into blocks whose boundaries depend only on `grain` (never on the thread
/// count), reduces each block left to right and then the block results left to right, so even
/// floating-point sums are bit-identical for 1 or N threads.
///
/// Thread count: set_num_threads(n), else the FABSYNTH_NUM_THREADS environment variable, else
/// std::thread::hardware_concurrency(). Calls nested inside a worker run serially.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace fabsynth {

namespace detail {
inline std::atomic<unsigned>& thread_setting() {
    static std::atomic<unsigned> n{0};
    return n;
}
inline bool& inside_worker() {
    thread_local bool inside = false;
    return inside;
}
}  // namespace detail

/// Sets the number of worker threads for later parallel calls (0 = automatic).
inline void set_num_threads(unsigned n) { detail::thread_setting() = n; }

/// Number of threads parallel calls will use (>= 1).
inline unsigned num_threads() {
    if (unsigned n = detail::thread_setting()) return n;
    if (const char* env = std::getenv("FABSYNTH_NUM_THREADS")) {
        const long v = std::strtol(env, nullptr, 10);
        if (v > 0) return static_cast<unsigned>(std::min<long>(v, 1024));
    }
    return std::max(1u, std::thread::hardware_concurrency());
}

/// Options for parallel loops: `grain` indices are handed to a worker at a time.
struct parallel_options {
    std::size_t grain = 1;
    unsigned threads = 0;  ///< 0 = num_threads()
};

/// Calls f(i) for every i in [begin, end). If some calls throw, the exception of the lowest
/// failing chunk is rethrown after all workers stop (so the error reported is deterministic).
template <class F>
void parallel_for(std::size_t begin, std::size_t end, F&& f, parallel_options opt = {}) {
    if (end <= begin) return;
    const std::size_t grain = std::max<std::size_t>(1, opt.grain);
    const std::size_t chunks = (end - begin + grain - 1) / grain;
    unsigned threads = opt.threads ? opt.threads : num_threads();
    if (detail::inside_worker()) threads = 1;
    threads = static_cast<unsigned>(std::min<std::size_t>(threads, chunks));

    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    std::mutex error_mutex;
    std::exception_ptr first_error;
    std::size_t first_error_chunk = chunks;

    auto work = [&] {
        const bool was_inside = detail::inside_worker();
        detail::inside_worker() = true;
        for (;;) {
            const std::size_t c = next.fetch_add(1, std::memory_order_relaxed);
            if (c >= chunks || failed.load(std::memory_order_relaxed)) break;
            const std::size_t lo = begin + c * grain, hi = std::min(end, lo + grain);
            try {
                for (std::size_t i = lo; i < hi; ++i) f(i);
            } catch (...) {
                std::lock_guard lock(error_mutex);
                if (c < first_error_chunk) first_error_chunk = c, first_error = std::current_exception();
                failed = true;
            }
        }
        detail::inside_worker() = was_inside;
    };
    if (threads <= 1) {
        work();
    } else {
        std::vector<std::jthread> pool;
        pool.reserve(threads - 1);
        for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
        work();
    }  // jthreads join here
    if (first_error) std::rethrow_exception(first_error);
}

/// Deterministic reduction: returns reduce(...reduce(reduce(identity, map(begin)), map(begin+1))...)
/// evaluated blockwise with block boundaries at multiples of `grain` from begin.
template <class T, class Map, class Reduce>
T parallel_reduce(std::size_t begin, std::size_t end, T identity, Map&& map, Reduce&& reduce,
                  parallel_options opt = {.grain = 1024}) {
    if (end <= begin) return identity;
    const std::size_t grain = std::max<std::size_t>(1, opt.grain);
    const std::size_t blocks = (end - begin + grain - 1) / grain;
    std::vector<T> partial(blocks, identity);
    parallel_for(
        0, blocks,
        [&](std::size_t b) {
            const std::size_t lo = begin + b * grain, hi = std::min(end, lo + grain);
            T acc = identity;
            for (std::size_t i = lo; i < hi; ++i) acc = reduce(std::move(acc), map(i));
            partial[b] = std::move(acc);
        },
        {.grain = 1, .threads = opt.threads});
    T total = std::move(identity);
    for (auto& p : partial) total = reduce(std::move(total), std::move(p));
    return total;
}

}  // namespace fabsynth
