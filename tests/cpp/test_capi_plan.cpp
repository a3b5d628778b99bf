// A run as a plan of tasks through the C ABI (sf_plan_*): the tasks run one after another give the
// output of sf_filter_run; bad arguments are refused before anything is written. The same for the
// detect plan (sf_plan_write_detect) against sf_filter_execute of the detect filter.
#include <statfilter/statfilter.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include "capi_util.hpp"

using namespace statfilter_test;

namespace {

// Noisy frames of a smooth image, RGB, frames 1..F, written as float EXRs.
std::string write_shot(const TempDir& dir, int64_t frames = 8, int64_t height = 12) {
    std::mt19937 rng(7);
    std::normal_distribution<float> noise(0.0f, 0.2f);
    Seq seq = filled_sequence(shape_of(frames, height, 10, 3), [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        return 1.0f + 0.1f * static_cast<float>(c) + 0.02f * static_cast<float>(x + y) + 0.01f * static_cast<float>(f) +
               noise(rng) * noise(rng);
    });
    const char* names[] = {"R", "G", "B"};
    for (int64_t c = 0; c < 3; ++c) EXPECT_SF_OK(sf_sequence_set_channel_name(seq.get(), c, names[c]));
    for (int64_t f = 0; f < frames; ++f) EXPECT_SF_OK(sf_sequence_set_frame_number(seq.get(), f, f + 1));
    const std::string pattern = dir.file("in.####.exr");
    const sf_write_options o = write_options(SF_PIXEL_FLOAT);
    EXPECT_SF_OK(sf_sequence_write(seq.get(), pattern.c_str(), &o));
    return pattern;
}

Filt pca_filter() {
    sf_filter f = nullptr;
    EXPECT_SF_OK(sf_filter_create("pca", &f));
    EXPECT_SF_OK(sf_filter_set_string(f, "firefly_z", "0"));
    return Filt(f);
}

// A noisy shot of a smooth image (noisy.####.exr) and its "denoised" version (den.####.exr): the
// smooth image but for a block 60% too bright in frames 5-7 (what detect should flag), 12 frames.
struct DetectShot {
    std::string noisy, denoised;
};
DetectShot write_detect_shot(const TempDir& dir) {
    std::mt19937 rng(11);
    std::normal_distribution<float> noise(0.0f, 0.05f);
    auto clean = [](int64_t f, int64_t y, int64_t x, int64_t c) {
        return 0.6f + 0.1f * static_cast<float>(c) + 0.01f * static_cast<float>(x + y) + 0.002f * static_cast<float>(f);
    };
    const sf_shape shape = shape_of(12, 16, 14, 3);
    Seq noisy = filled_sequence(shape, [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        return clean(f, y, x, c) * (1.0f + noise(rng));
    });
    Seq den = filled_sequence(shape, [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        const bool block = f >= 5 && f <= 7 && y >= 4 && y < 11 && x >= 3 && x < 9;
        return clean(f, y, x, c) * (block ? 1.6f : 1.0f);
    });
    const char* names[] = {"R", "G", "B"};
    for (sf_sequence seq : {noisy.get(), den.get()}) {
        for (int64_t c = 0; c < 3; ++c) EXPECT_SF_OK(sf_sequence_set_channel_name(seq, c, names[c]));
        for (int64_t f = 0; f < shape.frames; ++f) EXPECT_SF_OK(sf_sequence_set_frame_number(seq, f, f + 1));
    }
    DetectShot shot{dir.file("noisy.####.exr"), dir.file("den.####.exr")};
    const sf_write_options o = write_options(SF_PIXEL_FLOAT);
    EXPECT_SF_OK(sf_sequence_write(noisy.get(), shot.noisy.c_str(), &o));
    EXPECT_SF_OK(sf_sequence_write(den.get(), shot.denoised.c_str(), &o));
    return shot;
}

Filt detect_filter() {
    sf_filter f = nullptr;
    EXPECT_SF_OK(sf_filter_create("detect", &f));
    return Filt(f);
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// A plan's string member (the test's paths need no unescaping).
std::string plan_string(const std::string& plan_path, const std::string& key) {
    const std::string text = read_text(plan_path), start = "\"" + key + "\": \"";
    const size_t at = text.find(start);
    if (at == std::string::npos) return "";
    const size_t begin = at + start.size();
    return text.substr(begin, text.find('"', begin) - begin);
}

// Where the plan's tasks keep their files: its work directory, then its run.
std::string plan_files(const std::string& plan_path, const std::string& name) {
    return plan_string(plan_path, "work") + "/" + plan_string(plan_path, "run") + "/" + name;
}

// The tasks of a plan's JSON text as the plan writer lays them out, one a line: index, phase and
// the "after" list (as written, e.g. "0, 1, 2"), and the rows it reads ("" when it has none).
struct PlanTask {
    int64_t index;
    std::string phase, after, read_rows;
};
std::vector<PlanTask> plan_tasks(const std::string& text) {
    static const std::regex line(R"re(\{"index": (\d+), "phase": "(\w+)"(.*)"after": \[([0-9, ]*)\]\})re");
    static const std::regex read_rows(R"re("read_rows": \[(\d+, \d+)\])re");
    std::vector<PlanTask> tasks;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), line); it != std::sregex_iterator(); ++it) {
        const std::string fields = (*it)[3];
        std::smatch rows;
        tasks.push_back({std::stoll((*it)[1]), (*it)[2], (*it)[4],
                         std::regex_search(fields, rows, read_rows) ? rows[1].str() : std::string()});
    }
    return tasks;
}

