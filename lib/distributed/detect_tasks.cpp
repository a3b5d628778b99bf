// run_detect_task: one task of a detect plan (noise, tolerance, detect, masks). Each writes its files
// atomically (temporary + rename) and its report last; a rerun rewrites the same bytes.
#include <chrono>
#include <cstring>
#include <filesystem>

#include "distributed/detect_plan.hpp"
#include "distributed/task_common.hpp"
#include "distributed/tile_files.hpp"
#include "filters/detect_filter.hpp"
#include "pipeline/memory_budget.hpp"
#include "pipeline/library_threads.hpp"
#include "pipeline/parallel.hpp"
#include "statfilter/degree_preview.hpp"
#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/sequence_io.hpp"

namespace statfilter {
namespace {

namespace fs = std::filesystem;
constexpr char kNoiseMagic[8] = {'S', 'F', 'N', 'O', 'I', 'S', 'E', '1'};
constexpr char kToleranceMagic[8] = {'S', 'F', 'D', 'E', 'L', 'T', 'A', '1'};
constexpr char kBandMagic[8] = {'S', 'F', 'D', 'M', 'A', 'S', 'K', '1'};
constexpr int64_t kBandHeader = 8 + 7 * 8;  // magic, frames, rows, width, flagged, unexplained, degree sum, explained
constexpr char kScoreMagic[8] = {'S', 'F', 'D', 'S', 'C', 'O', 'R', '1'};
constexpr char kDegreeMagic[8] = {'S', 'F', 'D', 'D', 'E', 'G', 'R', '1'};
constexpr int64_t kRowsHeader = 8 + 3 * 8;  // magic, frames, rows, width; then float32 samples, frame by frame

struct Work {
    std::string dir;
    std::string noise(int64_t tile) const { return dir + "/noise-" + std::to_string(tile) + ".bin"; }
    std::string tolerance() const { return dir + "/tolerance.bin"; }
    std::string band(int64_t tile) const { return dir + "/mask-" + std::to_string(tile) + ".bin"; }
    std::string score(int64_t tile) const { return dir + "/score-" + std::to_string(tile) + ".f32"; }
    std::string degree(int64_t tile) const { return dir + "/degree-" + std::to_string(tile) + ".f32"; }
    std::string report(int64_t task) const { return dir + "/task-" + std::to_string(task) + ".json"; }
};

struct Run {
    const JsonValue& plan;
    const TaskContext& context;
    Work work;
    DetectOptions options;
    std::atomic<int64_t> pixels_read{0};
    int64_t bytes_read = 0, bytes_written = 0;
    Results results;
    std::vector<std::string> outputs;
};

void append(std::vector<char>& out, const void* p, size_t n) {
    out.insert(out.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n);
}

void check_magic(const std::string& path, const char* magic) {
    char m[8];
    read_file_at(path, 0, m, 8);
    if (std::memcmp(m, magic, 8) != 0) throw Error(Status::Io, "'" + path + "' is not the file a detect task writes");
}

// The band's rows [r0, r1) of every frame of one sequence.
std::shared_ptr<Sequence> read_band(Run& run, const FrameSource& source, int64_t r0, int64_t r1) {
    const Shape& s = source.shape();
    auto band = std::make_shared<Sequence>(Shape{s.frames, r1 - r0, s.width, s.channels});
    std::vector<float> rows(static_cast<size_t>((r1 - r0) * s.width * s.channels));
    for (int64_t f = 0; f < s.frames; ++f) {
        source.read_rows(f, r0, r1, rows.data());
        band->set_frame(f, rows.data());
    }
    run.pixels_read += s.frames * static_cast<int64_t>(rows.size() * sizeof(float));
    return band;
}

struct Band {
    std::shared_ptr<Sequence> denoised, noisy;
    DetectRows rows() const {
        return {*denoised, noisy.get(), r0, y0, y1, height};
    }
    int64_t r0 = 0, y0 = 0, y1 = 0, height = 0;
};

Band band_of(Run& run, const JsonValue& task) {
    Band b;
    const auto rows = range(task, "rows", "task"), read = range(task, "read_rows", "task");
    b.r0 = read.first, b.y0 = rows.first, b.y1 = rows.second, b.height = run.context.source->shape().height;
    b.denoised = read_band(run, *run.context.source, read.first, read.second);
    if (run.context.noisy) b.noisy = read_band(run, *run.context.noisy, read.first, read.second);
    return b;
}

void noise_task(Run& run, const JsonValue& task) {
    const Band b = band_of(run, task);
    const std::vector<double> ratios = detect_noise_ratios(b.rows(), run.options);
    std::vector<char> out;
    append(out, kNoiseMagic, 8);
    const auto count = static_cast<int64_t>(ratios.size());
    append(out, &count, 8);
    append(out, ratios.data(), ratios.size() * sizeof(double));
    const std::string path = run.work.noise(integer(task, "tile", "task"));
    write_file(path, out.data(), out.size());
    run.bytes_written += static_cast<int64_t>(out.size());
    run.outputs.push_back(path);
}

// Every band's ratios, read once each by its band number, in band order: the image's pixels in the
// single-process order (the median does not depend on it anyway).
void tolerance_task(Run& run, const JsonValue& task) {
    const int64_t tiles = integer(task, "tiles", "task");
    std::vector<double> ratios;
    for (int64_t t = 0; t < tiles; ++t) {
        const std::string path = run.work.noise(t);
        check_magic(path, kNoiseMagic);
        int64_t count = 0;
        read_file_at(path, 8, &count, 8);
        if (count < 0 || count > (int64_t(1) << 40)) throw Error(Status::Io, "'" + path + "' has a bad header");
        const size_t at = ratios.size();
        ratios.resize(at + static_cast<size_t>(count));
        read_file_at(path, 16, ratios.data() + at, static_cast<size_t>(count) * sizeof(double));
        run.bytes_read += 16 + count * 8;
    }
    double noise_ratio = 0;
    const double delta = detect_delta(run.options, std::move(ratios), &noise_ratio);
    std::vector<char> out;
    append(out, kToleranceMagic, 8);
    append(out, &delta, 8);
    append(out, &noise_ratio, 8);
    write_file(run.work.tolerance(), out.data(), out.size());
    run.bytes_written += static_cast<int64_t>(out.size());
    run.results.set("delta", delta);
    run.results.set("noise_ratio", noise_ratio);
    run.outputs.push_back(run.work.tolerance());
}

std::pair<double, double> read_tolerance(Run& run) {
    const std::string path = run.work.tolerance();
    if (!fs::exists(path))
        throw Error(Status::Io, "'" + path + "' is not there: run the tolerance task before the detect tasks");
    check_magic(path, kToleranceMagic);
    double v[2];
    read_file_at(path, 8, v, sizeof v);
    run.bytes_read += 24;
    return {v[0], v[1]};
}

// A band's rows of an image result (score: every frame; degree map: one), float32 after a header.
void write_rows(Run& run, const std::string& path, const char* magic, const Sequence& rows) {
    const Shape& s = rows.shape();
    std::vector<char> out;
    append(out, magic, 8);
    for (int64_t v : {s.frames, s.height, s.width}) append(out, &v, 8);
    const size_t header = out.size(), frame = static_cast<size_t>(s.pixels()) * sizeof(float);
    out.resize(header + static_cast<size_t>(s.frames) * frame);
    for (int64_t f = 0; f < s.frames; ++f) rows.get_frame(f, reinterpret_cast<float*>(out.data() + header + static_cast<size_t>(f) * frame));
    write_file(path, out.data(), out.size());
    run.bytes_written += static_cast<int64_t>(out.size());
    run.outputs.push_back(path);
}

// A band's image result file checked against the band's shape (once, before its frames are read).
void check_rows(const std::string& path, const char* magic, int64_t frames, int64_t rows, int64_t width) {
    check_magic(path, magic);
    int64_t h[3];
    read_file_at(path, 8, h, sizeof h);
    if (h[0] != frames || h[1] != rows || h[2] != width) throw Error(Status::Io, "'" + path + "' does not match the plan's band");
}

// Frame f's rows (rows x width floats) of a checked band's image result file.
void read_rows(Run& run, const std::string& path, int64_t rows, int64_t width, int64_t f, float* dst) {
    const size_t bytes = static_cast<size_t>(rows * width) * sizeof(float);
    read_file_at(path, kRowsHeader + f * static_cast<int64_t>(bytes), dst, bytes);
    run.bytes_read += static_cast<int64_t>(bytes);
}

bool wants_degree(const JsonValue& plan) {
    return !optional_text(plan, "degree_map").empty() || !optional_text(plan, "preview").empty();
}

void detect_task(Run& run, const JsonValue& task) {
    const double delta = read_tolerance(run).first;
    const Band b = band_of(run, task);
    const DetectBand found = detect_rows(b.rows(), run.options, delta, run.context.progress);
    const Shape& s = found.mask->shape();
    const int64_t tile = integer(task, "tile", "task");
    // The image results asked for, before the band's mask: a band file there means its rows are done.
    if (!optional_text(run.plan, "score").empty()) write_rows(run, run.work.score(tile), kScoreMagic, *found.score);
    if (wants_degree(run.plan)) write_rows(run, run.work.degree(tile), kDegreeMagic, *found.degree_map);
    std::vector<char> out;
    append(out, kBandMagic, 8);
    for (int64_t v : {s.frames, s.height, s.width, found.flagged, found.unexplained, found.degree_sum, found.explained})
        append(out, &v, 8);
    const size_t header = out.size();
    out.resize(header + static_cast<size_t>(s.frames * s.height * s.width));
    char* mask = out.data() + header;
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x) *mask++ = found.mask->at(f, y, x, 0) != 0.0f;
    const std::string path = run.work.band(tile);
    write_file(path, out.data(), out.size());
    run.bytes_written += static_cast<int64_t>(out.size());
    run.outputs.push_back(path);
}

// Frames of one pattern written under a staging directory beside it, each moved into place by one
// rename once every frame is written: a killed task leaves none of them under its final name.
class StagedFrames {
public:
    // The frames of an image result of the detect filter, one channel named `part`.
    StagedFrames(Run& run, int64_t index, const std::string& pattern, const char* part, bool as_float)
        : run_(run), pattern_(pattern), staging_(staging_dir(run.plan, index, pattern) + "-" + part),
          attributes_(std::make_unique<Sequence>(Shape{run.context.source->shape().frames, 1, 1, 1})) {
        clear_staging(staging_);
        attributes_->channel_names()[0] = part;
        attributes_->frame_numbers() = run.context.source->attributes().frame_numbers();
        // The sink reads the attributes as it writes: they live as long as it does.
        sink_ = run.context.open_sink(staged_pattern(staging_, pattern_), *attributes_, as_float);
    }
    void write(int64_t f, const float* pixels) { sink_->write_frame(f, pixels); }
    // Every frame written: moved into place.
    void finish() {
        sink_->commit();
        sink_.reset();
        run_.bytes_written += publish_staged(staging_, pattern_, attributes_->frame_numbers(), run_.outputs);
    }

private:
    Run& run_;
    std::string pattern_, staging_;
    std::unique_ptr<Sequence> attributes_;
    std::unique_ptr<FrameSink> sink_;
};

// The degree map (one frame, channel "degree") from the bands' rows, written as `statfilter detect
// --degree-map` writes it, and its preview as `--preview` does.
void write_degree_outputs(Run& run, const std::vector<std::pair<int64_t, int64_t>>& tiles) {
    const Shape& s = run.context.source->shape();
    Sequence map(Shape{1, s.height, s.width, 1});
    map.channel_names()[0] = "degree";
    map.frame_numbers() = {run.context.source->attributes().frame_numbers().front()};
    std::vector<float> rows;
    for (size_t k = 0; k < tiles.size(); ++k) {
        const auto [y0, y1] = tiles[k];
        rows.resize(static_cast<size_t>((y1 - y0) * s.width));
        const std::string path = run.work.degree(static_cast<int64_t>(k));
        check_rows(path, kDegreeMagic, 1, y1 - y0, s.width);
        read_rows(run, path, y1 - y0, s.width, 0, rows.data());
        for (int64_t y = y0; y < y1; ++y)
            for (int64_t x = 0; x < s.width; ++x) map.at(0, y, x, 0) = rows[static_cast<size_t>((y - y0) * s.width + x)];
    }
    WriteOptions as_float;
    as_float.half = false;
    auto write = [&](const Sequence& image, const std::string& path) {
        write_sequence(image, path, as_float);
        run.outputs.push_back(path);
        std::error_code ec;
        run.bytes_written += static_cast<int64_t>(fs::file_size(path, ec));
    };
    const std::string degree_map = optional_text(run.plan, "degree_map"), preview = optional_text(run.plan, "preview");
    if (!degree_map.empty()) write(map, degree_map);
    if (!preview.empty()) write(*degree_preview(map, run.options.degree), preview);
}

// Writes every mask (and score) frame once and the degree map, its preview and the crop windows,
// from the bands; the results are the detect filter's.
void masks_task(Run& run, const JsonValue& task, int64_t index) {
    const Shape& s = run.context.source->shape();
    const auto frames = range(task, "frames", "task");
    std::vector<std::pair<int64_t, int64_t>> tiles;
    for (const JsonValue& t : member(run.plan, "tasks", "the plan").array())
        if (t.find("phase")->string() == "detect") tiles.push_back(range(t, "rows", "task"));
    int64_t flagged = 0, unexplained = 0, degree_sum = 0, explained = 0;
    // Every band there before anything is staged (a task run before the detect tasks fails here).
    for (size_t k = 0; k < tiles.size(); ++k) {
        const std::string path = run.work.band(static_cast<int64_t>(k));
        if (!fs::exists(path))
            throw Error(Status::Io, "band " + std::to_string(k) + " ('" + path + "') is not there: run the detect tasks before the masks task");
        check_magic(path, kBandMagic);
        int64_t h[7];
        read_file_at(path, 8, h, sizeof h);
        if (h[0] != s.frames || h[1] != tiles[k].second - tiles[k].first || h[2] != s.width)
            throw Error(Status::Io, "'" + path + "' does not match the plan's band " + std::to_string(k));
        flagged += h[3], unexplained += h[4], degree_sum += h[5], explained += h[6];
        if (!optional_text(run.plan, "score").empty())
            check_rows(run.work.score(static_cast<int64_t>(k)), kScoreMagic, s.frames, tiles[k].second - tiles[k].first, s.width);
    }
    const auto [delta, noise_ratio] = read_tolerance(run);

    const std::string output = member(run.plan, "output", "the plan").string(), score = optional_text(run.plan, "score");
    const std::string crops_path = member(run.plan, "crops", "the plan").string();
    const CropOptions co = crop_options(run.context.filter->params());
    CropPlan crops;
    crops.width = s.width, crops.height = s.height, crops.frame_count = s.frames, crops.options = co;
    // The frames as the single-process detect writes its mask and score results.
    const Sequence& source = run.context.source->attributes();
    std::unique_ptr<StagedFrames> masks, scores;
    if (!output.empty()) masks = std::make_unique<StagedFrames>(run, index, output, "mask", false);
    if (!score.empty()) scores = std::make_unique<StagedFrames>(run, index, score, "score", true);
    Sequence frame(Shape{1, s.height, s.width, 1});
    std::vector<float> score_frame(scores ? static_cast<size_t>(s.pixels()) : 0);
    std::vector<char> rows;
    for (int64_t f = frames.first; f < frames.second; ++f) {
        run.context.progress.report(0.9 * static_cast<double>(f - frames.first) / static_cast<double>(frames.second - frames.first), "masks");
        for (size_t k = 0; k < tiles.size(); ++k) {
            const auto [y0, y1] = tiles[k];
            rows.resize(static_cast<size_t>((y1 - y0) * s.width));
            read_file_at(run.work.band(static_cast<int64_t>(k)), kBandHeader + f * static_cast<int64_t>(rows.size()), rows.data(), rows.size());
            run.bytes_read += static_cast<int64_t>(rows.size());
            for (int64_t y = y0; y < y1; ++y)
                for (int64_t x = 0; x < s.width; ++x) frame.at(0, y, x, 0) = rows[static_cast<size_t>((y - y0) * s.width + x)] ? 1.0f : 0.0f;
            if (scores)
                read_rows(run, run.work.score(static_cast<int64_t>(k)), y1 - y0, s.width, f, score_frame.data() + y0 * s.width);
        }
        frame.frame_numbers() = {source.frame_numbers()[static_cast<size_t>(f)]};
        for (FrameCrops& c : make_crop_plan(frame, co).frames) crops.frames.push_back(std::move(c));
        if (masks) masks->write(f, frame.data());
        if (scores) scores->write(f, score_frame.data());
    }
    if (masks) masks->finish();
    if (scores) scores->finish();
    if (wants_degree(run.plan)) write_degree_outputs(run, tiles);
    const std::string json = crop_plan_to_json(crops);
    if (!crops_path.empty()) {
        write_file(crops_path, json.data(), json.size());
        run.bytes_written += static_cast<int64_t>(json.size());
        run.outputs.push_back(crops_path);
    }
    // The detect filter's results (lib/filters/detect_filter.cpp), from the bands' counts.
    const double pixel_frames = static_cast<double>(s.frames * s.pixels());
    Results& r = run.results;
    r.set("source", std::string(detect_source_name(run.options.source)));
    r.set("delta", delta);
    r.set("noise_ratio", noise_ratio);
    r.set("flagged_pixel_frames", static_cast<double>(flagged));
    r.set("flagged_fraction", static_cast<double>(flagged) / pixel_frames);
    r.set("window_count", static_cast<double>(crops.window_count()));
    r.set("window_pixel_frames", static_cast<double>(crops.window_pixels()));
    r.set("window_fraction", static_cast<double>(crops.window_pixels()) / pixel_frames);
    r.set("frames_with_windows", static_cast<double>(crops.frames.size()));
    r.set("mean_degree", explained ? static_cast<double>(degree_sum) / static_cast<double>(explained) : 0.0);
    r.set("unexplained_fraction", static_cast<double>(unexplained) / static_cast<double>(s.pixels()));
}

}  // namespace

