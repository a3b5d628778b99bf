// A shot cut into tasks that any scheduler can run (Dask, a render farm's command lines), as data.
//
// Filters whose stage is the low-rank stage (pca, error-threshold, auto --quality fast) are cut into
// bands of full-width rows of every frame ("tiles"): statistics tasks write each tile's partial Gram,
// one reduction sums them in tile order and makes the basis (past 32 bands, "sum" tasks first sum runs
// of about sqrt(bands) partials and the reduction sums their sums), reconstruction tasks rebuild their rows
// (reading the halo their stage declares) into tile files, assembly tasks write each output frame
// once from the tiles (and an "images" task the rank map from the tiles' rows). A stage that is an analysis and frame windows (the hybrid's, and so
// --quality balanced) runs its analysis in one task ("window" plans) and its frames in chunks, each
// reading its window's reach of frames either side. Per-frame filters are cut into chunks of frames.
// Everything else runs as one task over the whole shot. Every task writes its outputs atomically (temporary + rename), so a rerun
// of a finished or killed task rewrites the same files; a task's report (task-N.json in the work
// directory) is written last and says it finished.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/frame_source.hpp"
#include "statfilter/filter.hpp"
#include "statfilter/json.hpp"

namespace statfilter {

struct PlanRequest {
    std::string input, output;    // patterns, absolute
    std::string work_dir;         // where partial statistics, tiles and task reports go (absolute)
    int64_t tiles = 0;            // bands of rows to cut the shot into; or
    int64_t tile_rows = 0;        // rows per band (0 and 0: one band per 256 rows)
    int64_t frames_per_task = 0;  // frames per assembly or per-frame task (0: 8)
    double budget_bytes = 0;      // each task's memory (0: the default share of the node's memory)
    int threads = 0;              // each task's threads (0: every core of its node)
    std::string front_end;        // the front end's own settings (JSON object text), kept verbatim
    int version = 1;              // the plan format version front_end needs (distributed/plan_json.hpp)
    // Image results to write (name, absolute path; paths checked by the front end): each by the task
    // that makes it, or refused when the plan's tasks make none of that name.
    std::vector<std::pair<std::string, std::string>> images;
    // The output is written as half with no colour conversion: the tiles' rows go through shared
    // storage as the half floats the frames will hold (the same rounding, half the bytes).
    bool half_tiles = false;
};

// Checks the shot against the filter and writes nothing but returns the plan (JSON text). Reads the
// headers of every frame, and for a tiled low-rank filter the frames its transform scale is measured
// on (once, for every tile).
std::string make_plan(const Filter& filter, const FrameSource& source, const PlanRequest& request);

// What a task needs from the front end that made the plan: the filter (configured), the input
// opened, and how to open the writer of output frames (pattern, the frames' attributes).
struct TaskContext {
    Filter* filter = nullptr;
    const FrameSource* source = nullptr;
    const FrameSource* noisy = nullptr;  // a detect plan's named input "noisy" (null without it)
    // as_float: float samples whatever the plan's write options say (a detect plan's score and maps).
    std::function<std::unique_ptr<FrameSink>(const std::string& pattern, const Sequence& attributes, bool as_float)> open_sink;
    std::vector<std::pair<std::string, std::string>> attributes;  // provenance for every frame written
    double budget_bytes = 0;  // 0: the plan's
    int threads = 0;          // 0: the plan's
    bool clamp_half = false;  // the plan's write options: finite values beyond half's range clamped
    Progress progress;
};

int64_t plan_task_count(const JsonValue& plan);
// Runs task `index`; returns its report (JSON text), also written to the work directory.
std::string run_plan_task(const JsonValue& plan, int64_t index, const TaskContext& context);

}  // namespace statfilter