// pca (no firefly test) run on `in` as one process, into single.####.exr beside it, then planned in
// bands of `tile_rows` (frames_per_task > 0: the assembly's chunks) into out.####.exr: the plan's path.
std::string single_run_and_plan(const TempDir& dir, const std::string& in, int64_t tile_rows, int64_t frames_per_task) {
    Filt single = pca_filter();
    const sf_write_options wo = write_options(SF_PIXEL_FLOAT);
    EXPECT_SF_OK(sf_filter_run(single.get(), in.c_str(), nullptr, dir.file("single.####.exr").c_str(), &wo, nullptr));
    Filt filter = pca_filter();
    sf_plan_options po;
    sf_plan_options_init(&po);
    po.tile_rows = tile_rows;
    if (frames_per_task > 0) po.frames_per_task = frames_per_task;
    const std::string plan = dir.file("plan.json");
    EXPECT_SF_OK(sf_plan_write(filter.get(), in.c_str(), nullptr, dir.file("out.####.exr").c_str(), &wo, nullptr, &po,
                               plan.c_str()));
    return plan;
}

}  // namespace

TEST(Plan, TasksInOrderGiveTheSingleRunOutput) {
    TempDir dir;
    const std::string in = write_shot(dir);
    const std::string plan = single_run_and_plan(dir, in, 5, 3);  // bands of 5, 5 and 2 rows
    EXPECT_FALSE(fs::exists(dir.file("out.0001.exr")));
    int64_t count = 0;
    ASSERT_SF_OK(sf_plan_task_count(plan.c_str(), &count));
    EXPECT_EQ(count, 3 + 1 + 3 + 3);  // statistics, reduce, reconstruct, assemble
    for (int64_t t = 0; t < count; ++t) ASSERT_SF_OK(sf_plan_run_task(plan.c_str(), t, nullptr));
    EXPECT_EQ(samples_of(read_sequence(dir.file("out.####.exr")).get()),
              samples_of(read_sequence(dir.file("single.####.exr")).get()));
    EXPECT_TRUE(fs::exists(plan_files(plan, "task-9.json")));
}

// Past 32 bands the partials are summed in runs ("sum" tasks) and the reduction sums the runs' sums:
// the same Gram up to the order of the additions, so the single run's output within rounding.
TEST(Plan, ManyBandsAreReducedThroughSumsOfRuns) {
    TempDir dir;
    const std::string in = write_shot(dir, 8, 70);
    const std::string plan = single_run_and_plan(dir, in, 2, 0);  // 35 bands: 6 runs (sqrt(35) rounded up)
    const std::vector<PlanTask> tasks = plan_tasks(read_text(plan));
    std::vector<int64_t> sums;
    int64_t reduce = -1, covered = 0;
    for (const PlanTask& t : tasks) {
        if (t.phase == "sum") {
            sums.push_back(t.index);
            // Each run waits for exactly its statistics tasks, contiguous, in band order.
            std::istringstream after(t.after);
            int64_t first = -1, k = 0, n = 0;
            char comma;
            while (after >> k) {
                if (first < 0) first = k;
                EXPECT_EQ(k, first + n);
                ++n;
                after >> comma;
            }
            EXPECT_EQ(first, covered);
            covered += n;
        }
        if (t.phase == "reduce") reduce = t.index;
    }
    ASSERT_EQ(sums.size(), 6u);
    EXPECT_EQ(covered, 35);
    ASSERT_EQ(reduce, 41);
    EXPECT_EQ(tasks[static_cast<size_t>(reduce)].after, "35, 36, 37, 38, 39, 40");
    // The reduction before its sums fails, naming what is missing, and writes nothing.
    const std::string reduced = plan_files(plan, "reduced.bin");
    EXPECT_NE(sf_plan_run_task(plan.c_str(), reduce, nullptr), SF_OK);
    EXPECT_NE(std::string(sf_last_error()).find("sum-0-5.bin"), std::string::npos) << sf_last_error();
    EXPECT_FALSE(fs::exists(reduced));
    int64_t count = 0;
    ASSERT_SF_OK(sf_plan_task_count(plan.c_str(), &count));
    for (int64_t t = 0; t < count; ++t) ASSERT_SF_OK(sf_plan_run_task(plan.c_str(), t, nullptr));
    const std::vector<float> out = samples_of(read_sequence(dir.file("out.####.exr")).get());
    const std::vector<float> want = samples_of(read_sequence(dir.file("single.####.exr")).get());
    ASSERT_EQ(out.size(), want.size());
    for (size_t i = 0; i < out.size(); ++i) ASSERT_NEAR(out[i], want[i], 1e-5 * std::fabs(want[i]) + 1e-6) << i;
    // A sum run again rewrites the same bytes.
    const std::string run3 = plan_files(plan, "sum-17-23.bin"), before = read_text(run3);
    ASSERT_FALSE(before.empty());
    ASSERT_SF_OK(sf_plan_run_task(plan.c_str(), sums[3], nullptr));
    EXPECT_EQ(read_text(run3), before);
    // The plan made again in the same place with other bands (70, 9 runs): its reduction never takes the
    // old runs' sums for its own.
    Filt filter = pca_filter();
    sf_plan_options po;
    sf_plan_options_init(&po);
    po.tile_rows = 1;
    const sf_write_options wo = write_options(SF_PIXEL_FLOAT);
    ASSERT_SF_OK(sf_plan_write(filter.get(), in.c_str(), nullptr, dir.file("out.####.exr").c_str(), &wo, nullptr, &po,
                               plan.c_str()));
    EXPECT_NE(sf_plan_run_task(plan.c_str(), 70 + 9, nullptr), SF_OK);
    EXPECT_NE(std::string(sf_last_error()).find("sum-0-7.bin"), std::string::npos) << sf_last_error();
}

