// Work items spread over threads, with progress and cancellation reported from the calling thread
// only (callbacks into Python or a host application never run on a worker).
#pragma once
#include <cstdint>
#include <functional>

#include "statfilter/progress.hpp"

namespace statfilter {

// The thread count to use: requested, or when requested <= 0 the calling thread's limit (ThreadLimit),
// else every core.
int resolve_threads(int requested);

// While it lives, work started from this thread that asks for "all" threads uses `threads` (a run's
// --threads reaches the numeric code that does not take a thread count of its own).
class ThreadLimit {
public:
    explicit ThreadLimit(int threads);
    ~ThreadLimit();
    ThreadLimit(const ThreadLimit&) = delete;
    ThreadLimit& operator=(const ThreadLimit&) = delete;

private:
    int previous_;
};

// Runs body(i) for i in [0, count) on up to `threads` threads (the caller's included). Items start in
// order; progress.report(done / count) runs on the calling thread between its items. The first
// exception (a failure, or cancellation from the progress callback) stops new items from starting and
// is rethrown here once the running ones finish.
void parallel_for(int64_t count, int threads, const std::function<void(int64_t)>& body, const ProgressSpan& progress);

// The same, with body(i, worker): worker in [0, worker_count(count, threads)) names the thread running
// item i, so a worker's buffers are made once and reused by its items (a frame-sized buffer made fresh
// per item costs more in page faults than many a stage's arithmetic). Worker 0 is the caller.
int worker_count(int64_t count, int threads);
void parallel_for_workers(int64_t count, int threads, const std::function<void(int64_t, int)>& body,
                          const ProgressSpan& progress);

}  // namespace statfilter
