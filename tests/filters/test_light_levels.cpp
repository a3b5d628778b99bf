// The shot's light level frame by frame (pipeline/light_levels.hpp): the smoothing's known answers,
// the measurement on a light ramp, black and broken frames, the levelled source's round trip, and
// balanced keeping a light's swing on a short noisy shot (where the automatic rank drops it).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "filter_runner.hpp"
#include "pipeline/light_levels.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

constexpr int64_t kW = 48, kH = 40, kC = 3, kF = 8;

double ramp(int64_t f) { return 1.0 + 0.35 * static_cast<double>(f) / (kF - 1); }

// A still picture under a light rising by 35% over the shot, with 4-spp-like gamma noise (or none).
std::unique_ptr<Sequence> lit_shot(bool noisy) {
    auto s = std::make_unique<Sequence>(Shape{kF, kH, kW, kC});
    std::mt19937 rng(11);
    std::gamma_distribution<double> sample(4.0, 0.25);  // mean 1, 50% deviation
    for (int64_t f = 0; f < kF; ++f)
        for (int64_t y = 0; y < kH; ++y)
            for (int64_t x = 0; x < kW; ++x)
                for (int64_t c = 0; c < kC; ++c)
                    s->at(f, y, x, c) = static_cast<float>(ramp(f) * (0.2 + 0.6 * x / kW) * (noisy ? sample(rng) : 1.0));
    return s;
}

double frame_mean(const Sequence& s, int64_t f) {
    double sum = 0;
    for (int64_t y = 0; y < kH; ++y)
        for (int64_t x = 0; x < kW; ++x)
            for (int64_t c = 0; c < kC; ++c) sum += s.at(f, y, x, c);
    return sum / (kH * kW * kC);
}

}  // namespace

TEST(LightLevels, TheSmoothingFitsAQuadraticExactly) {
    std::vector<double> quadratic(20), constant(20, 2.5);
    for (size_t f = 0; f < quadratic.size(); ++f) quadratic[f] = 1 + 0.1 * f - 0.004 * f * f;
    const auto q = smooth_light_levels(quadratic, kLightLevelHalfWidth);
    for (size_t f = 0; f < q.size(); ++f) EXPECT_NEAR(q[f], quadratic[f], 1e-12) << f;
    for (double v : smooth_light_levels(constant, kLightLevelHalfWidth)) EXPECT_NEAR(v, 2.5, 1e-12);
    // One and two frames: the mean and the line.
    EXPECT_NEAR(smooth_light_levels({3.0}, 8)[0], 3.0, 1e-12);
    const auto two = smooth_light_levels({1.0, 2.0}, 8);
    EXPECT_NEAR(two[0], 1.0, 1e-12);
    EXPECT_NEAR(two[1], 2.0, 1e-12);
    // A frame-to-frame wobble (noise, an object's motion) is smoothed away, not followed.
    std::vector<double> wobble(32);
    for (size_t f = 0; f < wobble.size(); ++f) wobble[f] = 1 + (f % 2 ? 0.01 : -0.01);
    const auto smooth = smooth_light_levels(wobble, kLightLevelHalfWidth);
    for (size_t f = 0; f < smooth.size(); ++f) {
        const bool whole_window = f >= kLightLevelHalfWidth && f + kLightLevelHalfWidth < smooth.size();
        EXPECT_NEAR(smooth[f], 1.0, whole_window ? 0.002 : 0.006) << f;  // one-sided at the ends
    }
}

TEST(LightLevels, MeasuresARampAndLeavesBlackAndBrokenShotsAlone) {
    const auto clean = lit_shot(false);
    const auto source = memory_source(*clean);
    const auto levels = measure_light_levels(*source, 2);
    double mean_ramp = 0;
    for (int64_t f = 0; f < kF; ++f) mean_ramp += ramp(f) / kF;
    for (int64_t f = 0; f < kF; ++f) EXPECT_NEAR(levels[static_cast<size_t>(f)], ramp(f) / mean_ramp, 1e-6) << f;
    // The levelled frames are one level; restore gives the frame back.
    const LevelledSource levelled(*source, levels);
    std::vector<float> frame(static_cast<size_t>(kH * kW * kC));
    levelled.read_rows(kF - 1, 0, kH, frame.data());
    EXPECT_NEAR(frame[0], clean->at(0, 0, 0, 0) / (ramp(0) / mean_ramp), 1e-5);
    levelled.restore(kF - 1, frame.data());
    EXPECT_NEAR(frame[5], clean->at(kF - 1, 0, 1, 2), 1e-5);
    // A black frame, or a NaN everywhere in one: nothing is divided.
    auto black = lit_shot(false);
    for (int64_t y = 0; y < kH; ++y)
        for (int64_t x = 0; x < kW; ++x)
            for (int64_t c = 0; c < kC; ++c) black->at(3, y, x, c) = 0.0f;
    for (double l : measure_light_levels(*memory_source(*black), 1)) EXPECT_EQ(l, 1.0);
    auto broken = lit_shot(false);
    for (int64_t x = 0; x < kW; ++x) broken->at(2, 0, x, 0) = std::numeric_limits<float>::quiet_NaN();
    const auto some = measure_light_levels(*memory_source(*broken), 1);  // NaN samples are left out
    EXPECT_NEAR(some[2], levels[2], 1e-3);
    Sequence one(Shape{1, kH, kW, kC});
    EXPECT_EQ(measure_light_levels(*memory_source(one), 1), std::vector<double>{1.0});
}

// 8 noisy frames under a rising light: global PCA's automatic rank keeps no component here, and
// before the levels the light's swing was averaged away (every frame at the shot's mean light).
TEST(LightLevels, BalancedKeepsALightsSwingOnAShortNoisyShot) {
    const auto noisy = lit_shot(true);
    const FilterRun run = run_filter("auto", *noisy, {{"quality", "balanced"}});
    EXPECT_EQ(run.filter->results().get_string("method").rfind("pca", 0), 0u);  // a still scene
    for (int64_t f = 0; f < kF; ++f) {
        const double truth = frame_mean(*lit_shot(false), f);
        EXPECT_NEAR(frame_mean(*run.output, f) / truth, 1.0, 0.02) << f;
    }
}
