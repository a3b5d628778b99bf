// A stage that streams: it reads its input from a FrameSource in bands or frames and hands each
// finished frame on, so the shot is never in memory. Filters that can work this way return one
// from Filter::stream_stage(); the others run on the whole shot in memory.
#pragma once
#include <functional>

#include "pipeline/footprint.hpp"
#include "pipeline/frame_source.hpp"
#include "statfilter/params.hpp"
#include "statfilter/progress.hpp"

namespace statfilter {

// Threads, the memory the stage may hold, and progress, for one run.
struct StageContext {
    int threads = 1;
    double budget_bytes = 512.0 * 1024 * 1024;
    const Progress* progress = nullptr;
};

// Receives each finished frame (index, contiguous row/pixel/channel floats it may modify); called
// from worker threads, each frame once, in any order.
using FrameConsumer = std::function<void(int64_t frame, float* pixels)>;

class StreamStage {
public:
    virtual ~StreamStage() = default;
    virtual Footprint footprint() const = 0;
    // The least memory the stage can run in for this shape (its smallest band), before the data is
    // seen; a stage whose need grows with what it finds (an automatic rank) checks again then.
    virtual double min_bytes(const Shape& shape, int threads) const = 0;
    virtual void run(const FrameSource& source, const FrameConsumer& consume, const StageContext& context,
                     Results& results) = 0;
    // A wrapper's inner stage (a preset's annotated stage), for a plan of tile tasks that runs the
    // inner stage's passes itself; else this stage.
    virtual const StreamStage& core() const { return *this; }
    // What a wrapper reports before its inner stage runs (the preset's choice and reason).
    virtual void annotate(Results& results) const { (void)results; }
};

// The stage over a sequence in memory: the source is the sequence itself (no copy), the frames go
// to output. Every core; budget bounds the stage's working buffers.
void run_in_memory(StreamStage& stage, const Sequence& input, Sequence& output, const Progress& progress,
                   double budget_bytes, Results& results);

}  // namespace statfilter
