// The detect filter as a plan of tasks (run by run_plan_task, like the denoise plan).
//
// The detection is per pixel over time, except for two window averages with a bounded reach
// (detect_halo rows) and one global number: the automatic tolerance, the median of every pixel's
// relative noise. So it is cut into bands of full-width rows of every frame: "noise" tasks (one per
// band: its pixels' relative noise), one "tolerance" task (the median of them all, in band order:
// the tolerance), "detect" tasks (one per band, reading its halo rows: the band's mask rows of every
// frame and its counts, and its score and degree rows when asked for) and one "masks" task that writes
// each mask (and score) frame once, the degree map, its preview and the crop windows from the bands.
// Every output is the single-process detect's, bit for bit.
#pragma once
#include <cstdint>
#include <string>

#include "pipeline/frame_source.hpp"
#include "statfilter/filter.hpp"
#include "statfilter/json.hpp"
#include "distributed/tile_plan.hpp"

namespace statfilter {

struct DetectPlanRequest {
    std::string denoised, noisy;  // patterns, absolute (noisy "" without it)
    // What to write, absolute ("" = not written; at least one is given): the mask and score frame
    // patterns, the crop windows' JSON, the degree map (one frame) and its preview.
    std::string mask, crops, score, degree_map, preview;
    std::string work_dir;
    int64_t tiles = 0, tile_rows = 0;  // as PlanRequest's
    double budget_bytes = 0;
    int threads = 0;
    std::string front_end;
    int version = 1;              // the plan format version front_end needs (distributed/plan_json.hpp)
};

// Checks the shot against the detect filter (as the filter checks it, on the headers) and returns
// the plan's JSON text; writes nothing.
std::string make_detect_plan(const Filter& filter, const FrameSource& denoised, const FrameSource* noisy,
                             const DetectPlanRequest& request);

// A task of a plan of kind "detect"; its report (JSON), also written to the work directory.
std::string run_detect_task(const JsonValue& plan, int64_t index, const TaskContext& context);

}  // namespace statfilter
