// make_plan: what runs as which task, from the filter's stage and its footprint.
#include "distributed/tile_plan.hpp"

#include <algorithm>
#include <sstream>

#include "distributed/plan_json.hpp"
#include "filters/frame_stages.hpp"
#include "pipeline/frame_stage_pool.hpp"
#include "pipeline/low_rank_stage.hpp"
#include "pipeline/memory_budget.hpp"
#include "pipeline/stage.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

// The image results a plan's tasks make, by kind: the low-rank tiles their per-pixel ranks (the
// error threshold's), a window plan's analysis its alpha, a shot task every image its filter has.
std::vector<std::string> plan_images(const Filter& filter, const std::string& kind, const LowRankStage* low_rank) {
    if (kind == "tiles") return low_rank->options().per_pixel ? std::vector<std::string>{"rank_map"} : std::vector<std::string>();
    if (kind == "window") return {"alpha"};
    if (kind == "shot") return filter.image_results();
    return {};
}

// Each image the request asks for, checked as the task that makes it will write it (the name, the
// pattern, format and directory, never over an input or output frame: check_image_result_output),
// that the plan's tasks make it, and that no name or path is asked for twice.
void check_images(const Filter& filter, const FrameSource& source, const std::string& kind, const LowRankStage* low_rank,
                  const PlanRequest& request) {
    const std::vector<std::string> made = plan_images(filter, kind, low_rank);
    for (const auto& [name, path] : request.images) {
        check_image_result_output(filter, name, path, source.attributes().frame_numbers(), request.input, request.output);
        if (std::find(made.begin(), made.end(), name) == made.end()) {
            std::string list;
            for (const std::string& n : made) list += (list.empty() ? "" : ", ") + n;
            throw Error(Status::InvalidArgument, "a '" + kind + "' plan's tasks do not make the image result '" + name +
                                                     "' (they make: " + (list.empty() ? std::string("none") : list) + ")");
        }
    }
    for (size_t i = 0; i < request.images.size(); ++i)
        for (size_t j = i + 1; j < request.images.size(); ++j) {
            if (request.images[i].first == request.images[j].first)
                throw Error(Status::InvalidArgument, "the image result '" + request.images[i].first + "' is asked for twice");
            if (request.images[i].second == request.images[j].second)
                throw Error(Status::InvalidArgument, "the image results '" + request.images[i].first + "' and '" +
                                                         request.images[j].first + "' are both written to '" +
                                                         request.images[i].second + "'");
        }
}

std::string images_json(const PlanRequest& request) {
    std::string out = "[";
    for (size_t i = 0; i < request.images.size(); ++i)
        out += std::string(i ? ", " : "") + "{\"name\": " + json_quote(request.images[i].first) + ", \"path\": " +
               json_quote(request.images[i].second) + "}";
    return out + "]";
}

struct Task {
    std::string phase;
    std::string fields;  // the phase's own members, JSON
    std::vector<int64_t> after;
};

// Up to this many bands one task reduces them all (a partial Gram at 4K x 200 is read in 11 ms: 0.35 s
// for 32); beyond, a flat reduction of hundreds or thousands of bands would be the plan's longest task.
constexpr int64_t kReduceFanIn = 32;

// The reduction of the statistics tasks' partials: one task when they are few, else "sum" tasks over
// contiguous runs of them (in band order) and one reduction of those sums (in order). sqrt(bands)
// runs of sqrt(bands) partials make the longest chain of reads (a run, then the sums) the shortest:
// 2 sqrt(bands), 104 files for 2700 bands against 2700. Returns the reduction's index.
int64_t add_reduction(std::vector<Task>& tasks, const std::vector<int64_t>& statistics) {
    const auto tiles = static_cast<int64_t>(statistics.size());
    if (tiles <= kReduceFanIn) {
        tasks.push_back({"reduce", "\"tiles\": " + std::to_string(tiles), statistics});
        return static_cast<int64_t>(tasks.size()) - 1;
    }
    int64_t parts = 1;
    while (parts * parts < tiles) ++parts;
    std::vector<int64_t> sums;
    for (int64_t k = 0; k < parts; ++k) {
        const int64_t first = k * tiles / parts, last = (k + 1) * tiles / parts;
        sums.push_back(static_cast<int64_t>(tasks.size()));
        tasks.push_back({"sum", "\"tiles\": " + range_json(first, last),
                         std::vector<int64_t>(statistics.begin() + first, statistics.begin() + last)});
    }
    tasks.push_back({"reduce", "\"tiles\": " + std::to_string(tiles), sums});
    return static_cast<int64_t>(tasks.size()) - 1;
}

}  // namespace

