// The postfilter stage: a single-frame filter on every frame of a temporal filter's output.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "filter_runner.hpp"
#include "filters/frame_stages.hpp"
#include "statfilter/error.hpp"
#include "synthetic.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

// Spatially smooth light (a slow wave and a soft step) changing over time, plus white noise: what
// indirect illumination looks like before the albedo.
std::unique_ptr<Sequence> smooth_scene(std::unique_ptr<Sequence>* clean, double noise) {
    const Shape shape{16, 40, 48, 3};
    auto noisy = std::make_unique<Sequence>(shape);
    *clean = std::make_unique<Sequence>(shape);
    std::mt19937 rng(11);
    std::normal_distribution<double> n(0.0, noise);
    for (int64_t f = 0; f < shape.frames; ++f)
        for (int64_t y = 0; y < shape.height; ++y)
            for (int64_t x = 0; x < shape.width; ++x)
                for (int64_t c = 0; c < shape.channels; ++c) {
                    const double v = 1.0 + 0.4 * std::sin(x / 7.0 + 0.2 * f) * std::cos(y / 9.0) +
                                     0.5 / (1.0 + std::exp(-(x - 24.0))) + 0.1 * c;
                    (*clean)->at(f, y, x, c) = static_cast<float>(v);
                    noisy->at(f, y, x, c) = static_cast<float>(v + n(rng));
                }
    return noisy;
}

std::map<std::string, std::string> refine() {
    return {{"postfilter", kRefinePostfilter}, {"postfilter_params", kRefinePostfilterParams}};
}

}  // namespace

TEST(Postfilter, IsTheSingleFrameFilterOnTheTemporalOutput) {
    std::unique_ptr<Sequence> clean;
    const auto seq = smooth_scene(&clean, 0.2);
    for (const char* method : {"pca", "error-threshold", "moving-basis"}) {
        const FilterRun both = run_filter(method, *seq, refine());
        const FilterRun temporal = run_filter(method, *seq);
        const FilterRun after = run_filter("diffusion", *temporal.output, {{"iterations", "3"}, {"k", "3"}});
        EXPECT_EQ(max_abs_diff(*both.output, *after.output), 0.0) << method;
        EXPECT_GT(max_abs_diff(*both.output, *temporal.output), 0.0) << method;
    }
    // With a prefilter too: copy, then pca, then diffusion.
    auto params = refine();
    params["prefilter"] = "copy";
    const FilterRun three = run_filter("pca", *seq, params);
    EXPECT_EQ(max_abs_diff(*three.output, *run_filter("pca", *seq, refine()).output), 0.0);
}

TEST(Postfilter, LowersTheErrorATemporalBasisLeavesOnSmoothLight) {
    std::unique_ptr<Sequence> clean;
    const auto seq = smooth_scene(&clean, 0.2);
    for (const char* method : {"pca", "error-threshold"}) {
        const double plain = mse(*run_filter(method, *seq).output, *clean);
        const double refined = mse(*run_filter(method, *seq, refine()).output, *clean);
        EXPECT_LT(refined, 0.7 * plain) << method << ": " << refined << " vs " << plain;
    }
}

TEST(Postfilter, TheHybridHasItByDefaultAndCanDropIt) {
    std::unique_ptr<Sequence> clean;
    const auto seq = smooth_scene(&clean, 0.2);
    const FilterRun hybrid = run_filter("hybrid", *seq);
    const FilterRun raw = run_filter("hybrid", *seq, {{"postfilter", ""}});
    const FilterRun after = run_filter("diffusion", *raw.output, {{"iterations", "3"}, {"k", "3"}});
    EXPECT_EQ(max_abs_diff(*hybrid.output, *after.output), 0.0);
    EXPECT_LT(mse(*hybrid.output, *clean), mse(*raw.output, *clean));
}

// prefilter_order=last: the temporal filter on the noisy frames, then the prefilter on its result in
// place of the postfilter (without the trust blend, exactly the two filters one after the other).
TEST(Postfilter, APrefilterRunLastIsTheSingleFrameFilterOnTheTemporalOutput) {
    std::unique_ptr<Sequence> clean;
    const auto seq = smooth_scene(&clean, 0.2);
    const std::map<std::string, std::string> last = {
        {"prefilter", "diffusion"}, {"prefilter_params", "iterations=2"}, {"prefilter_order", "last"}, {"prefilter_trust", "0"}};
    const FilterRun pca_last = run_filter("pca", *seq, last);
    const FilterRun pca = run_filter("pca", *seq);
    const FilterRun after = run_filter("diffusion", *pca.output, {{"iterations", "2"}});
    EXPECT_EQ(max_abs_diff(*pca_last.output, *after.output), 0.0);
    // Run first instead, the temporal filter sees the prefiltered frames: another result.
    auto first = last;
    first["prefilter_order"] = "first";
    EXPECT_GT(max_abs_diff(*run_filter("pca", *seq, first).output, *after.output), 1e-4);
    // The hybrid runs its prefilter last by default, in place of its light diffusion pass.
    auto hybrid_params = last;
    hybrid_params.erase("prefilter_order");
    const FilterRun hybrid = run_filter("hybrid", *seq, hybrid_params);
    const FilterRun raw = run_filter("hybrid", *seq, {{"postfilter", ""}});
    EXPECT_EQ(max_abs_diff(*hybrid.output, *run_filter("diffusion", *raw.output, {{"iterations", "2"}}).output), 0.0);
    // With the trust blend (the default) each tile keeps a share of the change from the prefiltered
    // noisy frames: well below their error, where the temporal result is right.
    auto trusted = last;
    trusted.erase("prefilter_trust");
    const FilterRun blended = run_filter("pca", *seq, trusted);
    const double alone = mse(*run_filter("diffusion", *seq, {{"iterations", "2"}}).output, *clean);
    EXPECT_LT(mse(*blended.output, *clean), 0.5 * alone);
    EXPECT_GE(blended.result("prefilter_trust.share"), 0.0);
    EXPECT_LE(blended.result("prefilter_trust.share"), 1.0);
}

TEST(Postfilter, BadStagesAreNamed) {
    std::unique_ptr<Sequence> clean;
    const auto seq = smooth_scene(&clean, 0.2);
    auto fails = [&](const std::map<std::string, std::string>& params, Status status, const std::string& fragment) {
        try {
            run_filter("pca", *seq, params);
            ADD_FAILURE() << "no error for " << fragment;
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), status);
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    fails({{"postfilter", "moving-basis"}}, Status::InvalidArgument, "postfilter 'moving-basis' is a temporal filter");
    fails({{"postfilter", "no-such-filter"}}, Status::NotFound, "no-such-filter");
    fails({{"postfilter", "diffusion"}, {"postfilter_params", "iterations=-1"}}, Status::InvalidArgument,
          "postfilter_params");
    fails({{"postfilter", "diffusion"}, {"postfilter_params", "gain=2"}}, Status::NotFound, "postfilter_params");
    // A postfilter the user names would not run after a prefilter run last: refused, not dropped.
    fails({{"postfilter", "diffusion"}, {"prefilter", "diffusion"}, {"prefilter_order", "last"}}, Status::InvalidArgument,
          "prefilter_order=last");
    fails({{"prefilter_order", "middle"}}, Status::InvalidArgument, "prefilter_order");
}
