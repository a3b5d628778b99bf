// Global temporal PCA: known answers on synthetic low-rank data, agreement with OpenCV's PCA as an
// independent reference, tiling invariance, and the numerical extremes.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "filter_runner.hpp"
#include "statfilter/error.hpp"
#include "synthetic.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

// Reference: centre each series by hand, let cv::PCA find the temporal components, project back.
std::unique_ptr<Sequence> opencv_pca_reference(const Sequence& in, int rank) {
    const Shape& s = in.shape();
    const int n = static_cast<int>(s.pixels() * s.channels), F = static_cast<int>(s.frames);
    cv::Mat data(n, F, CV_64F), means(n, 1, CV_64F);
    for (int64_t p = 0; p < s.pixels(); ++p)
        for (int64_t c = 0; c < s.channels; ++c)
            for (int f = 0; f < F; ++f) data.at<double>(static_cast<int>(p * s.channels + c), f) = in.at(f, p / s.width, p % s.width, c);
    cv::reduce(data, means, 1, cv::REDUCE_AVG);
    for (int i = 0; i < n; ++i) data.row(i) -= means.at<double>(i);
    cv::PCA pca(data, cv::Mat::zeros(1, F, CV_64F), cv::PCA::DATA_AS_ROW, rank);
    cv::Mat recon = pca.backProject(pca.project(data));
    auto out = std::make_unique<Sequence>(s);
    for (int64_t p = 0; p < s.pixels(); ++p)
        for (int64_t c = 0; c < s.channels; ++c) {
            const int i = static_cast<int>(p * s.channels + c);
            for (int f = 0; f < F; ++f)
                out->at(f, p / s.width, p % s.width, c) = static_cast<float>(recon.at<double>(i, f) + means.at<double>(i));
        }
    return out;
}

}  // namespace

TEST(Pca, AutoRankFindsTheTrueRankAndRemovesMostNoise) {
    std::unique_ptr<Sequence> clean;
    LowRank g;
    g.noise = 0.05;
    const auto noisy = make_low_rank(g, &clean);
    const FilterRun r = run_linear("pca", *noisy, {{"rank", "auto"}});
    EXPECT_EQ(r.result("rank"), 3);
    EXPECT_NEAR(r.result("noise_sigma"), 0.05, 0.005);  // Gavish-Donoho's noise estimate
    EXPECT_LT(mse(*r.output, *clean), mse(*noisy, *clean) / 5);
}

TEST(Pca, PoissonLikeNoise) {
    std::unique_ptr<Sequence> clean;
    LowRank g;
    g.noise = 0.08;
    g.poisson_like = true;
    const auto noisy = make_low_rank(g, &clean);
    const FilterRun plain = run_linear("pca", *noisy, {{"rank", "auto"}});
    EXPECT_EQ(plain.result("rank"), 3);
    EXPECT_LT(mse(*plain.output, *clean), mse(*noisy, *clean) / 4);
    // sqrt evens out the noise but bends the low-rank signal: one more (weak) component appears.
    const FilterRun stabilised = run_linear("pca", *noisy, {{"rank", "auto"}, {"transform", "sqrt"}});
    EXPECT_GE(stabilised.result("rank"), 3);
    EXPECT_LE(stabilised.result("rank"), 4);
    EXPECT_LT(mse(*stabilised.output, *clean), mse(*noisy, *clean) / 3);
}

TEST(Pca, NoiseFreeLowRankIsReconstructedExactly) {
    LowRank g;
    const auto clean = make_low_rank(g);
    const FilterRun r = run_linear("pca", *clean, {{"rank", "3"}});
    EXPECT_LT(max_abs_diff(*r.output, *clean), 1e-5);
    // Too few components loses signal: the test can fail.
    EXPECT_GT(max_abs_diff(*run_linear("pca", *clean, {{"rank", "2"}}).output, *clean), 1e-2);
}

TEST(Pca, MatchesOpenCvReference) {
    LowRank g;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    for (int rank : {1, 2, 5}) {
        const FilterRun r = run_linear("pca", *noisy, {{"rank", std::to_string(rank)}});
        EXPECT_LT(max_abs_diff(*r.output, *opencv_pca_reference(*noisy, rank)), 1e-5) << "rank " << rank;
    }
}

