// The scheduler: runs a filter from a frame source to a frame sink within a memory budget on a
// number of threads. It owns the loop over frames, the threads, the memory check and progress; the
// filter's stages only say what they reach (footprint) and do their work.
#pragma once
#include <cstdint>
#include <string>

#include "statfilter/params.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"

namespace statfilter {

struct RunOptions {
    double budget_bytes = 0;  // 0 = the default share of physical memory (pipeline/memory_budget.hpp)
    int threads = 0;          // 0 = every core
    Progress progress;
};

// The memory a run holds, as the scheduler will run it (streamed or in memory), for the message of a
// refusal and for reports.
struct RunPlan {
    bool streamed = false;
    double bytes = 0;       // the least memory the run needs
    std::string reason;     // what runs, and how
};

// What a run sets aside of its memory budget before its stream stage gets the rest: each thread's
// frame for a prefilter or postfilter and its working set (three frames more with the trust blend),
// and, reading and writing files, each thread's decode and encode buffers. Filter::execute gives the
// stage the budget less this (and less a single-frame denoiser's share); a plan's window tasks give
// theirs the same, so its bands, and so its numbers, are the single run's.
double frame_reserve_bytes(const ParamSet& stages, const Shape& shape, int threads, bool files);

}  // namespace statfilter