// A half output without a colour conversion: the tiles hold the halves the writer will write (half the
// bytes), with the writer's own rule for a value beyond half's range: the same error, or clamped.
TEST(Plan, HalfOutputTilesHoldTheWritersHalves) {
    TempDir dir;
    std::mt19937 rng(3);
    std::normal_distribution<float> noise(0.0f, 0.05f);
    Seq seq = filled_sequence(shape_of(6, 8, 6, 3), [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        const bool hot = y == 2 && x == 3;  // a pixel beyond half's range in every frame
        return (hot ? 2e5f : 0.3f + 0.1f * static_cast<float>(c) + 0.01f * static_cast<float>(x + y + f)) + noise(rng);
    });
    for (int64_t f = 0; f < 6; ++f) ASSERT_SF_OK(sf_sequence_set_frame_number(seq.get(), f, f + 1));
    const std::string in = dir.file("in.####.exr");
    const sf_write_options float_out = write_options(SF_PIXEL_FLOAT);
    ASSERT_SF_OK(sf_sequence_write(seq.get(), in.c_str(), &float_out));
    for (const int clamp : {1, 0}) {
        sf_write_options wo = write_options(SF_PIXEL_HALF);
        wo.half_overflow = clamp;
        const std::string tag = std::to_string(clamp);
        Filt single = pca_filter();
        const sf_status single_status =
            sf_filter_run(single.get(), in.c_str(), nullptr, dir.file("single" + tag + ".####.exr").c_str(), &wo, nullptr);
        Filt filter = pca_filter();
        sf_plan_options po;
        sf_plan_options_init(&po);
        po.tile_rows = 3;
        const std::string plan = dir.file("plan" + tag + ".json");
        ASSERT_SF_OK(sf_plan_write(filter.get(), in.c_str(), nullptr, dir.file("out" + tag + ".####.exr").c_str(), &wo,
                                   nullptr, &po, plan.c_str()));
        EXPECT_NE(read_text(plan).find("\"tile_samples\": \"half\""), std::string::npos);
        int64_t count = 0;
        ASSERT_SF_OK(sf_plan_task_count(plan.c_str(), &count));
        sf_status status = SF_OK;
        for (int64_t t = 0; t < count && status == SF_OK; ++t) status = sf_plan_run_task(plan.c_str(), t, nullptr);
        if (clamp) {
            ASSERT_SF_OK(single_status);
            ASSERT_SF_OK(status);
            EXPECT_EQ(samples_of(read_sequence(dir.file("out1.####.exr")).get()),
                      samples_of(read_sequence(dir.file("single1.####.exr")).get()));
            EXPECT_EQ(fs::file_size(plan_files(dir.file("plan1.json"), "tile-0.f32")), static_cast<uintmax_t>(6 * 3 * 6 * 3 * 2));
        } else {  // the writer's error, from the reconstruction that meets the value, and no frame written
            EXPECT_EQ(single_status, SF_ERROR_NUMERIC);
            EXPECT_EQ(status, SF_ERROR_NUMERIC);
            EXPECT_NE(std::string(sf_last_error()).find("beyond half float's range"), std::string::npos) << sf_last_error();
            EXPECT_FALSE(fs::exists(dir.file("out0.0001.exr")));
        }
    }
    // Float output: float32 tiles.
    Filt filter = pca_filter();
    ASSERT_SF_OK(sf_plan_write(filter.get(), in.c_str(), nullptr, dir.file("f.####.exr").c_str(), &float_out, nullptr,
                               nullptr, dir.file("float.json").c_str()));
    EXPECT_NE(read_text(dir.file("float.json")).find("\"tile_samples\": \"float32\""), std::string::npos);
}