TEST(Pca, SeparateBasesPerChannelMatchPerChannelRuns) {
    LowRank g;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    const FilterRun both = run_linear("pca", *noisy, {{"rank", "2"}, {"shared_basis", "0"}});
    // Channel 1 alone through a one-channel sequence gives the same numbers.
    Sequence one(Shape{g.frames, g.height, g.width, 1});
    for (int64_t f = 0; f < g.frames; ++f)
        for (int64_t y = 0; y < g.height; ++y)
            for (int64_t x = 0; x < g.width; ++x) one.at(f, y, x, 0) = noisy->at(f, y, x, 1);
    const FilterRun single = run_linear("pca", one, {{"rank", "2"}});
    double worst = 0;
    for (int64_t f = 0; f < g.frames; ++f)
        for (int64_t y = 0; y < g.height; ++y)
            for (int64_t x = 0; x < g.width; ++x)
                worst = std::max(worst, std::fabs(double(both.output->at(f, y, x, 1)) - single.output->at(f, y, x, 0)));
    EXPECT_LT(worst, 1e-6);
    EXPECT_EQ(both.filter->results().get_string("rank"), "2,2,2");
}

TEST(Pca, TiledResultEqualsUntiled) {
    LowRank g;
    g.height = 64;
    g.width = 80;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    const FilterRun whole = run_linear("pca", *noisy, {{"rank", "auto"}, {"memory_mb", "4096"}});
    const FilterRun tiled = run_linear("pca", *noisy, {{"rank", "auto"}, {"memory_mb", "1"}});  // 1024-pixel tiles
    EXPECT_EQ(whole.result("rank"), tiled.result("rank"));
    EXPECT_LT(max_abs_diff(*whole.output, *tiled.output), 1e-6);
}

TEST(Pca, StridedInputAndOutputGiveTheSameResult) {
    LowRank g;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    const Shape& s = noisy->shape();
    // Channel-planar buffers (all R, then all G, ...) with every other pixel skipped.
    const Strides planar{s.frames * s.height * s.width * 2 * 4, 2 * 4, s.width * 2 * 4, s.height * s.width * 2 * 4};
    std::vector<float> in_buffer(static_cast<size_t>(s.samples() * 2)), out_buffer(in_buffer.size(), -1.0f);
    Sequence in(in_buffer.data(), s, planar), out(out_buffer.data(), s, planar);
    in.copy_samples_from(*noisy);
    for (const char* name : {"pca", "error-threshold", "moving-basis"}) {
        const FilterRun contiguous = run_filter(name, *noisy);
        auto filter = create_filter(name);
        filter->execute(in, out, Progress());
        EXPECT_EQ(max_abs_diff(out, *contiguous.output), 0.0) << name;
    }
}

TEST(Pca, EnergyRank) {
    LowRank g;
    const auto clean = make_low_rank(g);
    EXPECT_EQ(run_linear("pca", *clean, {{"rank", "energy"}, {"energy", "0.999999"}}).result("rank"), 3);
    EXPECT_LE(run_linear("pca", *clean, {{"rank", "energy"}, {"energy", "0.3"}}).result("rank"), 2);
}

TEST(PcaExtremes, ConstantAndZeroSequencesAreUnchanged) {
    for (float value : {0.0f, 5.0f, -3.0f}) {
        Sequence in(Shape{10, 4, 5, 3});
        for (int64_t f = 0; f < 10; ++f)
            for (int64_t y = 0; y < 4; ++y)
                for (int64_t x = 0; x < 5; ++x)
                    for (int64_t c = 0; c < 3; ++c) in.at(f, y, x, c) = value;
        const FilterRun r = run_linear("pca", in);
        EXPECT_EQ(max_abs_diff(*r.output, in), 0.0) << value;
        EXPECT_EQ(r.result("rank"), 0);
    }
}

TEST(PcaExtremes, OneAndTwoFrames) {
    LowRank g;
    g.frames = 1;
    g.noise = 0.1;
    const auto one = make_low_rank(g);
    const FilterRun r1 = run_linear("pca", *one, {{"rank", "auto"}});
    EXPECT_EQ(max_abs_diff(*r1.output, *one), 0.0);  // nothing to learn from time: unchanged
    EXPECT_EQ(r1.result("rank"), 0);
    g.frames = 2;
    const auto two = make_low_rank(g);
    const FilterRun r2 = run_linear("pca", *two, {{"rank", "5"}});
    EXPECT_EQ(r2.result("rank"), 1);  // clamped to frames - 1
    EXPECT_LT(max_abs_diff(*r2.output, *two), 1e-6);
}

TEST(PcaExtremes, RankLargerThanFramesIsClampedAndExact) {
    LowRank g;
    g.frames = 5;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    const FilterRun r = run_linear("pca", *noisy, {{"rank", "100"}});
    EXPECT_EQ(r.result("rank"), 4);
    EXPECT_LT(max_abs_diff(*r.output, *noisy), 1e-5);
}