std::string run_detect_task(const JsonValue& plan, int64_t index, const TaskContext& context) {
    const int64_t count = plan_task_count(plan);
    if (index < 0 || index >= count)
        throw Error(Status::InvalidArgument, "task " + std::to_string(index) + " is not in the plan (tasks 0 to " +
                                                 std::to_string(count - 1) + ")");
    const JsonValue& task = plan.find("tasks")->array()[static_cast<size_t>(index)];
    const std::string phase = member(task, "phase", "task " + std::to_string(index)).string();
    const auto start = std::chrono::steady_clock::now();
    const double cpu0 = cpu_seconds();
    if (!context.filter || !context.source) throw Error(Status::Internal, "a detect task without its filter or input");
    Run run{plan, context, Work{plan_files_dir(plan)}, {}, {}, 0, 0, {}, {}};
    fs::create_directories(run.work.dir);
    const int threads = resolve_threads(context.threads > 0 ? context.threads : static_cast<int>(integer(plan, "threads", "the plan")));
    const ThreadLimit limit(threads);
    const LibraryThreads pools(threads);
    run.options = detect_options(context.filter->params(), context.noisy != nullptr);
    const Shape& s = context.source->shape();
    check_detect_options(s, context.noisy ? &context.noisy->shape() : nullptr, run.options);
    if (phase == "noise") noise_task(run, task);
    else if (phase == "tolerance") tolerance_task(run, task);
    else if (phase == "detect") detect_task(run, task);
    else if (phase == "masks") masks_task(run, task, index);
    else throw Error(Status::InvalidArgument, "task " + std::to_string(index) + " has an unknown phase '" + phase + "' for a detect plan");
    context.progress.report(1.0, "done");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return write_task_report(run.work.report(index), index, phase, seconds, cpu_seconds() - cpu0, threads,
                             run.pixels_read.load(), run.bytes_read, run.bytes_written, run.results, run.outputs);
}

}  // namespace statfilter
