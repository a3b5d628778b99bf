// A stage that streams: it reads its input from a FrameSource in bands or frames and hands each
// finished frame on, so the shot is never in memory. Filters that can work this way return one
// from Filter::stream_stage(); the others run on the whole shot in memory.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "pipeline/footprint.hpp"
#include "pipeline/frame_source.hpp"
#include "statfilter/params.hpp"
#include "statfilter/progress.hpp"

namespace statfilter {

// The renderer's passes beside the input (named input sequences the front ends give: in memory or
// files), each with the input's frames and size; null when not given. A stage reads them in bands or
// frames as it reads its input, so they are never in memory whole either.
struct GuideSources {
    const FrameSource* albedo = nullptr;
    const FrameSource* normal = nullptr;
    const FrameSource* vectors = nullptr;  // Cycles' Vector pass: X, Y, Z, W in its first four channels
};

// The image result (1 x H x W x 1, 0..1) in which a stage says where it followed the motion (the
// hybrid's aligned region) rather than modelling the whole shot: the trust blend's temporal probe
// counts there, and its fit pools over more frames where it is zero (TimeTrust::set_motion_path). A
// stage that knows it modelled the whole shot sets it all zero; one that does not say sets none.
inline constexpr const char* kMotionPathResult = "motion_path";

// Threads, the memory the stage may hold, progress and the renderer's passes, for one run.
struct StageContext {
    int threads = 1;
    double budget_bytes = 512.0 * 1024 * 1024;
    const Progress* progress = nullptr;
    GuideSources passes;
};

// Receives each finished frame (index, contiguous row/pixel/channel floats it may modify); called
// from worker threads, each frame once, in any order.
using FrameConsumer = std::function<void(int64_t frame, float* pixels)>;

class WindowedStage;

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
    // The stage as an analysis and frame windows, when it can run that way (else null).
    virtual const WindowedStage* windowed() const { return nullptr; }
};

// Where a plan's tasks of a windowed stage leave what the next phase reads: a directory each (made
// whole or not at all by the task), in the plan's work directory.
struct WindowedFiles {
    struct Chunk {
        int64_t begin = 0, end = 0;  // frames [begin, end)
        std::string dir;
    };
    std::string analysis;       // 1. the passes over the whole shot
    std::vector<Chunk> passes;  // 2. a pass frame by frame, in chunks of frames covering the shot
    std::string shot_pass;      // 3. what needs every frame's pass
};

// A stage whose frames, once its passes over the whole shot are made, each need only the frames
// t - h .. t + h around them (the hybrid's window). A plan runs it as four phases: the passes over
// the shot (one task), a pass frame by frame (chunks), what needs all of those (one task), then the
// frames (chunks), each chunk on its own, with the same numbers as the stage's run. Each phase
// writes into its own directory (existing, empty) and reads the earlier phases' (WindowedFiles).
class WindowedStage {
public:
    virtual ~WindowedStage() = default;
    // Frames each side a frame's window reads.
    virtual int64_t window_half() const = 0;
    // The least memory of a chunk of frames on one thread.
    virtual double frames_min_bytes(const Shape& shape) const = 0;
    // 1. Results: what the run reports of its analysis (its choice, the motion it measured).
    virtual void analyse_into(const FrameSource& source, const std::string& dir, const StageContext& context,
                              Results& results) const = 0;
    // 2. Frames [f0, f1) of the pass frame by frame.
    virtual void frame_pass_into(const FrameSource& source, const WindowedFiles& files, int64_t f0, int64_t f1,
                                 const std::string& dir, const StageContext& context, Results& results) const = 0;
    // 3.
    virtual void shot_pass_into(const FrameSource& source, const WindowedFiles& files, const std::string& dir,
                                const StageContext& context, Results& results) const = 0;
    // 4. Frames [f0, f1), each handed to consume once (any order, worker threads). Results: the
    // analysis' choice ("method", "reason") and what these frames report.
    virtual void frames_from(const FrameSource& source, const WindowedFiles& files, int64_t f0, int64_t f1,
                             const FrameConsumer& consume, const StageContext& context, Results& results) const = 0;
};

// The stage over a sequence in memory: the source is the sequence itself (no copy), the frames go
// to output. Every core; budget bounds the stage's working buffers. passes: the renderer's (sources
// of sequences in memory too, as the caller holds them).
void run_in_memory(StreamStage& stage, const Sequence& input, Sequence& output, const Progress& progress,
                   double budget_bytes, Results& results, const GuideSources& passes = {});

}  // namespace statfilter