TEST(Plan, BadArgumentsAreRefusedBeforeAnythingIsWritten) {
    TempDir dir;
    const std::string in = write_shot(dir, 4);
    Filt filter = pca_filter();
    const std::string out = dir.file("out.####.exr"), plan = dir.file("plan.json");
    sf_plan_options po;
    sf_plan_options_init(&po);
    po.tiles = 2;
    po.tile_rows = 3;
    expect_failure(sf_plan_write(filter.get(), in.c_str(), nullptr, out.c_str(), nullptr, nullptr, &po, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"not both"});
    sf_plan_options_init(&po);
    po.struct_size = 3;
    expect_failure(sf_plan_write(filter.get(), in.c_str(), nullptr, out.c_str(), nullptr, nullptr, &po, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"struct_size"});
    sf_run_options ro;
    sf_run_options_init(&ro);
    ro.overwrite = 1;
    expect_failure(sf_plan_write(filter.get(), in.c_str(), nullptr, in.c_str(), nullptr, &ro, nullptr, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"cannot overwrite its input"});
    expect_failure(sf_plan_write(filter.get(), in.c_str(), nullptr, dir.file("out.exr").c_str(), nullptr, nullptr, nullptr,
                                 plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"frame token"});
    expect_failure(sf_plan_write(filter.get(), in.c_str(), nullptr, out.c_str(), nullptr, nullptr, nullptr, nullptr),
                   SF_ERROR_INVALID_ARGUMENT, {"plan_path"});
    EXPECT_FALSE(fs::exists(plan));
    expect_failure(sf_plan_run_task(plan.c_str(), 0, nullptr), SF_ERROR_IO, {"plan.json"});
    ASSERT_SF_OK(sf_plan_write(filter.get(), in.c_str(), nullptr, out.c_str(), nullptr, nullptr, nullptr, plan.c_str()));
    expect_failure(sf_plan_run_task(plan.c_str(), 7, nullptr), SF_ERROR_INVALID_ARGUMENT, {"task 7 is not in the plan"});
    expect_failure(sf_plan_run_task(plan.c_str(), 1, nullptr), SF_ERROR_IO, {"partial-0.bin"});  // reduce before statistics
    int64_t count = 0;
    expect_failure(sf_plan_task_count(nullptr, &count), SF_ERROR_INVALID_ARGUMENT, {"plan_path"});
    write_text_file(dir.file("not-a-plan.json"), "{\"tasks\": []}");
    expect_failure(sf_plan_task_count(dir.file("not-a-plan.json").c_str(), &count), SF_ERROR_INVALID_ARGUMENT,
                   {"not a statfilter plan"});
    // A plan of a format newer than this release reads is refused, not run without what it added.
    std::string text = read_text(plan);
    EXPECT_NE(text.find("\"version\": 1,"), std::string::npos) << "a plan with no passes is of the first format";
    text.replace(text.find("\"version\": 1,"), 13, "\"version\": 9,");
    write_text_file(dir.file("newer.json"), text);
    expect_failure(sf_plan_task_count(dir.file("newer.json").c_str(), &count), SF_ERROR_UNSUPPORTED,
                   {"version 9", "newer"});
    expect_failure(sf_plan_run_task(dir.file("newer.json").c_str(), 0, nullptr), SF_ERROR_UNSUPPORTED, {"version 9"});
    write_text_file(dir.file("no-version.json"), "{\"format\": \"statfilter-plan\", \"tasks\": []}");
    expect_failure(sf_plan_task_count(dir.file("no-version.json").c_str(), &count), SF_ERROR_INVALID_ARGUMENT,
                   {"version"});
}

// A plan's tasks read every input from files: a pass in the caller's memory is refused (naming the
// call that gives it as files), a pass that does not match the input is refused before the plan is
// written, and one given as files reaches the plan's front end.
TEST(Plan, TheRenderersPassesReachThePlanAsFilesOnly) {
    TempDir dir;
    const std::string in = write_shot(dir, 4);
    sf_filter f = nullptr;
    ASSERT_SF_OK(sf_filter_create("hybrid", &f));
    Filt filter(f);
    // The output's directory is new: a refused plan does not leave it behind.
    const std::string out = dir.file("new/out.####.exr"), plan = dir.file("plan.json");
    Seq albedo = filled_sequence(shape_of(4, 12, 10, 3), [](int64_t, int64_t, int64_t x, int64_t) { return 0.1f * x; });
    ASSERT_SF_OK(sf_filter_set_input(filter.get(), "albedo", albedo.get()));
    expect_failure(sf_plan_write(filter.get(), in.c_str(), nullptr, out.c_str(), nullptr, nullptr, nullptr, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"'albedo' is in memory", "sf_filter_set_input_files"});
    const std::string missing = dir.file("missing.####.exr");
    ASSERT_SF_OK(sf_filter_set_input_files(filter.get(), "albedo", missing.c_str()));
    EXPECT_NE(sf_plan_write(filter.get(), in.c_str(), nullptr, out.c_str(), nullptr, nullptr, nullptr, plan.c_str()), SF_OK);
    EXPECT_FALSE(fs::exists(plan));
    EXPECT_FALSE(fs::exists(dir.file("new")));
    const std::string pass = dir.file("albedo.####.exr");
    const sf_write_options o = write_options(SF_PIXEL_FLOAT);
    for (int64_t i = 0; i < 4; ++i) ASSERT_SF_OK(sf_sequence_set_frame_number(albedo.get(), i, i + 1));
    ASSERT_SF_OK(sf_sequence_write(albedo.get(), pass.c_str(), &o));
    ASSERT_SF_OK(sf_filter_set_input_files(filter.get(), "albedo", pass.c_str()));
    ASSERT_SF_OK(sf_plan_write(filter.get(), in.c_str(), nullptr, out.c_str(), nullptr, nullptr, nullptr, plan.c_str()));
    const std::string text = read_text(plan);
    EXPECT_NE(text.find("\"inputs\": {\"albedo\": "), std::string::npos) << text.substr(0, 600);
    EXPECT_NE(text.find("albedo.####.exr"), std::string::npos);
    // A worker that knows no "inputs" would run without the pass: the plan says it needs a newer one.
    EXPECT_NE(text.find("\"version\": 2,"), std::string::npos) << text.substr(0, 200);
}