TEST(PcaExtremes, MoreFramesThanPixels) {
    LowRank g;
    g.frames = 500;
    g.height = 1;
    g.width = 1;
    g.rank = 1;
    g.noise = 0.01;
    const auto noisy = make_low_rank(g);
    const FilterRun r = run_linear("pca", *noisy, {{"rank", "auto"}});
    EXPECT_LE(r.result("rank"), 3);  // at most as many components as series
    EXPECT_TRUE(all_finite(*r.output));
    EXPECT_LT(max_abs_diff(*run_linear("pca", *noisy, {{"rank", "3"}}).output, *noisy), 1e-5);
}

TEST(PcaExtremes, TinyAndHugeValuesScaleExactly) {
    LowRank g;
    g.noise = 0.05;
    const auto base = make_low_rank(g);
    const FilterRun reference = run_linear("pca", *base, {{"rank", "auto"}});
    for (double scale : {1e-30, 1e30}) {
        Sequence scaled(base->shape());
        const Shape& s = base->shape();
        for (int64_t f = 0; f < s.frames; ++f)
            for (int64_t y = 0; y < s.height; ++y)
                for (int64_t x = 0; x < s.width; ++x)
                    for (int64_t c = 0; c < s.channels; ++c)
                        scaled.at(f, y, x, c) = static_cast<float>(base->at(f, y, x, c) * scale);
        const FilterRun r = run_linear("pca", scaled, {{"rank", "auto"}});
        EXPECT_EQ(r.result("rank"), reference.result("rank")) << scale;
        ASSERT_TRUE(all_finite(*r.output));
        double worst = 0;
        for (int64_t f = 0; f < s.frames; ++f)
            for (int64_t y = 0; y < s.height; ++y)
                for (int64_t x = 0; x < s.width; ++x)
                    for (int64_t c = 0; c < s.channels; ++c)
                        worst = std::max(worst, std::fabs(r.output->at(f, y, x, c) / scale - reference.output->at(f, y, x, c)));
        EXPECT_LT(worst, 1e-4) << scale;
    }
}

TEST(PcaExtremes, LogTransformStaysFiniteUpToTheFloatLimit) {
    LowRank g;
    g.offset = 1.0;
    g.noise = 0.05;
    auto seq = make_low_rank(g);
    seq->at(0, 0, 0, 0) = std::numeric_limits<float>::max();
    seq->at(1, 0, 0, 0) = -std::numeric_limits<float>::max();
    seq->at(2, 1, 1, 1) = std::numeric_limits<float>::denorm_min();
    const FilterRun r = run_filter("pca", *seq, {{"rank", "auto"}, {"transform", "log"}});
    EXPECT_TRUE(all_finite(*r.output));
    // With every component kept, the transform round trip gives back the input.
    // (firefly_z=0: by default the lone float-max sample is a firefly and replaced by its median.)
    const FilterRun full = run_filter("pca", *seq, {{"rank", "100"}, {"transform", "log"}, {"firefly_z", "0"}});
    EXPECT_TRUE(all_finite(*full.output));
    EXPECT_NEAR(full.output->at(0, 0, 0, 0) / std::numeric_limits<float>::max(), 1.0, 1e-4);
    EXPECT_NEAR(full.output->at(5, 3, 3, 0), seq->at(5, 3, 3, 0), 1e-5);
}

TEST(PcaExtremes, LargeMeanSmallVariationKeepsThePrecisionFloatHas) {
    LowRank g;
    g.offset = 1e6;
    g.amplitude = 1.0;
    const auto clean = make_low_rank(g);
    const FilterRun r = run_linear("pca", *clean, {{"rank", "3"}});
    EXPECT_LE(max_abs_diff(*r.output, *clean), 0.0625);  // one float ulp at 1e6
    EXPECT_GT(max_abs_diff(*run_linear("pca", *clean, {{"rank", "0"}}).output, *clean), 0.5);
}

TEST(PcaExtremes, NonFiniteInputErrorOrRepair) {
    LowRank g;
    g.noise = 0.05;
    auto noisy = make_low_rank(g);
    noisy->at(3, 2, 1, 0) = std::numeric_limits<float>::quiet_NaN();
    noisy->at(7, 5, 5, 2) = std::numeric_limits<float>::infinity();
    try {
        run_linear("pca", *noisy);
        FAIL() << "NaN accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Numeric);
        EXPECT_NE(std::string(e.what()).find("NaN in frame 4 at pixel (1, 2)"), std::string::npos) << e.what();
    }
    const FilterRun r = run_linear("pca", *noisy, {{"nonfinite", "repair"}});
    EXPECT_EQ(r.result("nonfinite_repaired"), 2);
    EXPECT_TRUE(all_finite(*r.output));
}

TEST(RankChoice, GavishDonohoOnPureNoiseKeepsNothing) {
    LowRank g;
    g.rank = 0;
    g.noise = 1.0;
    const auto noise = make_low_rank(g);
    EXPECT_EQ(run_linear("pca", *noise, {{"rank", "auto"}}).result("rank"), 0);
}