std::string make_plan(const Filter& filter, const FrameSource& source, const PlanRequest& request) {
    filter.check();
    const Shape& s = source.shape();
    if (request.tiles < 0 || request.tile_rows < 0 || request.frames_per_task < 0)
        throw Error(Status::InvalidArgument, "tiles, tile rows and frames per task must be >= 0");
    if (request.tiles > 0 && request.tile_rows > 0)
        throw Error(Status::InvalidArgument, "give the number of tiles or the rows per tile, not both");
    const int64_t per_task = request.frames_per_task > 0 ? request.frames_per_task : 8;
    const ParamSet stages = filter.frame_stage_params();  // with what a preset runs around its stage
    const bool pre = has_frame_stage(stages, "prefilter"), post = runs_postfilter(stages);
    const auto stage = filter.stream_stage();
    const auto* low_rank = stage ? dynamic_cast<const LowRankStage*>(&stage->core()) : nullptr;
    // A postfilter runs on each frame a window task makes, unless it takes a share of the memory budget
    // (OIDN's tiles follow the share, which depends on the run around it).
    const bool post_per_frame = !post || !FrameStagePool("postfilter", stages).takes_memory_share();
    const WindowedStage* windowed = stage && !pre && post_per_frame ? stage->windowed() : nullptr;

    // What runs as which task; the images asked for checked against it before any frame is read.
    const std::string kind = low_rank && !pre && !post                                 ? "tiles"
                             : windowed                                               ? "window"
                             : stage && stage->footprint().reach == TemporalReach::Frame ? "frames"
                                                                                      : "shot";
    check_images(filter, source, kind, low_rank, request);

    std::string reason;
    std::vector<Task> tasks;
    std::ostringstream extra;
    if (kind == "tiles") {
        int64_t rows = request.tile_rows;
        if (request.tiles > 0) rows = (s.height + request.tiles - 1) / request.tiles;
        if (rows <= 0) rows = 256;
        rows = std::min(rows, s.height);
        const int64_t tiles = (s.height + rows - 1) / rows;
        const int64_t halo = low_rank->footprint().halo;
        // Every tile's tasks measure nothing of their own: the transform scale of the whole shot.
        const std::vector<double> scales = low_rank->transform_scales(source);
        // Each tile task holds its band (with halo) within the task's budget, or is refused now.
        const double budget = request.budget_bytes > 0 ? request.budget_bytes : static_cast<double>(default_memory_budget());
        const int threads = request.threads > 0 ? request.threads : 1;  // every core: the node's count is not known here
        const Shape tile_shape{s.frames, std::min(s.height, rows + 2 * halo), s.width, s.channels};
        check_memory_budget(low_rank->min_bytes(tile_shape, threads), budget,
                            "a tile task (" + std::to_string(tile_shape.height) + " rows of every frame)");
        reason = "the low-rank stage (" + describe(low_rank->footprint()) + ") as " + std::to_string(tiles) +
                 " bands of " + std::to_string(rows) + " rows: partial Grams summed in tile order" +
                 (tiles > kReduceFanIn ? " (in runs, then the runs' sums)" : "") + ", halo " +
                 std::to_string(halo) + " rows, rebuilt rows exchanged as " +
                 (request.half_tiles ? "the output's half floats" : "float32");
        extra << "  \"scales\": [";
        for (size_t i = 0; i < scales.size(); ++i) extra << (i ? ", " : "") << json_number(scales[i]);
        extra << "],\n  \"halo\": " << halo << ",\n  \"tile_rows\": " << rows << ",\n";
        extra << "  \"tile_samples\": " << (request.half_tiles ? "\"half\"" : "\"float32\"") << ",\n";
        std::vector<int64_t> statistics, reconstruct;
        for (int64_t t = 0; t < tiles; ++t) {
            const int64_t y0 = t * rows, y1 = std::min(s.height, y0 + rows);
            statistics.push_back(static_cast<int64_t>(tasks.size()));
            tasks.push_back({"statistics", "\"tile\": " + std::to_string(t) + ", \"rows\": " + range_json(y0, y1), {}});
        }
        const int64_t reduce = add_reduction(tasks, statistics);
        for (int64_t t = 0; t < tiles; ++t) {
            const int64_t y0 = t * rows, y1 = std::min(s.height, y0 + rows);
            reconstruct.push_back(static_cast<int64_t>(tasks.size()));
            tasks.push_back({"reconstruct",
                             "\"tile\": " + std::to_string(t) + ", \"rows\": " + range_json(y0, y1) + ", \"read_rows\": " +
                                 range_json(std::max<int64_t>(0, y0 - halo), std::min(s.height, y1 + halo)),
                             {reduce}});
        }
        for (int64_t f = 0; f < s.frames; f += per_task)
            tasks.push_back({"assemble", "\"frames\": " + range_json(f, std::min(s.frames, f + per_task)), reconstruct});
        // The rank map from every tile's rows, beside the assembly.
        if (!request.images.empty()) tasks.push_back({"images", "\"tiles\": " + std::to_string(tiles), reconstruct});
    } else if (kind == "window") {
        // The passes over the shot in one task; then chunks of frames, each reading its frames and the
        // window's reach either side from the input and from the analysis.
        const int64_t h = windowed->window_half();
        const double budget = request.budget_bytes > 0 ? request.budget_bytes : static_cast<double>(default_memory_budget());
        const int threads = request.threads > 0 ? request.threads : 1;
        check_memory_budget(stage->min_bytes(s, threads), budget, "the analysis task (" + std::to_string(s.frames) + " frames)");
        check_memory_budget(windowed->frames_min_bytes(s), budget, "a frame task");
        reason = "the stage (" + describe(stage->footprint()) + ") as an analysis task over the shot, first passes in chunks of " +
                 std::to_string(per_task) + " frames, the guides, then the frames in chunks of " + std::to_string(per_task) +
                 ", each reading " + std::to_string(h) + " frames either side" +
                 (post ? " and running the postfilter on its frames" : "");
        extra << "  \"window_half\": " << h << ",\n";
        tasks.push_back({"analysis", "\"frames\": " + range_json(0, s.frames), {}});
        std::vector<int64_t> passes;
        for (int64_t f = 0, chunk = 0; f < s.frames; f += per_task, ++chunk) {
            passes.push_back(static_cast<int64_t>(tasks.size()));
            tasks.push_back({"first_pass",
                             "\"chunk\": " + std::to_string(chunk) + ", \"frames\": " + range_json(f, std::min(s.frames, f + per_task)),
                             {0}});
        }
        const auto guides = static_cast<int64_t>(tasks.size());
        tasks.push_back({"guides", "\"frames\": " + range_json(0, s.frames), passes});
        for (int64_t f = 0; f < s.frames; f += per_task) {
            const int64_t f1 = std::min(s.frames, f + per_task);
            tasks.push_back({"window",
                             "\"frames\": " + range_json(f, f1) + ", \"read_frames\": " +
                                 range_json(std::max<int64_t>(0, f - h), std::min(s.frames, f1 + h)),
                             {guides}});
        }
    } else if (kind == "frames") {
        reason = "a per-frame filter (" + describe(stage->footprint()) + "): chunks of " + std::to_string(per_task) +
                 " whole frames";
        for (int64_t f = 0; f < s.frames; f += per_task)
            tasks.push_back({"frames", "\"frames\": " + range_json(f, std::min(s.frames, f + per_task)), {}});
    } else {
        reason = std::string("one task for the whole shot: ") +
                 (low_rank ? "a prefilter or postfilter around the low-rank stage is not cut into tiles yet"
                  : stage  ? "the filter's stage (" + describe(stage->footprint()) + ") is not cut into tiles yet"
                           : "the filter runs on the whole shot in memory");
        tasks.push_back({"shot", "\"frames\": " + range_json(0, s.frames), {}});
    }

    if (!request.images.empty()) extra << "  \"images\": " << images_json(request) << ",\n";

    std::ostringstream out;
    out << "{\n  \"format\": \"statfilter-plan\",\n  \"version\": " << request.version << ",\n";
    out << "  \"input\": " << json_quote(request.input) << ",\n  \"output\": " << json_quote(request.output) << ",\n";
    out << "  \"work\": " << json_quote(request.work_dir) << ",\n";
    out << "  \"front_end\": " << (request.front_end.empty() ? "{}" : request.front_end) << ",\n";
    out << "  \"memory\": " << json_number(request.budget_bytes) << ",\n  \"threads\": " << request.threads << ",\n";
    out << "  \"shape\": {\"frames\": " << s.frames << ", \"height\": " << s.height << ", \"width\": " << s.width
        << ", \"channels\": " << s.channels << "},\n";
    out << "  \"frame_numbers\": " << list_json(source.attributes().frame_numbers()) << ",\n";
    out << "  \"kind\": " << json_quote(kind) << ",\n  \"reason\": " << json_quote(reason) << ",\n" << extra.str();
    out << "  \"tasks\": [\n";
    for (size_t i = 0; i < tasks.size(); ++i)
        out << "    {\"index\": " << i << ", \"phase\": " << json_quote(tasks[i].phase) << ", " << tasks[i].fields
            << ", \"after\": " << list_json(tasks[i].after) << "}" << (i + 1 < tasks.size() ? ",\n" : "\n");
    out << "  ]\n}\n";
    return out.str();
}

int64_t plan_task_count(const JsonValue& plan) {
    const JsonValue* tasks = plan.find("tasks");
    if (!tasks || !tasks->is(JsonValue::Type::Array)) throw Error(Status::InvalidArgument, "the plan has no task list");
    return static_cast<int64_t>(tasks->array().size());
}

}  // namespace statfilter
