// The noise-in-time check (statfilter/noise_in_time.hpp): independent noise against the same noise
// in every frame (a renderer's fixed seed), at any scale, through a change of the light, with
// noise-free, black and non-finite frames; and the warning the presets report.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "filter_runner.hpp"
#include "statfilter/noise_in_time.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

constexpr int64_t kW = 64, kH = 48, kC = 3, kF = 8;
constexpr size_t kSamples = kW * kH * kC;

// A smooth picture (a gradient, brighter to the right) times (1 + gamma-like noise of 16 spp).
std::vector<float> noisy_frame(uint32_t seed, double light = 1.0) {
    std::mt19937 rng(seed);
    std::gamma_distribution<double> sample(16.0, 1.0 / 16.0);  // mean 1, 25% deviation
    std::vector<float> frame(kSamples);
    for (int64_t y = 0; y < kH; ++y)
        for (int64_t x = 0; x < kW; ++x)
            for (int64_t c = 0; c < kC; ++c)
                frame[static_cast<size_t>((y * kW + x) * kC + c)] =
                    static_cast<float>(light * (0.2 + 0.6 * x / kW + 0.1 * c) * sample(rng));
    return frame;
}

NoiseInTime pair(const std::vector<float>& a, const std::vector<float>& b) {
    return measure_noise_in_time(a.data(), b.data(), kH, kW, kC);
}

std::unique_ptr<Sequence> shot(bool same_seed) {
    auto s = std::make_unique<Sequence>(Shape{kF, kH, kW, kC});
    for (int64_t f = 0; f < kF; ++f) {
        const auto frame = noisy_frame(same_seed ? 7u : 100u + static_cast<uint32_t>(f), 1.0 + 0.05 * f);
        std::copy(frame.begin(), frame.end(), &s->at(f, 0, 0, 0));
    }
    return s;
}

}  // namespace

TEST(NoiseInTime, IndependentNoiseIsNearOne) {
    const NoiseInTime r = pair(noisy_frame(1), noisy_frame(2));
    EXPECT_EQ(r.pairs, 1);
    EXPECT_GT(r.spatial, 0.1);  // about 0.25 in log units at this level
    EXPECT_GT(r.ratio(), 0.85);
    EXPECT_LT(r.ratio(), 1.15);
}

TEST(NoiseInTime, TheSameNoiseInEveryFrameIsNearZeroThroughALightChange) {
    const auto a = noisy_frame(3);
    EXPECT_LT(pair(a, a).ratio(), 1e-9);
    // The same seed while the light brightens by 30%: each frame's own median is its unit.
    EXPECT_LT(pair(a, noisy_frame(3, 1.3)).ratio(), 0.05);
    EXPECT_LT(pair(a, noisy_frame(3, 1.3)).ratio(), kSameNoiseRatio);
}

TEST(NoiseInTime, DoesNotDependOnTheUnits) {
    const auto a = noisy_frame(4), b = noisy_frame(5);
    const double reference = pair(a, b).ratio();
    for (double k : {1e-6, 1e-3, 1e3, 1e6}) {
        std::vector<float> ka(a), kb(b);
        for (auto& v : ka) v = static_cast<float>(v * k);
        for (auto& v : kb) v = static_cast<float>(v * k);
        EXPECT_NEAR(pair(ka, kb).ratio(), reference, 1e-3 * reference) << k;
    }
}

TEST(NoiseInTime, ExtremesAreNotMeasuredOrLeftOut) {
    // Noise-free and black frames: nothing across the frame to compare with, ratio 1 (no warning).
    const std::vector<float> flat(kSamples, 0.5f), black(kSamples, 0.0f);
    EXPECT_EQ(pair(flat, flat).ratio(), 1.0);
    EXPECT_EQ(pair(black, black).ratio(), 1.0);
    // Too few rows for a neighbour on each side: not measured.
    const auto a = noisy_frame(6), b = noisy_frame(7);
    EXPECT_EQ(measure_noise_in_time(a.data(), b.data(), 2, kW, kC).pairs, 0);
    EXPECT_EQ(measure_noise_in_time(a.data(), b.data(), 0, kW, kC).ratio(), 1.0);
    // NaN, Inf and negative samples are left out; the rest still decide.
    std::vector<float> bad(b);
    bad[10] = std::numeric_limits<float>::quiet_NaN();
    bad[500] = std::numeric_limits<float>::infinity();
    bad[900] = -3.0f;
    const NoiseInTime r = pair(a, bad);
    EXPECT_TRUE(std::isfinite(r.ratio()));
    EXPECT_NEAR(r.ratio(), pair(a, b).ratio(), 0.05);
    // Several pairs: the median of each figure.
    const NoiseInTime three[] = {{0.1, 0.2, 1}, {0.3, 0.2, 1}, {0.2, 0.4, 1}};
    const NoiseInTime m = combine_noise_in_time(three, 3);
    EXPECT_EQ(m.pairs, 3);
    EXPECT_DOUBLE_EQ(m.temporal, 0.2);
    EXPECT_DOUBLE_EQ(m.spatial, 0.2);
    EXPECT_EQ(combine_noise_in_time(three, 0).ratio(), 1.0);
}

// Every preset measures it before its work and warns when the noise is the same in every frame.
TEST(NoiseInTime, ThePresetsWarnOfTheSameNoiseInEveryFrame) {
    const auto fixed = shot(true), independent = shot(false);
    for (const char* quality : {"fast", "balanced"}) {
        const FilterRun same = run_filter("auto", *fixed, {{"quality", quality}});
        EXPECT_LT(same.result("noise_in_time"), kSameNoiseRatio) << quality;
        const std::string warning = same.filter->results().get_string("warning");
        EXPECT_NE(warning.find("the same in every frame"), std::string::npos) << warning;
        EXPECT_NE(warning.find("seed"), std::string::npos) << warning;
        const FilterRun fine = run_filter("auto", *independent, {{"quality", quality}});
        EXPECT_GT(fine.result("noise_in_time"), 0.8) << quality;
        EXPECT_FALSE(fine.filter->results().has("warning")) << quality;
    }
    // A prefilter run first: the stage sees its frames, which say nothing of the seed; not measured.
    const FilterRun prefiltered = run_filter("auto", *fixed, {{"quality", "balanced"}, {"prefilter", "diffusion"},
                                                              {"prefilter_order", "first"}});
    EXPECT_FALSE(prefiltered.filter->results().has("noise_in_time"));
    EXPECT_FALSE(prefiltered.filter->results().has("warning"));
    // One frame: nothing to measure, no warning.
    Sequence one(Shape{1, kH, kW, kC});
    for (int64_t y = 0; y < kH; ++y)
        for (int64_t x = 0; x < kW; ++x)
            for (int64_t c = 0; c < kC; ++c) one.at(0, y, x, c) = fixed->at(0, y, x, c);
    const FilterRun single = run_filter("auto", one, {{"quality", "fast"}});
    EXPECT_FALSE(single.filter->results().has("noise_in_time"));
    EXPECT_FALSE(single.filter->results().has("warning"));
}