// plan->images: error-threshold's rank map written by the plan's images task from the bands' rows,
// the values sf_filter_run's result holds; a caller built before the field (a smaller struct_size)
// still gets its plan; bad image lists are refused before the plan is written.
TEST(Plan, ImageResultsAreTheSingleRunsAndBadOnesAreRefused) {
    TempDir dir;
    const std::string in = write_shot(dir);
    const auto error_threshold = [] {
        sf_filter f = nullptr;
        EXPECT_SF_OK(sf_filter_create("error-threshold", &f));
        EXPECT_SF_OK(sf_filter_set_string(f, "firefly_z", "0"));
        EXPECT_SF_OK(sf_filter_set_string(f, "window", "3"));
        return Filt(f);
    };
    Filt single = error_threshold();
    const sf_write_options wo = write_options(SF_PIXEL_FLOAT);
    ASSERT_SF_OK(sf_filter_run(single.get(), in.c_str(), nullptr, dir.file("single.####.exr").c_str(), &wo, nullptr));
    sf_sequence ranks = nullptr;
    ASSERT_SF_OK(sf_filter_result_sequence(single.get(), "rank_map", &ranks));
    Seq single_ranks(ranks);

    Filt filter = error_threshold();
    const std::string out = dir.file("out.####.exr"), plan = dir.file("plan.json"), path = dir.file("maps/ranks.exr");
    sf_image_output images[] = {{"rank_map", path.c_str()}};
    sf_plan_options po;
    sf_plan_options_init(&po);
    po.tile_rows = 5;  // bands of 5, 5 and 2 rows; the pooling window reaches 1 row into the next
    po.images = images;
    po.image_count = 1;
    ASSERT_SF_OK(sf_plan_write(filter.get(), in.c_str(), nullptr, out.c_str(), &wo, nullptr, &po, plan.c_str()));
    EXPECT_FALSE(fs::exists(path));
    const std::vector<PlanTask> tasks = plan_tasks(read_text(plan));
    ASSERT_FALSE(tasks.empty());
    EXPECT_EQ(tasks.back().phase, "images");
    EXPECT_EQ(tasks.back().after, "4, 5, 6");  // the reconstructions
    for (const PlanTask& t : tasks) ASSERT_SF_OK(sf_plan_run_task(plan.c_str(), t.index, nullptr));
    EXPECT_EQ(samples_of(read_sequence(path).get()), samples_of(single_ranks.get()));
    EXPECT_EQ(samples_of(read_sequence(out).get()), samples_of(read_sequence(dir.file("single.####.exr")).get()));

    // A caller built before the image fields: its struct ends at work_dir.
    sf_plan_options older;
    sf_plan_options_init(&older);
    older.struct_size = offsetof(sf_plan_options, images);
    older.images = images;  // past its struct_size: not read
    older.image_count = 1;
    ASSERT_SF_OK(sf_plan_write(filter.get(), in.c_str(), nullptr, dir.file("older.####.exr").c_str(), &wo, nullptr,
                               &older, dir.file("older.json").c_str()));
    EXPECT_EQ(read_text(dir.file("older.json")).find("\"images\""), std::string::npos);

    const std::string bad_plan = dir.file("bad.json");
    const auto refused = [&](const sf_plan_options& o, const std::vector<std::string>& words) {
        expect_failure(sf_plan_write(filter.get(), in.c_str(), nullptr, out.c_str(), &wo, nullptr, &o, bad_plan.c_str()),
                       SF_ERROR_INVALID_ARGUMENT, words);
        EXPECT_FALSE(fs::exists(bad_plan));
    };
    sf_plan_options o = po;
    o.image_count = -1;
    refused(o, {"image_count"});
    o.image_count = 1;
    o.images = nullptr;
    refused(o, {"NULL"});
    sf_image_output alpha[] = {{"alpha", path.c_str()}};
    o.images = alpha;
    refused(o, {"no image result 'alpha'", "rank_map"});
    sf_image_output onto_output[] = {{"rank_map", out.c_str()}};
    o.images = onto_output;
    refused(o, {"the plan's output"});
    const std::string other = dir.file("other.exr");
    sf_image_output twice[] = {{"rank_map", path.c_str()}, {"rank_map", other.c_str()}};
    o.images = twice;
    o.image_count = 2;
    refused(o, {"asked for twice"});
    Filt pca = pca_filter();  // no rank map
    expect_failure(sf_plan_write(pca.get(), in.c_str(), nullptr, out.c_str(), &wo, nullptr, &po, bad_plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"no image result 'rank_map'"});
}

