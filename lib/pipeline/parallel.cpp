#include "pipeline/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace statfilter {

namespace {
thread_local int limit = 0;
}  // namespace

ThreadLimit::ThreadLimit(int threads) : previous_(limit) { limit = threads; }
ThreadLimit::~ThreadLimit() { limit = previous_; }

int resolve_threads(int requested) {
    if (requested > 0) return requested;
    if (limit > 0) return limit;
    const unsigned cores = std::thread::hardware_concurrency();
    return cores > 0 ? static_cast<int>(cores) : 1;
}

int worker_count(int64_t count, int threads) {
    return static_cast<int>(std::min<int64_t>(std::max(threads, 1), std::max<int64_t>(count, 1)));
}

void parallel_for(int64_t count, int threads, const std::function<void(int64_t)>& body, const ProgressSpan& progress) {
    parallel_for_workers(count, threads, [&](int64_t i, int) { body(i); }, progress);
}

void parallel_for_workers(int64_t count, int threads, const std::function<void(int64_t, int)>& body,
                          const ProgressSpan& progress) {
    std::atomic<int64_t> next{0}, done{0};
    std::atomic<bool> stop{false};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto record = [&](std::exception_ptr e) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = e;
        stop = true;
    };
    auto work = [&](int worker) {
        const bool reporter = worker == 0;
        while (!stop) {
            const int64_t i = next++;
            if (i >= count) break;
            try {
                body(i, worker);
                ++done;
                if (reporter) progress.report(static_cast<double>(done) / static_cast<double>(count));
            } catch (...) {
                record(std::current_exception());
            }
        }
    };
    const int extra = worker_count(count, threads) - 1;
    std::vector<std::thread> pool;
    pool.reserve(static_cast<size_t>(extra));
    for (int t = 0; t < extra; ++t) pool.emplace_back(work, t + 1);
    try {
        progress.report(0.0);
    } catch (...) {
        record(std::current_exception());
    }
    work(0);
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    progress.report(1.0);
}

}  // namespace statfilter
