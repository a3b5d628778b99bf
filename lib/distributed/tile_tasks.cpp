// run_plan_task: one task of a plan (statistics, reduce, reconstruct, assemble, images, frames, the
// window plan's phases, shot).
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <functional>
#include <filesystem>
#include <mutex>
#include <sstream>

#include "distributed/detect_plan.hpp"
#include "distributed/task_common.hpp"
#include "distributed/tile_files.hpp"
#include "distributed/tile_plan.hpp"
#include "filters/frame_stages.hpp"
#include "pipeline/frame_stage_pool.hpp"
#include "pipeline/guide_sources.hpp"
#include "pipeline/low_rank_stage.hpp"
#include "pipeline/memory_budget.hpp"
#include "pipeline/library_threads.hpp"
#include "pipeline/parallel.hpp"
#include "pipeline/scheduler.hpp"
#include "pipeline/stage.hpp"
#include "pipeline/window_source.hpp"
#include "statfilter/error.hpp"
#include "statfilter/false_colour.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/half_samples.hpp"
#include "statfilter/sequence_io.hpp"

namespace statfilter {
namespace {

namespace fs = std::filesystem;

// Paths in the work directory.
struct Work {
    std::string dir;
    std::string partial(int64_t tile) const { return dir + "/partial-" + std::to_string(tile) + ".bin"; }
    // Named by their run of partials [first, last): a plan made again with other bands in the same
    // directory never reads an old run as one of its own.
    std::string sum(int64_t first, int64_t last) const {
        return dir + "/sum-" + std::to_string(first) + "-" + std::to_string(last) + ".bin";
    }
    std::string reduced() const { return dir + "/reduced.bin"; }
    std::string tile(int64_t tile) const { return dir + "/tile-" + std::to_string(tile) + ".f32"; }
    std::string rank_rows(int64_t tile) const { return dir + "/rank-" + std::to_string(tile) + ".bin"; }
    std::string report(int64_t task) const { return dir + "/task-" + std::to_string(task) + ".json"; }
    std::string analysis() const { return dir + "/analysis"; }
    std::string first_pass(int64_t chunk) const { return dir + "/first-" + std::to_string(chunk); }
    std::string guides() const { return dir + "/guides"; }
};

struct Run {
    const JsonValue& plan;
    const TaskContext& context;
    Work work;
    StageContext stage;
    std::atomic<int64_t> pixels_read{0};
    int64_t bytes_read = 0, bytes_written = 0;
    Results results;
    std::vector<std::string> outputs;
};

// The tiles' rebuilt rows as the output's half floats (the plan says; a plan without the field: float32).
bool half_tiles(const JsonValue& plan) {
    const JsonValue* samples = plan.find("tile_samples");
    return samples && samples->is(JsonValue::Type::String) && samples->string() == "half";
}

// The plan's low-rank stage, carrying the plan's transform scales.
LowRankStage tile_stage(const Run& run, bool gram) {
    const auto stage = run.context.filter->stream_stage();
    const auto* low_rank = stage ? dynamic_cast<const LowRankStage*>(&stage->core()) : nullptr;
    if (!low_rank) throw Error(Status::InvalidArgument, "the plan's filter has no low-rank stage (was the plan made with other options?)");
    LowRankOptions options = low_rank->options();
    options.scales.clear();
    for (const JsonValue& v : member(run.plan, "scales", "the plan").array()) options.scales.push_back(v.number());
    options.gram = gram;
    return LowRankStage(options);
}

// The image results the plan writes (name, path), from its "images" list.
std::vector<std::pair<std::string, std::string>> asked_images(const JsonValue& plan) {
    std::vector<std::pair<std::string, std::string>> out;
    if (const JsonValue* images = plan.find("images"))
        for (const JsonValue& image : images->array())
            out.emplace_back(member(image, "name", "an image of the plan").string(), member(image, "path", "an image of the plan").string());
    return out;
}
bool asks_for(const JsonValue& plan, const std::string& name) {
    for (const auto& image : asked_images(plan))
        if (image.first == name) return true;
    return false;
}

// Writes each image result the plan asks for, as `statfilter denoise --save` writes it: a float
// EXR, or the false-colour picture of a .png path. Each file goes to a temporary and is renamed into
// place: a rerun rewrites it whole.
void write_images(Run& run, const Results& made) {
    WriteOptions as_float;
    as_float.half = false;
    for (const auto& [name, path] : asked_images(run.plan)) {
        std::shared_ptr<const Sequence> image;
        try {
            image = made.image(name);
        } catch (const Error&) {
            throw Error(Status::NotFound, "the plan asks for the image result '" + name + "', which the filter did not make in this run");
        }
        std::string extension = fs::path(path).extension().string();
        for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        const bool png = extension == ".png";
        write_sequence(png ? *false_colour_preview(*image) : *image, path, as_float);
        run.outputs.push_back(path);
        const FramePattern files(path);  // a frame per frame (beta): each file's bytes
        for (int64_t f = 0; f < image->shape().frames; ++f) {
            std::error_code ec;
            const auto bytes = fs::file_size(files.has_frame_token() ? files.format(image->frame_numbers()[static_cast<size_t>(f)]) : path, ec);
            if (!ec) run.bytes_written += static_cast<int64_t>(bytes);
            if (!files.has_frame_token()) break;
        }
    }
}

void annotate(const Run& run, Results& results) {
    const auto stage = run.context.filter->stream_stage();
    if (stage) stage->annotate(results);
}

void statistics_task(Run& run, const JsonValue& task) {
    const auto y0y1_range = range(task, "rows", "task");
    const int64_t y0 = y0y1_range.first, y1 = y0y1_range.second;
    const int64_t tile = integer(task, "tile", "task");
    CountingSource counted(*run.context.source, run.pixels_read);
    const auto window = row_window(counted, y0, y1);
    const LowRankStatistics stats = tile_stage(run, true).statistics(*window, run.stage);
    TileStatistics partial;
    partial.frames = window->shape().frames;
    partial.repaired = stats.repaired;
    for (const LowRankStatistics::Group& g : stats.groups) partial.groups.push_back({g.series, g.gram, {}});
    write_tile_statistics(run.work.partial(tile), partial);
    run.bytes_written += tile_statistics_bytes(partial);
    run.outputs.push_back(run.work.partial(tile));
}

// The statistics of the files, summed in the order given (the first one's frames and groups): each
// partial is read once, by its tile's name, so nothing is counted twice.
TileStatistics sum_statistics(Run& run, const std::vector<std::string>& files) {
    TileStatistics total;
    for (size_t t = 0; t < files.size(); ++t) {
        const TileStatistics part = read_tile_statistics(files[t]);
        run.bytes_read += tile_statistics_bytes(part);
        if (t == 0) {
            total = part;
            for (GroupStatistics& g : total.groups) std::fill(g.gram.begin(), g.gram.end(), 0.0), g.series = 0;
            total.repaired = 0;
        }
        if (part.frames != total.frames || part.groups.size() != total.groups.size())
            throw Error(Status::InvalidArgument, "'" + files[t] + "' does not match '" + files[0] + "' (frames, channel groups)");
        total.repaired += part.repaired;
        for (size_t g = 0; g < total.groups.size(); ++g) {
            total.groups[g].series += part.groups[g].series;
            for (size_t k = 0; k < total.groups[g].gram.size(); ++k) total.groups[g].gram[k] += part.groups[g].gram[k];
        }
    }
    return total;
}

// A run of the partials, tiles [first, last), summed in band order (a reduction of many bands).
void sum_task(Run& run, const JsonValue& task) {
    const auto [first, last] = range(task, "tiles", "task");
    if (!(0 <= first && first < last)) throw Error(Status::InvalidArgument, "a sum task's tiles are an empty range");
    std::vector<std::string> files;
    for (int64_t t = first; t < last; ++t) files.push_back(run.work.partial(t));
    const TileStatistics total = sum_statistics(run, files);
    const std::string out = run.work.sum(first, last);
    write_tile_statistics(out, total);
    run.bytes_written += tile_statistics_bytes(total);
    run.outputs.push_back(out);
}

// Every partial (or, for many bands, the runs' sums made by the sum tasks it waits for, which must
// cover the tiles once, in order) summed in order, and each channel group's basis from the total,
// made once for every reconstruction.
void reduce_task(Run& run, const JsonValue& task) {
    const int64_t tiles = integer(task, "tiles", "task");
    std::vector<const JsonValue*> sums;  // the sum tasks it waits for, if it waits for any
    for (const JsonValue& after : member(task, "after", "task").array()) {
        const JsonValue& waited = run.plan.find("tasks")->array().at(static_cast<size_t>(after.number()));
        if (member(waited, "phase", "task").string() == "sum") sums.push_back(&waited);
    }
    std::vector<std::string> files;
    if (sums.empty())
        for (int64_t t = 0; t < tiles; ++t) files.push_back(run.work.partial(t));
    int64_t covered = 0;
    for (const JsonValue* sum : sums) {
        const auto [first, last] = range(*sum, "tiles", "sum task");
        if (first != covered || last <= first)
            throw Error(Status::InvalidArgument, "the reduction's sum tasks do not cover the tiles in order (was the plan edited?)");
        files.push_back(run.work.sum(first, last));
        covered = last;
    }
    if (!sums.empty() && covered != tiles)
        throw Error(Status::InvalidArgument, "the reduction's sum tasks cover " + std::to_string(covered) + " of its " +
                                                 std::to_string(tiles) + " tiles (was the plan edited?)");
    TileStatistics total = sum_statistics(run, files);
    for (GroupStatistics& g : total.groups) g.basis = basis_from_gram(g.gram, total.frames, g.series);
    write_tile_statistics(run.work.reduced(), total);
    run.bytes_written += tile_statistics_bytes(total);
    run.results.set("nonfinite_repaired", static_cast<double>(total.repaired));
    run.outputs.push_back(run.work.reduced());
}

void reconstruct_task(Run& run, const JsonValue& task) {
    const auto y0y1_range = range(task, "rows", "task");
    const int64_t y0 = y0y1_range.first, y1 = y0y1_range.second;
    const auto r0r1_range = range(task, "read_rows", "task");
    const int64_t r0 = r0r1_range.first, r1 = r0r1_range.second;
    const int64_t tile = integer(task, "tile", "task");
    const TileStatistics reduced = read_tile_statistics(run.work.reduced());
    run.bytes_read += tile_statistics_bytes(reduced);
    CountingSource counted(*run.context.source, run.pixels_read);
    const auto window = row_window(counted, r0, r1);
    const Shape& s = window->shape();
    // The tile's own statistics pass finds the same fireflies as its statistics task and keeps the
    // band when it fits; the Gram and basis are the reduction's.
    const LowRankStage stage = tile_stage(run, false);
    LowRankStatistics stats = stage.statistics(*window, run.stage);
    if (stats.groups.size() != reduced.groups.size() || reduced.frames != s.frames)
        throw Error(Status::InvalidArgument, "'" + run.work.reduced() + "' does not match the shot's frames and channel groups");
    for (size_t g = 0; g < stats.groups.size(); ++g) {
        stats.groups[g].gram = reduced.groups[g].gram;
        stats.groups[g].series = reduced.groups[g].series;
        stats.groups[g].basis = std::make_shared<TemporalBasis>(reduced.groups[g].basis);
    }
    const int64_t row_floats = s.width * s.channels, rows = y1 - y0;
    const bool half = half_tiles(run.plan);
    const size_t count = static_cast<size_t>(rows * row_floats);
    const size_t frame_bytes = count * (half ? sizeof(uint16_t) : sizeof(float));
    AtomicFile out(run.work.tile(tile));
    Results own;
    stage.reconstruct(*window, std::move(stats), [&](int64_t t, float* pixels) {  // frames on several threads
        const float* own_rows = pixels + (y0 - r0) * row_floats;
        if (!half) return out.write_at(t * static_cast<int64_t>(frame_bytes), own_rows, frame_bytes);
        // What the writer does with the frame, here on the tile's rows: the same error, or the same halves.
        if (!run.context.clamp_half) check_half_range(own_rows, count, window->attributes(), t);
        std::vector<uint16_t> halves(count);
        to_half(own_rows, count, run.context.clamp_half, halves.data());
        out.write_at(t * static_cast<int64_t>(frame_bytes), halves.data(), frame_bytes);
    }, run.stage, own);
    out.commit();
    run.bytes_written += static_cast<int64_t>(frame_bytes) * s.frames;
    // The tile's rows of the rank map, for the images task (the window's halo rows left out).
    if (asks_for(run.plan, "rank_map")) {
        const Sequence& ranks = *own.image("rank_map");
        const std::vector<char> file = image_rows_file(ranks, y0 - r0, y1 - r0);
        write_file(run.work.rank_rows(tile), file.data(), file.size());
        run.bytes_written += static_cast<int64_t>(file.size());
        run.outputs.push_back(run.work.rank_rows(tile));
    }
    annotate(run, run.results);
    for (const std::string& name : own.names())
        if (name != "rank_map" && name != "nonfinite_repaired" && name != "bands") run.results.copy(own, name, name);
    run.outputs.push_back(run.work.tile(tile));
}

// Frames of a sink in the staging directory moved into their final names, one rename each.
void publish(Run& run, const std::string& staging, const Sequence& attributes) {
    run.bytes_written += publish_staged(staging, run.plan.find("output")->string(), attributes.frame_numbers(), run.outputs);
}

std::unique_ptr<FrameSink> staging_sink(Run& run, const std::string& staging, const Sequence& attributes) {
    clear_staging(staging);
    auto sink = run.context.open_sink(staged_pattern(staging, run.plan.find("output")->string()), attributes, false);
    for (const auto& [name, value] : run.context.attributes) sink->set_attribute(name, value);
    return sink;
}

void assemble_task(Run& run, const JsonValue& task, int64_t index) {
    const auto f0f1_range = range(task, "frames", "task");
    const int64_t f0 = f0f1_range.first, f1 = f0f1_range.second;
    const Shape& s = run.context.source->shape();
    const auto attributes = frame_range_attributes(run.context.source->attributes(), f0, f1);
    std::vector<std::pair<int64_t, int64_t>> tiles;  // rows of each tile
    for (const JsonValue& t : member(run.plan, "tasks", "the plan").array())
        if (t.find("phase")->string() == "reconstruct") tiles.push_back(range(t, "rows", "task"));
    // Every tile there before any frame is staged (a task run before the reconstructions fails here).
    for (size_t k = 0; k < tiles.size(); ++k)
        if (!fs::exists(run.work.tile(static_cast<int64_t>(k))))
            throw Error(Status::Io, "tile " + std::to_string(k) + " ('" + run.work.tile(static_cast<int64_t>(k)) +
                                        "') is not there: run the reconstruction tasks before the assembly");
    const std::string staging = staging_dir(run.plan, index);
    auto sink = staging_sink(run, staging, *attributes);
    // What the preset chose, as the single-process frames say.
    Results annotation;
    annotate(run, annotation);
    for (const char* name : {"method", "reason"})
        if (annotation.has(name)) sink->set_attribute(std::string("statfilter:") + name, annotation.get_string(name));
    const int64_t row_floats = s.width * s.channels;
    const bool half = half_tiles(run.plan);
    const int64_t sample_bytes = half ? sizeof(uint16_t) : sizeof(float);
    parallel_for(f1 - f0, run.stage.threads, [&](int64_t i) {
        const int64_t t = f0 + i;
        std::vector<float> frame(static_cast<size_t>(s.height * row_floats));
        std::vector<uint16_t> halves;
        for (size_t k = 0; k < tiles.size(); ++k) {
            const auto [y0, y1] = tiles[k];
            const auto count = static_cast<size_t>((y1 - y0) * row_floats);
            const size_t bytes = count * static_cast<size_t>(sample_bytes);
            const std::string path = run.work.tile(static_cast<int64_t>(k));
            float* rows = frame.data() + y0 * row_floats;
            if (!half) {
                read_file_at(path, t * static_cast<int64_t>(bytes), rows, bytes);
                continue;
            }
            halves.resize(count);
            read_file_at(path, t * static_cast<int64_t>(bytes), halves.data(), bytes);
            from_half(halves.data(), count, rows);  // exact: the writer rounds them to the same halves
        }
        sink->write_frame(i, frame.data());
    }, {run.context.progress, 0.0, 0.9, "assemble"});
    run.bytes_read += (f1 - f0) * s.height * row_floats * sample_bytes;
    sink->commit();
    sink.reset();
    publish(run, staging, *attributes);
}

// The image results from every tile's rows: the rank map, as the single run makes it.
void images_task(Run& run, const JsonValue& task) {
    const int64_t tiles = integer(task, "tiles", "task");
    const Shape& s = run.context.source->shape();
    std::shared_ptr<Sequence> map;
    int64_t y = 0;
    for (int64_t t = 0; t < tiles; ++t) {
        const std::string path = run.work.rank_rows(t);
        if (!fs::exists(path))
            throw Error(Status::Io, "tile " + std::to_string(t) + "'s rank rows ('" + path + "') are not there: run the reconstruction tasks first");
        const std::unique_ptr<Sequence> rows = read_image_rows_file(path);
        const Shape& r = rows->shape();
        if (!map) {
            map = std::make_shared<Sequence>(Shape{1, s.height, s.width, r.channels});
            map->channel_names() = rows->channel_names();
        }
        if (r.width != s.width || r.channels != map->shape().channels || y + r.height > s.height)
            throw Error(Status::Io, "'" + path + "' does not match the plan's tile " + std::to_string(t));
        for (int64_t i = 0; i < r.height; ++i, ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < r.channels; ++c) map->at(0, y, x, c) = rows->at(0, i, x, c);
        std::error_code ec;
        run.bytes_read += static_cast<int64_t>(fs::file_size(path, ec));
    }
    if (y != s.height) throw Error(Status::Io, "the tiles' rank rows cover " + std::to_string(y) + " of " + std::to_string(s.height) + " rows");
    Results made;
    made.set_image("rank_map", map);
    write_images(run, made);
}

RunOptions run_options(const Run& run) {
    RunOptions o;
    o.budget_bytes = run.stage.budget_bytes;
    o.threads = run.stage.threads;
    o.progress = run.context.progress;
    return o;
}

void frames_task(Run& run, const JsonValue& task, int64_t index) {
    const auto f0f1_range = range(task, "frames", "task");
    const int64_t f0 = f0f1_range.first, f1 = f0f1_range.second;
    CountingSource counted(*run.context.source, run.pixels_read);
    const auto frames = frame_range(counted, f0, f1);
    const std::string staging = staging_dir(run.plan, index);
    auto sink = staging_sink(run, staging, frames->attributes());
    run.context.filter->execute(*frames, *sink, run_options(run));
    sink.reset();
    run.results = run.context.filter->results();
    publish(run, staging, frames->attributes());
}

const WindowedStage& windowed_stage(const Run& run, std::unique_ptr<StreamStage>& holder) {
    holder = run.context.filter->stream_stage();
    const WindowedStage* windowed = holder ? holder->windowed() : nullptr;
    if (!windowed) throw Error(Status::InvalidArgument, "the plan's filter has no analysis and frame windows (was the plan made with other options?)");
    return *windowed;
}

// Where the phases of a window plan leave their files, from the plan's first-pass tasks.
WindowedFiles windowed_files(const Run& run) {
    WindowedFiles files;
    files.analysis = run.work.analysis();
    files.shot_pass = run.work.guides();
    for (const JsonValue& t : member(run.plan, "tasks", "the plan").array())
        if (t.find("phase")->string() == "first_pass") {
            const auto [f0, f1] = range(t, "frames", "task");
            files.passes.push_back({f0, f1, run.work.first_pass(integer(t, "chunk", "task"))});
        }
    return files;
}

// A window plan's stage gets the task's budget less what Filter::execute sets aside (the frame
// stages' and the files' buffers), as the single run's stage does: the same bands, the same numbers
// (at the single run's budget and threads). The stage reports a phase's progress within its whole run
// ([from, to] of it: the passes 0-0.35, the first passes to 0.5, the guides to 0.55, the window to 1);
// a task shows its own, 0 to 1.
StageContext phase_context(const Run& run, const Progress& own) {
    StageContext c = run.stage;
    const FrameSource& source = *run.context.source;
    c.budget_bytes -= frame_reserve_bytes(run.context.filter->frame_stage_params(), source.shape(), c.threads,
                                          !source.in_memory());
    c.progress = &own;
    return c;
}
Progress rescaled(const Progress& task, double from, double to) {
    return Progress([&task, from, to](double fraction, const char* stage) {
        task.report(std::clamp((fraction - from) / (to - from), 0.0, 1.0), stage);
        return true;
    });
}

// A task's frames [f0, f1), checked against the shot (a plan edited by hand).
std::pair<int64_t, int64_t> task_frames(const Run& run, const JsonValue& task) {
    const auto [f0, f1] = range(task, "frames", "task");
    const int64_t F = run.context.source->shape().frames;
    if (!(0 <= f0 && f0 < f1 && f1 <= F))
        throw Error(Status::InvalidArgument, "the task's frames [" + std::to_string(f0) + ", " + std::to_string(f1) +
                                                 ") are not within the shot's " + std::to_string(F));
    return {f0, f1};
}

// Fails before the task writes anything when a phase before it has not left its directory.
void require(const std::string& dir, const std::string& what) {
    if (!fs::is_directory(dir)) throw Error(Status::Io, "'" + dir + "' is not there: run the " + what + " first");
}

// The stage's passes over the whole shot (work/analysis, made whole or not at all).
void analysis_task(Run& run) {
    std::unique_ptr<StreamStage> holder;
    const WindowedStage& stage = windowed_stage(run, holder);
    CountingSource counted(*run.context.source, run.pixels_read);
    AtomicDirectory dir(run.work.analysis());
    const Progress progress = rescaled(run.context.progress, 0.0, 0.35);
    stage.analyse_into(counted, dir.temporary(), phase_context(run, progress), run.results);
    run.bytes_written += dir.commit();
    run.outputs.push_back(run.work.analysis());
    write_images(run, run.results);
}

// The first passes of frames [f0, f1): reads those frames of the input and of I_T.
void first_pass_task(Run& run, const JsonValue& task) {
    const auto [f0, f1] = task_frames(run, task);
    const int64_t chunk = integer(task, "chunk", "task");
    std::unique_ptr<StreamStage> holder;
    const WindowedStage& stage = windowed_stage(run, holder);
    require(run.work.analysis(), "analysis task");
    CountingSource counted(*run.context.source, run.pixels_read);
    AtomicDirectory dir(run.work.first_pass(chunk));
    const Progress progress = rescaled(run.context.progress, 0.35, 0.5);
    stage.frame_pass_into(counted, windowed_files(run), f0, f1, dir.temporary(), phase_context(run, progress), run.results);
    const Shape& s = counted.shape();
    run.bytes_read += (f1 - f0) * s.pixels() * s.channels * static_cast<int64_t>(sizeof(float));  // I_T's frames
    run.bytes_written += dir.commit();
    run.outputs.push_back(run.work.first_pass(chunk));
}

// What needs every frame's first pass: the flow guides and their scale.
void guides_task(Run& run) {
    std::unique_ptr<StreamStage> holder;
    const WindowedStage& stage = windowed_stage(run, holder);
    const WindowedFiles files = windowed_files(run);
    require(files.analysis, "analysis task");
    for (const WindowedFiles::Chunk& c : files.passes) require(c.dir, "first-pass tasks");
    CountingSource counted(*run.context.source, run.pixels_read);
    AtomicDirectory dir(run.work.guides());
    const Progress progress = rescaled(run.context.progress, 0.5, 0.55);
    stage.shot_pass_into(counted, files, dir.temporary(), phase_context(run, progress), run.results);
    const Shape& s = counted.shape();
    if (fs::exists(dir.temporary() + "/guides.f32"))  // the first passes read, twice over the guides
        run.bytes_read += s.frames * s.pixels() * s.channels * static_cast<int64_t>(sizeof(float)) * 2;
    run.bytes_written += dir.commit();
    run.outputs.push_back(run.work.guides());
}

// Frames [f0, f1) from the analysis, reading frames f0 - h .. f1 - 1 + h of the input and of the
// guides; each output frame staged and moved into place.
void window_task(Run& run, const JsonValue& task, int64_t index) {
    const auto frames = task_frames(run, task);  // named: the frame consumer below captures f0
    const int64_t f0 = frames.first, f1 = frames.second;
    std::unique_ptr<StreamStage> holder;
    const WindowedStage& stage = windowed_stage(run, holder);
    // The phases before it there before any frame is staged (run before them, it leaves nothing).
    const WindowedFiles files = windowed_files(run);
    require(files.analysis, "analysis task");
    for (const WindowedFiles::Chunk& c : files.passes) require(c.dir, "first-pass tasks");
    require(files.shot_pass, "guides task");
    CountingSource counted(*run.context.source, run.pixels_read);
    const auto attributes = frame_range_attributes(run.context.source->attributes(), f0, f1);
    const std::string staging = staging_dir(run.plan, index);
    auto sink = staging_sink(run, staging, *attributes);
    const Shape& s = counted.shape();
    const int64_t frame_bytes = s.pixels() * s.channels * static_cast<int64_t>(sizeof(float));
    // The postfilter on each frame, as Filter::execute runs it (the plan has one only when it takes no
    // share of the memory budget).
    const ParamSet stages = run.context.filter->frame_stage_params();
    std::unique_ptr<FrameStagePool> post;
    if (runs_postfilter(stages)) post = std::make_unique<FrameStagePool>("postfilter", stages);
    std::once_flag provenance;
    const Progress progress = rescaled(run.context.progress, 0.55, 1.0);
    stage.frames_from(counted, files, f0, f1, [&](int64_t t, float* pixels) {
        // What the preset chose (the analysis said), as the single-process frames say.
        std::call_once(provenance, [&] {
            for (const char* name : {"method", "reason"})
                if (run.results.has(name)) sink->set_attribute(std::string("statfilter:") + name, run.results.get_string(name));
        });
        if (post) post->apply(t, pixels, s, counted.attributes());
        sink->write_frame(t - f0, pixels);
    }, phase_context(run, progress), run.results);
    if (post) post->add_results(run.results);
    sink->commit();
    sink.reset();
    // The analysis' frames read: each frame's I_T (a still scene's frames), and with motion its first
    // pass and the guides of its window.
    const auto [r0, r1] = range(task, "read_frames", "task");
    const bool still = !fs::exists(files.shot_pass + "/guides.f32");
    run.bytes_read += ((f1 - f0) + (still ? 0 : (f1 - f0) + (r1 - r0))) * frame_bytes;
    publish(run, staging, *attributes);
}

void shot_task(Run& run) {
    CountingSource counted(*run.context.source, run.pixels_read);
    auto sink = run.context.open_sink(run.plan.find("output")->string(), counted.attributes(), false);
    for (const auto& [name, value] : run.context.attributes) sink->set_attribute(name, value);
    run.context.filter->execute(counted, *sink, run_options(run));
    run.results = run.context.filter->results();
    run.outputs.push_back(run.plan.find("output")->string());
    write_images(run, run.results);
}

}  // namespace

std::string run_plan_task(const JsonValue& plan, int64_t index, const TaskContext& context) {
    if (const JsonValue* kind = plan.find("kind"); kind && kind->is(JsonValue::Type::String) && kind->string() == "detect")
        return run_detect_task(plan, index, context);
    const int64_t count = plan_task_count(plan);
    if (index < 0 || index >= count)
        throw Error(Status::InvalidArgument, "task " + std::to_string(index) + " is not in the plan (tasks 0 to " +
                                                 std::to_string(count - 1) + ")");
    const JsonValue& task = plan.find("tasks")->array()[static_cast<size_t>(index)];
    const std::string phase = member(task, "phase", "task " + std::to_string(index)).string();
    const auto start = std::chrono::steady_clock::now();
    const double cpu0 = cpu_seconds();
    Run run{plan, context, Work{plan_files_dir(plan)}, {}, {}, 0, 0, {}, {}};
    fs::create_directories(run.work.dir);
    const int threads = resolve_threads(context.threads > 0 ? context.threads : static_cast<int>(integer(plan, "threads", "the plan")));
    const ThreadLimit limit(threads);
    const LibraryThreads pools(threads);
    const double plan_budget = member(plan, "memory", "the plan").number();
    run.stage.threads = threads;
    run.stage.budget_bytes = context.budget_bytes > 0 ? context.budget_bytes
                             : plan_budget > 0       ? plan_budget
                                                     : static_cast<double>(default_memory_budget());
    run.stage.progress = &context.progress;
    // The renderer's passes the plan's filter names, opened and checked before any work by the
    // window plan's tasks (the analysis reads them in bands, the window tasks each frame's); a shot
    // task's run opens its own, the other phases read none.
    const bool reads_passes = phase == "analysis" || phase == "first_pass" || phase == "guides" || phase == "window";
    const OpenGuides guides = reads_passes ? open_guide_sources(*context.filter, *context.source) : OpenGuides();
    run.stage.passes = guides.view;
    if (phase == "statistics") statistics_task(run, task);
    else if (phase == "sum") sum_task(run, task);
    else if (phase == "reduce") reduce_task(run, task);
    else if (phase == "reconstruct") reconstruct_task(run, task);
    else if (phase == "assemble") assemble_task(run, task, index);
    else if (phase == "images") images_task(run, task);
    else if (phase == "frames") frames_task(run, task, index);
    else if (phase == "analysis") analysis_task(run);
    else if (phase == "first_pass") first_pass_task(run, task);
    else if (phase == "guides") guides_task(run);
    else if (phase == "window") window_task(run, task, index);
    else if (phase == "shot") shot_task(run);
    else throw Error(Status::InvalidArgument, "task " + std::to_string(index) + " has an unknown phase '" + phase + "'");
    context.progress.report(1.0, "done");

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return write_task_report(run.work.report(index), index, phase, seconds, cpu_seconds() - cpu0, threads,
                             run.pixels_read.load(), run.bytes_read, run.bytes_written, run.results, run.outputs);
}

}  // namespace statfilter