TEST(DetectPlan, TasksAndDependenciesThenTheSingleRunMaskAndCrops) {
    TempDir dir;
    const DetectShot shot = write_detect_shot(dir);
    // The detect filter in one process on the same files.
    Filt single = detect_filter();
    Seq den = read_sequence(shot.denoised), noisy = read_sequence(shot.noisy);
    sf_shape shape{};
    ASSERT_SF_OK(sf_sequence_shape(den.get(), &shape));
    Seq out = create_sequence(shape);
    ASSERT_SF_OK(sf_filter_set_input(single.get(), "noisy", noisy.get()));
    ASSERT_SF_OK(sf_filter_execute(single.get(), den.get(), out.get()));
    sf_sequence mask_result = nullptr;
    ASSERT_SF_OK(sf_filter_result_sequence(single.get(), "mask", &mask_result));
    Seq single_mask(mask_result);
    const char* single_crops = nullptr;
    ASSERT_SF_OK(sf_filter_result_string(single.get(), "crops", &single_crops));
    double flagged = 0;
    ASSERT_SF_OK(sf_filter_result_float(single.get(), "flagged_pixel_frames", &flagged));
    ASSERT_GT(flagged, 0);  // the block is found: the comparison below is not of two empty masks

    Filt filter = detect_filter();
    sf_plan_options po;
    sf_plan_options_init(&po);
    po.tile_rows = 6;  // bands of 6, 6 and 4 rows
    const std::string plan = dir.file("detect.plan.json"), mask = dir.file("mask/m.####.exr"),
                      crops = dir.file("crops/c.json");
    ASSERT_SF_OK(sf_plan_write_detect(filter.get(), shot.denoised.c_str(), shot.noisy.c_str(), nullptr, mask.c_str(),
                                      crops.c_str(), nullptr, &po, plan.c_str()));
    EXPECT_FALSE(fs::exists(dir.file("mask/m.0001.exr")));
    EXPECT_FALSE(fs::exists(crops));
    const std::string text = read_text(plan);
    EXPECT_NE(text.find("\"kind\": \"detect\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"noisy\": \"" + shot.noisy + "\""), std::string::npos) << text;
    const std::smatch halo_match = [&] {
        std::smatch m;
        std::regex_search(text, m, std::regex(R"re("halo": (\d+))re"));
        return m;
    }();
    ASSERT_FALSE(halo_match.empty()) << text;
    const int64_t halo = std::stoll(halo_match[1]);
    EXPECT_GT(halo, 0);

    const std::vector<PlanTask> tasks = plan_tasks(text);
    ASSERT_EQ(tasks.size(), 3u + 1u + 3u + 1u) << text;  // noise x3, tolerance, detect x3, masks
    int64_t count = 0;
    ASSERT_SF_OK(sf_plan_task_count(plan.c_str(), &count));
    EXPECT_EQ(count, 8);
    const std::vector<std::pair<std::string, std::string>> expected = {
        {"noise", ""}, {"noise", ""}, {"noise", ""}, {"tolerance", "0, 1, 2"},
        {"detect", "3"}, {"detect", "3"}, {"detect", "3"}, {"masks", "4, 5, 6"}};
    const int64_t bands[3][2] = {{0, 6}, {6, 12}, {12, 16}};
    for (size_t i = 0; i < tasks.size(); ++i) {
        EXPECT_EQ(tasks[i].index, static_cast<int64_t>(i));
        EXPECT_EQ(tasks[i].phase, expected[i].first) << "task " << i;
        EXPECT_EQ(tasks[i].after, expected[i].second) << "task " << i;
        if (tasks[i].phase == "noise" || tasks[i].phase == "detect") {
            const auto& b = bands[(i < 3 ? i : i - 4)];
            EXPECT_EQ(tasks[i].read_rows, std::to_string(std::max<int64_t>(0, b[0] - halo)) + ", " +
                                              std::to_string(std::min<int64_t>(16, b[1] + halo)))
                << "task " << i;
        }
    }

    for (int64_t t = 0; t < count; ++t) ASSERT_SF_OK(sf_plan_run_task(plan.c_str(), t, nullptr));
    Seq farm_mask = read_sequence(mask);
    EXPECT_EQ(frame_numbers(farm_mask.get()), frame_numbers(den.get()));
    EXPECT_EQ(channel_name(farm_mask.get(), 0), "mask");
    EXPECT_EQ(samples_of(farm_mask.get()), samples_of(single_mask.get()));
    EXPECT_EQ(read_text(crops), std::string(single_crops));
    EXPECT_TRUE(fs::exists(plan_files(plan, "task-7.json")));

    // The score frames and the degree map through sf_plan_write_detect_outputs: the filter's results.
    sf_detect_outputs outputs;
    sf_detect_outputs_init(&outputs);
    const std::string score = dir.file("score/s.####.exr"), degree = dir.file("maps/degree.exr"),
                      preview = dir.file("maps/degree.png"), plan2 = dir.file("maps.plan.json");
    outputs.score = score.c_str();
    outputs.degree_map = degree.c_str();
    outputs.preview = preview.c_str();
    ASSERT_SF_OK(sf_plan_write_detect_outputs(filter.get(), shot.denoised.c_str(), shot.noisy.c_str(), nullptr, &outputs,
                                              nullptr, &po, plan2.c_str()));
    ASSERT_SF_OK(sf_plan_task_count(plan2.c_str(), &count));
    for (int64_t t = 0; t < count; ++t) ASSERT_SF_OK(sf_plan_run_task(plan2.c_str(), t, nullptr));
    for (const auto& [name, path] : {std::pair<const char*, std::string>{"score", score}, {"degree_map", degree}}) {
        sf_sequence result = nullptr;
        ASSERT_SF_OK(sf_filter_result_sequence(single.get(), name, &result));
        Seq expected(result), written = read_sequence(path);
        EXPECT_EQ(frame_numbers(written.get()), frame_numbers(expected.get())) << name;
        EXPECT_EQ(channel_name(written.get(), 0), channel_name(expected.get(), 0)) << name;
        EXPECT_EQ(samples_of(written.get()), samples_of(expected.get())) << name;
    }
    EXPECT_TRUE(fs::exists(preview));
}

