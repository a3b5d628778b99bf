// A run as a plan of tasks through the C ABI (sf_plan_*): the tasks run one after another give the
// output of sf_filter_run; bad arguments are refused before anything is written.
#include <statfilter/statfilter.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capi_util.hpp"

using namespace statfilter_test;

namespace {

// Noisy frames of a smooth image, RGB, frames 1..F, written as float EXRs.
std::string write_shot(const TempDir& dir, int64_t frames = 8) {
    std::mt19937 rng(7);
    std::normal_distribution<float> noise(0.0f, 0.2f);
    Seq seq = filled_sequence(shape_of(frames, 12, 10, 3), [&](int64_t f, int64_t y, int64_t x, int64_t c) {
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

}  // namespace

TEST(Plan, TasksInOrderGiveTheSingleRunOutput) {
    TempDir dir;
    const std::string in = write_shot(dir);
    Filt single = pca_filter();
    const sf_write_options wo = write_options(SF_PIXEL_FLOAT);
    ASSERT_SF_OK(sf_filter_run(single.get(), in.c_str(), nullptr, dir.file("single.####.exr").c_str(), &wo, nullptr));

    Filt filter = pca_filter();
    sf_plan_options po;
    sf_plan_options_init(&po);
    po.tile_rows = 5;  // bands of 5, 5 and 2 rows
    po.frames_per_task = 3;
    const std::string plan = dir.file("plan.json");
    ASSERT_SF_OK(sf_plan_write(filter.get(), in.c_str(), nullptr, dir.file("out.####.exr").c_str(), &wo, nullptr, &po,
                               plan.c_str()));
    EXPECT_FALSE(fs::exists(dir.file("out.0001.exr")));
    int64_t count = 0;
    ASSERT_SF_OK(sf_plan_task_count(plan.c_str(), &count));
    EXPECT_EQ(count, 3 + 1 + 3 + 3);  // statistics, reduce, reconstruct, assemble
    for (int64_t t = 0; t < count; ++t) ASSERT_SF_OK(sf_plan_run_task(plan.c_str(), t, nullptr));
    EXPECT_EQ(samples_of(read_sequence(dir.file("out.####.exr")).get()),
              samples_of(read_sequence(dir.file("single.####.exr")).get()));
    EXPECT_TRUE(fs::exists(dir.file("plan.json.work/task-9.json")));
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
}
