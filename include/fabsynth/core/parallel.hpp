// SPDX-License-Identifier: MIT
#pragma once
/// @file parallel.hpp  Deterministic parallel loops on a persistent thread pool.
///
/// Determinism contract: parallel_for calls f(i) exactly once per index; as long as f(i) writes
/// only to data owned by index i, the result does not depend on the thread count. parallel_reduce
/// splits the range into blocks whose boundaries depend only on `grain` (never on the thread
/// count), reduces each block left to right and then the block results left to right, so even
/// floating-point sums are bit-identical for 1 or N threads. If calls throw, the exception of the
/// lowest failing chunk is rethrown: a chunk is skipped only when a lower chunk has already
/// failed, so every chunk below the lowest failing one runs and the error does not depend on
/// timing.
///
/// Thread count: set_num_threads(n), else the FABSYNTH_NUM_THREADS environment variable, else
/// std::thread::hardware_concurrency(). Calls nested inside a parallel loop (in a worker or in the
/// calling thread's own share) run serially.
///
/// Workers are started once, on first use, and kept (they spin briefly after a loop, then sleep
/// on a condition variable), so a loop costs a queue push and a wake-up rather than thread
/// creation. Several host threads may call parallel_for at once: each call is a job in a queue;
/// the calling thread always works on its own job, and idle workers help the oldest job that
/// still has unclaimed chunks, at most `threads - 1` of them per job.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <exception>
#include <limits>
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

/// One parallel_for call: chunks [0, chunks) handed out in increasing order.
struct parallel_job {
    std::size_t chunks = 0;
    void (*run_chunk)(const void* ctx, std::size_t chunk) = nullptr;  // type-erased loop body
    const void* ctx = nullptr;
    unsigned max_helpers = 0;                          // workers allowed besides the caller
    unsigned helpers = 0;                              // workers that joined (guarded by the pool mutex)
    std::atomic<std::size_t> next{0};                  // next chunk to claim
    std::atomic<std::size_t> lowest_failed{std::numeric_limits<std::size_t>::max()};
    unsigned active = 0;                               // workers inside work() (guarded by the pool mutex)
    std::mutex error_mutex;
    std::exception_ptr error;

    /// Claims and runs chunks until none is left (or all remaining ones lie above a failure).
    void work() noexcept {
        const bool was_inside = inside_worker();
        inside_worker() = true;
        for (;;) {
            const std::size_t c = next.fetch_add(1, std::memory_order_relaxed);
            if (c >= chunks) break;
            if (c > lowest_failed.load(std::memory_order_relaxed)) continue;  // cannot be the reported error
            try {
                run_chunk(ctx, c);
            } catch (...) {
                std::lock_guard lock(error_mutex);
                if (c < lowest_failed.load(std::memory_order_relaxed)) {
                    lowest_failed.store(c, std::memory_order_relaxed);
                    error = std::current_exception();
                }
            }
        }
        inside_worker() = was_inside;
    }
    [[nodiscard]] bool has_unclaimed() const noexcept { return next.load(std::memory_order_relaxed) < chunks; }
};

/// The process-wide pool (see the file comment). Grows to the largest thread count requested.
class thread_pool {
public:
    static thread_pool& instance() {
        static thread_pool pool;
        return pool;
    }
    thread_pool(const thread_pool&) = delete;
    thread_pool& operator=(const thread_pool&) = delete;
    ~thread_pool() {
        {
            std::lock_guard lock(mutex_);
            stop_ = true;
            epoch_.fetch_add(1);
        }
        wake_.notify_all();
        workers_.clear();  // jthreads join
    }

    /// Runs job with the caller and up to job.max_helpers workers; returns when every chunk is done.
    void run(parallel_job& job) {
        {
            std::lock_guard lock(mutex_);
            while (workers_.size() < job.max_helpers) workers_.emplace_back([this] { worker_loop(); });
            queue_.push_back(&job);
            epoch_.fetch_add(1, std::memory_order_release);
        }
        if (sleepers_.load(std::memory_order_acquire) > 0) wake_.notify_all();
        job.work();
        // No worker can join once the job is out of the queue; wait for those inside it. Workers
        // leave under the mutex and signal the pool's own condition variable, so nothing touches
        // the job after the caller returns.
        std::unique_lock lock(mutex_);
        queue_.erase(std::find(queue_.begin(), queue_.end(), &job));
        done_.wait(lock, [&] { return job.active == 0; });
    }

private:
    thread_pool() = default;

    parallel_job* take() {
        for (parallel_job* j : queue_)
            if (j->helpers < j->max_helpers && j->has_unclaimed()) {
                ++j->helpers;
                ++j->active;
                return j;
            }
        return nullptr;
    }

    void worker_loop() {
        parallel_job* finished = nullptr;
        for (;;) {
            std::uint64_t seen;
            parallel_job* job;
            {
                std::lock_guard lock(mutex_);
                if (finished && --finished->active == 0) done_.notify_all();
                finished = nullptr;
                if (stop_) return;
                seen = epoch_.load(std::memory_order_relaxed);
                job = take();
            }
            if (job) {
                job->work();
                finished = job;
                continue;
            }
            // Idle: spin a little (loops often come in quick succession), then sleep. The spin
            // yields, so it does not hold a core that the calling thread needs.
            bool changed = false;
            for (int i = 0; i < spin_rounds && !changed; ++i) {
                changed = epoch_.load(std::memory_order_acquire) != seen;
                if (!changed) std::this_thread::yield();
            }
            if (changed) continue;
            std::unique_lock lock(mutex_);
            sleepers_.fetch_add(1, std::memory_order_acq_rel);
            wake_.wait(lock, [&] { return stop_ || epoch_.load(std::memory_order_relaxed) != seen; });
            sleepers_.fetch_sub(1, std::memory_order_acq_rel);
        }
    }

    static constexpr int spin_rounds = 2000;  // ~0.5-1 ms of yielding before a worker sleeps
    std::mutex mutex_;
    std::condition_variable wake_;  // workers: a job was queued (or stop)
    std::condition_variable done_;  // callers: a worker left a job
    std::deque<parallel_job*> queue_;
    std::atomic<std::uint64_t> epoch_{0};  // bumped on every new job
    std::atomic<unsigned> sleepers_{0};
    bool stop_ = false;
    std::vector<std::jthread> workers_;  // last member: joined first on destruction
};
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

    struct context {
        std::size_t begin, end, grain;
        F* f;
    } ctx{begin, end, grain, &f};
    detail::parallel_job job;
    job.chunks = chunks;
    job.ctx = &ctx;
    job.run_chunk = [](const void* p, std::size_t c) {
        const auto& x = *static_cast<const context*>(p);
        const std::size_t lo = x.begin + c * x.grain, hi = std::min(x.end, lo + x.grain);
        for (std::size_t i = lo; i < hi; ++i) (*x.f)(i);
    };
    job.max_helpers = threads - 1;
    if (threads <= 1) job.work();
    else detail::thread_pool::instance().run(job);
    if (job.error) std::rethrow_exception(job.error);
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