TEST(DetectPlan, BadArgumentsAreRefusedBeforeAnythingIsWritten) {
    TempDir dir;
    const DetectShot shot = write_detect_shot(dir);
    const std::string plan = dir.file("plan.json"), mask = dir.file("m.####.exr"), crops = dir.file("c.json");
    const char* den = shot.denoised.c_str();
    const char* noisy = shot.noisy.c_str();
    Filt filter = detect_filter();
    expect_failure(sf_plan_write_detect(nullptr, den, noisy, nullptr, mask.c_str(), nullptr, nullptr, nullptr, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"filter"});
    Filt pca = pca_filter();
    expect_failure(sf_plan_write_detect(pca.get(), den, noisy, nullptr, mask.c_str(), nullptr, nullptr, nullptr, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"takes the \"detect\" filter", "pca"});
    expect_failure(sf_plan_write_detect(filter.get(), den, noisy, nullptr, nullptr, nullptr, nullptr, nullptr, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"mask_pattern", "crops_path"});
    expect_failure(sf_plan_write_detect(filter.get(), nullptr, noisy, nullptr, mask.c_str(), nullptr, nullptr, nullptr,
                                        plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"denoised_pattern"});
    expect_failure(sf_plan_write_detect(filter.get(), den, noisy, nullptr, mask.c_str(), nullptr, nullptr, nullptr, nullptr),
                   SF_ERROR_INVALID_ARGUMENT, {"plan_path"});
    sf_run_options ro;
    sf_run_options_init(&ro);
    ro.overwrite = 1;
    expect_failure(sf_plan_write_detect(filter.get(), den, noisy, nullptr, mask.c_str(), nullptr, &ro, nullptr, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"overwrite"});
    sf_plan_options po;
    sf_plan_options_init(&po);
    po.tiles = 2;
    po.tile_rows = 3;
    expect_failure(sf_plan_write_detect(filter.get(), den, noisy, nullptr, mask.c_str(), nullptr, nullptr, &po, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"not both"});
    const std::string missing = dir.file("nowhere/d.####.exr");
    expect_failure(sf_plan_write_detect(filter.get(), missing.c_str(), noisy, nullptr, nullptr, crops.c_str(), nullptr,
                                        nullptr, plan.c_str()),
                   SF_ERROR_NOT_FOUND, {"no files match", missing});
    EXPECT_SF_OK(sf_filter_set_string(filter.get(), "degree", "12"));  // 12 frames allow degree 11
    expect_failure(sf_plan_write_detect(filter.get(), den, noisy, nullptr, nullptr, crops.c_str(), nullptr, nullptr,
                                        plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"degree 12 needs at least 13 frames"});
    EXPECT_NE(std::string(sf_filter_last_error(filter.get())).find("degree 12"), std::string::npos);
    EXPECT_FALSE(fs::exists(plan));
    EXPECT_FALSE(fs::exists(crops));
    EXPECT_FALSE(fs::exists(dir.file("m.0001.exr")));

    // sf_plan_write_detect_outputs: its struct is required, one output at least, no output twice or an input.
    expect_failure(sf_plan_write_detect_outputs(filter.get(), den, noisy, nullptr, nullptr, nullptr, nullptr, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"outputs"});
    sf_detect_outputs outputs;
    sf_detect_outputs_init(&outputs);
    EXPECT_EQ(outputs.struct_size, sizeof outputs);
    expect_failure(sf_plan_write_detect_outputs(filter.get(), den, noisy, nullptr, &outputs, nullptr, nullptr, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"mask, crops, score, degree_map or preview"});
    outputs.mask = mask.c_str();
    outputs.score = mask.c_str();
    expect_failure(sf_plan_write_detect_outputs(filter.get(), den, noisy, nullptr, &outputs, nullptr, nullptr, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"mask and score outputs are both", mask});
    outputs.score = nullptr;
    outputs.degree_map = den;
    expect_failure(sf_plan_write_detect_outputs(filter.get(), den, noisy, nullptr, &outputs, nullptr, nullptr, plan.c_str()),
                   SF_ERROR_INVALID_ARGUMENT, {"degree_map output", "is an input"});
    EXPECT_FALSE(fs::exists(plan));

    // A valid plan, its tasks out of order: each says which file of an earlier phase is missing.
    EXPECT_SF_OK(sf_filter_set_string(filter.get(), "degree", "8"));
    ASSERT_SF_OK(sf_plan_write_detect(filter.get(), den, noisy, nullptr, mask.c_str(), crops.c_str(), nullptr, nullptr,
                                      plan.c_str()));
    int64_t count = 0;
    ASSERT_SF_OK(sf_plan_task_count(plan.c_str(), &count));
    ASSERT_EQ(count, 4);  // 16 rows: one band of the default 256 rows
    expect_failure(sf_plan_run_task(plan.c_str(), 4, nullptr), SF_ERROR_INVALID_ARGUMENT, {"task 4 is not in the plan"});
    const sf_status masks_first = sf_plan_run_task(plan.c_str(), 3, nullptr);
    EXPECT_EQ(masks_first, SF_ERROR_IO) << sf_last_error();
    EXPECT_NE(std::string(sf_last_error()).find("run the detect tasks before the masks task"), std::string::npos)
        << sf_last_error();
    EXPECT_FALSE(fs::exists(crops));
}

namespace {

// A square brighter than the background moving 2 pixels a frame across a noisy frame (moving), or
// the same frame without it (still); RGB, 16 frames of 28 x 20.
std::string write_window_shot(const TempDir& dir, const std::string& name, bool moving) {
    std::mt19937 rng(5);
    std::normal_distribution<float> noise(0.0f, 0.15f);
    Seq seq = filled_sequence(shape_of(16, 20, 28, 3), [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        const int64_t x0 = 2 + 2 * f;
        const bool square = moving && x >= x0 && x < x0 + 6 && y >= 7 && y < 13;
        return (square ? 3.0f : 0.5f + 0.05f * static_cast<float>(c)) * std::max(0.05f, 1.0f + noise(rng));
    });
    const char* names[] = {"R", "G", "B"};
    for (int64_t c = 0; c < 3; ++c) EXPECT_SF_OK(sf_sequence_set_channel_name(seq.get(), c, names[c]));
    for (int64_t f = 0; f < 16; ++f) EXPECT_SF_OK(sf_sequence_set_frame_number(seq.get(), f, f + 1));
    const std::string pattern = dir.file(name + ".####.exr");
    const sf_write_options o = write_options(SF_PIXEL_FLOAT);
    EXPECT_SF_OK(sf_sequence_write(seq.get(), pattern.c_str(), &o));
    return pattern;
}

Filt filter_with(const std::string& name, const std::vector<std::pair<std::string, std::string>>& params) {
    sf_filter f = nullptr;
    EXPECT_SF_OK(sf_filter_create(name.c_str(), &f));
    for (const auto& [k, v] : params) EXPECT_SF_OK(sf_filter_set_string(f, k.c_str(), v.c_str()));
    return Filt(f);
}

}  // namespace

// The hybrid's window plan (the passes, first passes in chunks, the guides, windows in chunks), each
// task on its own: the single run's output bit for bit, with and without the temporal-change test
// (its model goes through the work directory, or there is none), and for a still scene (global PCA:
// the later phases hand its frames on).
TEST(WindowPlan, TasksGiveTheSingleRunOutputBitForBit) {
    struct Case {
        std::string name, filter;
        bool moving;
        std::vector<std::pair<std::string, std::string>> params;
    };
    const std::vector<Case> cases = {
        {"hybrid", "hybrid", true, {{"mc_half_width", "2"}}},
        {"no_change_test", "hybrid", true, {{"mc_half_width", "2"}, {"change_z", "0"}}},
        {"balanced", "auto", true, {{"quality", "balanced"}}},
        {"still", "auto", false, {{"quality", "balanced"}}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        TempDir dir;
        const std::string in = write_window_shot(dir, "in", c.moving);
        const sf_write_options wo = write_options(SF_PIXEL_FLOAT);
        Filt single = filter_with(c.filter, c.params);
        ASSERT_SF_OK(sf_filter_run(single.get(), in.c_str(), nullptr, dir.file("single.####.exr").c_str(), &wo, nullptr));
        Filt filter = filter_with(c.filter, c.params);
        sf_plan_options po;
        sf_plan_options_init(&po);
        po.frames_per_task = 5;  // chunks of 5, 5, 5 and 1 frames
        const std::string plan = dir.file("plan.json");
        ASSERT_SF_OK(sf_plan_write(filter.get(), in.c_str(), nullptr, dir.file("out.####.exr").c_str(), &wo, nullptr, &po,
                                   plan.c_str()));
        const std::vector<PlanTask> tasks = plan_tasks(read_text(plan));
        ASSERT_EQ(tasks.size(), 1u + 4 + 1 + 4);
        EXPECT_EQ(tasks[0].phase, "analysis");
        EXPECT_EQ(tasks[5].phase, "guides");
        EXPECT_EQ(tasks[5].after, "1, 2, 3, 4");
        EXPECT_EQ(tasks[9].phase, "window");
        // Run out of order where the dependencies allow: the last chunks first.
        for (const int64_t t : {0, 4, 3, 2, 1, 5, 9, 8, 7, 6}) ASSERT_SF_OK(sf_plan_run_task(plan.c_str(), t, nullptr));
        EXPECT_EQ(samples_of(read_sequence(dir.file("out.####.exr")).get()),
                  samples_of(read_sequence(dir.file("single.####.exr")).get()));
        const std::string analysis = read_text(plan_files(plan, "analysis/analysis.json"));
        EXPECT_EQ(analysis.find("\"change\"") != std::string::npos, c.name != "no_change_test" && c.moving);
        EXPECT_EQ(analysis.find("\"still\": true") != std::string::npos, !c.moving);
    }
}
