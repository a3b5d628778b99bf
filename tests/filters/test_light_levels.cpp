// The shot's light level frame by frame (pipeline/light_levels.hpp): the smoothing's known answers,
// the measurement on a light ramp, black and broken frames, the levelled source's round trip, and
// balanced keeping a light's swing on a short noisy shot (where the automatic rank drops it).
#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "filter_runner.hpp"
#include "filters/frame_stages.hpp"
#include "pipeline/light_levels.hpp"
#include "statfilter/sequence_io.hpp"
#include "synthetic.hpp"

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
    const LightLevels light = measure_light_levels(*source, 2);
    ASSERT_TRUE(light.modelled);
    const auto& levels = light.levels;
    double mean_ramp = 0;
    for (int64_t f = 0; f < kF; ++f) mean_ramp += ramp(f) / kF;
    for (int64_t f = 0; f < kF; ++f) EXPECT_NEAR(levels[static_cast<size_t>(f)], ramp(f) / mean_ramp, 1e-6) << f;
    EXPECT_NEAR(light.swing, ramp(kF - 1) / mean_ramp - 1, 1e-6);
    EXPECT_LT(light.noise, 1e-6);  // float samples
    // The levelled frames are one level; restore gives the frame back.
    const LevelledSource levelled(*source, light);
    std::vector<float> frame(static_cast<size_t>(kH * kW * kC));
    levelled.read_rows(kF - 1, 0, kH, frame.data());
    EXPECT_NEAR(frame[0], clean->at(kF - 1, 0, 0, 0) / (ramp(kF - 1) / mean_ramp), 1e-5);
    levelled.restore(kF - 1, frame.data());
    EXPECT_NEAR(frame[5], clean->at(kF - 1, 0, 1, 2), 1e-5);
    // A black frame: nothing is divided. NaN samples are left out of their block.
    auto black = lit_shot(false);
    for (int64_t y = 0; y < kH; ++y)
        for (int64_t x = 0; x < kW; ++x)
            for (int64_t c = 0; c < kC; ++c) black->at(3, y, x, c) = 0.0f;
    const LightLevels dark = measure_light_levels(*memory_source(*black), 1);
    EXPECT_FALSE(dark.modelled);
    for (double l : dark.levels) EXPECT_EQ(l, 1.0);
    auto broken = lit_shot(false);
    for (int64_t x = 0; x < kW; ++x) broken->at(2, 0, x, 0) = std::numeric_limits<float>::quiet_NaN();
    broken->at(5, 7, 7, 1) = std::numeric_limits<float>::infinity();
    const auto some = measure_light_levels(*memory_source(*broken), 1).levels;
    for (int64_t f = 0; f < kF; ++f) EXPECT_NEAR(some[static_cast<size_t>(f)], levels[static_cast<size_t>(f)], 1e-6) << f;
    // One frame, and frames smaller than the 8 x 8 blocks: the light is still, or measured.
    Sequence one(Shape{1, kH, kW, kC});
    EXPECT_EQ(measure_light_levels(*memory_source(one), 1).levels, std::vector<double>{1.0});
    Sequence tiny(Shape{kF, 1, 2, 1});
    for (int64_t f = 0; f < kF; ++f) tiny.at(f, 0, 0, 0) = tiny.at(f, 0, 1, 0) = static_cast<float>(ramp(f));
    const LightLevels small = measure_light_levels(*memory_source(tiny), 1);
    EXPECT_TRUE(small.modelled);
    EXPECT_NEAR(small.levels[0], ramp(0) / mean_ramp, 1e-6);
}

// The levels are ratios: the units of the input do not change them (1e-6 .. 1e6, and tiny values
// near the smallest normal float).
TEST(LightLevels, TheUnitsOfTheInputDoNotChangeThem) {
    const auto noisy = lit_shot(true);
    const auto base = measure_light_levels(*memory_source(*noisy), 1);
    for (double k : {1e-30, 1e-6, 1e6, 1e30}) {
        Sequence scaled(noisy->shape());
        for (int64_t f = 0; f < kF; ++f)
            for (int64_t y = 0; y < kH; ++y)
                for (int64_t x = 0; x < kW; ++x)
                    for (int64_t c = 0; c < kC; ++c) scaled.at(f, y, x, c) = static_cast<float>(k * noisy->at(f, y, x, c));
        const auto light = measure_light_levels(*memory_source(scaled), 1);
        EXPECT_EQ(light.modelled, base.modelled) << k;
        for (int64_t f = 0; f < kF; ++f) EXPECT_NEAR(light.levels[static_cast<size_t>(f)], base.levels[static_cast<size_t>(f)], 1e-5) << k;
    }
}

// A steady light is left alone, even under heavy noise and with a firefly; a firefly under a
// changing light does not move the levels (a median of blocks, not a frame's mean).
TEST(LightLevels, ASteadyLightAndAFireflyAreNotModelled) {
    auto steady = std::make_unique<Sequence>(Shape{kF, kH, kW, kC});
    std::mt19937 rng(5);
    std::gamma_distribution<double> sample(1.0, 1.0);  // 1 spp-like: 100% deviation
    for (int64_t f = 0; f < kF; ++f)
        for (int64_t y = 0; y < kH; ++y)
            for (int64_t x = 0; x < kW; ++x)
                for (int64_t c = 0; c < kC; ++c) steady->at(f, y, x, c) = static_cast<float>((0.2 + 0.6 * x / kW) * sample(rng));
    steady->at(4, 10, 10, 0) = 500.0f;
    const LightLevels still = measure_light_levels(*memory_source(*steady), 1);
    EXPECT_FALSE(still.modelled) << still.swing << " " << still.noise;
    for (double l : still.levels) EXPECT_EQ(l, 1.0);
    auto fired = lit_shot(true);
    const auto before = measure_light_levels(*memory_source(*fired), 1);
    for (int64_t c = 0; c < kC; ++c) fired->at(4, 10, 10, c) = 500.0f;
    const auto after = measure_light_levels(*memory_source(*fired), 1);
    ASSERT_TRUE(after.modelled);
    for (int64_t f = 0; f < kF; ++f)
        EXPECT_NEAR(after.levels[static_cast<size_t>(f)], before.levels[static_cast<size_t>(f)], 0.003) << f;
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

// Given renderer passes, balanced runs its method on the shot in memory (filters/auto_filter.cpp):
// the light's level is divided out there too.
TEST(LightLevels, BalancedWithPassesKeepsTheSwingToo) {
    const auto noisy = lit_shot(true), clean = lit_shot(false);
    const auto dir = std::filesystem::temp_directory_path() / ("statfilter-light-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    WriteOptions w;
    w.half = false;
    const std::string albedo = (dir / "albedo.####.exr").string();
    write_sequence(*clean, albedo, w);
    const FilterRun run = run_filter("auto", *noisy, {{"quality", "balanced"}, {"albedo", albedo}});
    EXPECT_EQ(run.filter->results().get_string("light_levels").rfind("divided out", 0), 0u);
    for (int64_t f = 0; f < kF; ++f) EXPECT_NEAR(frame_mean(*run.output, f) / frame_mean(*clean, f), 1.0, 0.02) << f;
    // A still light: the levels are not used and the run is the same as without them.
    const auto still = lit_shot(true);
    for (int64_t f = 0; f < kF; ++f)
        for (int64_t y = 0; y < kH; ++y)
            for (int64_t x = 0; x < kW; ++x)
                for (int64_t c = 0; c < kC; ++c) still->at(f, y, x, c) = static_cast<float>(still->at(f, y, x, c) / ramp(f));
    write_sequence(*lit_shot(false), albedo, w);
    const FilterRun flat = run_filter("auto", *still, {{"quality", "balanced"}, {"albedo", albedo}});
    EXPECT_EQ(flat.filter->results().get_string("light_levels").rfind("still", 0), 0u);
    EXPECT_EQ(flat.filter->results().get_string("method"), "pca then diffusion");
    const FilterRun named = run_filter("pca", *still, {{"postfilter", kRefinePostfilter}, {"postfilter_params", kRefinePostfilterParams}});
    EXPECT_EQ(max_abs_diff(*flat.output, *named.output), 0.0);
    std::filesystem::remove_all(dir);
}

// The half-width the levels of a changing light are smoothed over follows the data: a light that
// swings fast (a period of 16 frames) is followed closely; the same swing under heavy noise, over
// a wider window; and a frame's level is then closer to the truth than the fixed +-8 frames give.
TEST(LightLevels, TheSmoothingFollowsAFastLightAndAveragesANoisyOne) {
    std::vector<double> fast(32), noisy(32);
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 0.03);
    for (size_t f = 0; f < fast.size(); ++f) {
        fast[f] = 1 + 0.3 * std::sin(2 * M_PI * static_cast<double>(f) / 16);
        noisy[f] = 1 + 0.1 * static_cast<double>(f) / 31 + noise(rng);
    }
    const int h_fast = choose_light_half_width(fast), h_noisy = choose_light_half_width(noisy);
    EXPECT_LE(h_fast, 3);
    EXPECT_GE(h_noisy, 8);
    const auto chosen = smooth_light_levels(fast, h_fast), fixed = smooth_light_levels(fast, kLightLevelHalfWidth);
    double chosen_error = 0, fixed_error = 0;
    for (size_t f = 0; f < fast.size(); ++f) {
        chosen_error = std::max(chosen_error, std::fabs(chosen[f] - fast[f]));
        fixed_error = std::max(fixed_error, std::fabs(fixed[f] - fast[f]));
    }
    EXPECT_LT(chosen_error, 0.01);
    EXPECT_GT(fixed_error, 0.05);
}

// A short shot of a steady light whose frames' levels wobble by 1% (noise) is not taken for a
// changing light: the spread is measured leaving each frame out of its own fit (a fit through
// every level of a 3-frame shot had no spread, and 43% of such shots were "modelled").
TEST(LightLevels, ShortShotsOfASteadyLightAreNotModelled) {
    for (int64_t frames : {2, 3, 4, 6, 8}) {
        int modelled = 0;
        for (unsigned seed = 0; seed < 40; ++seed) {
            std::mt19937 rng(seed);
            std::normal_distribution<double> wobble(0.0, 0.01);
            Sequence shot(Shape{frames, 16, 16, 1});
            for (int64_t f = 0; f < frames; ++f) {
                const double level = 1 + wobble(rng);
                for (int64_t y = 0; y < 16; ++y)
                    for (int64_t x = 0; x < 16; ++x) shot.at(f, y, x, 0) = static_cast<float>(level * (0.5 + x / 16.0));
            }
            modelled += measure_light_levels(*memory_source(shot), 1).modelled ? 1 : 0;
        }
        EXPECT_LE(modelled, 2) << frames << " frames";
    }
}

// Every block is read whatever the frame's height (a strip centred in each row of blocks above 256
// rows; strips every 128 rows missed block rows 1, 3, 5 and 7 of a 480-row frame), only the light
// channels count, and a NaN sample is left out of its block, not the block out of the shot.
TEST(LightLevels, EveryBlockEveryLightChannelAndNoBlockLostToANaN) {
    constexpr int64_t F = 8, H = 480, W = 8;
    Sequence tall(Shape{F, H, W, 1});
    for (int64_t f = 0; f < F; ++f)
        for (int64_t y = 0; y < H; ++y) {
            const int64_t block_row = y * 8 / H;
            const bool lit = block_row == 0 || block_row % 2 == 1;  // 5 of 8 rows of blocks follow the light
            for (int64_t x = 0; x < W; ++x) tall.at(f, y, x, 0) = static_cast<float>(lit ? ramp(f) : 1.0);
        }
    const LightLevels light = measure_light_levels(*memory_source(tall), 1);
    ASSERT_TRUE(light.modelled);
    double mean_ramp = 0;
    for (int64_t f = 0; f < F; ++f) mean_ramp += ramp(f) / F;
    for (int64_t f = 0; f < F; ++f) EXPECT_NEAR(light.levels[static_cast<size_t>(f)], ramp(f) / mean_ramp, 1e-6) << f;

    // RGBA: a steady alpha of 1 neither dilutes the light's swing nor is divided.
    Sequence rgba(Shape{F, 16, 16, 4});
    rgba.channel_names() = {"R", "G", "B", "A"};
    for (int64_t f = 0; f < F; ++f)
        for (int64_t y = 0; y < 16; ++y)
            for (int64_t x = 0; x < 16; ++x) {
                for (int64_t c = 0; c < 3; ++c) rgba.at(f, y, x, c) = static_cast<float>(0.2 * ramp(f));
                rgba.at(f, y, x, 3) = 1.0f;
            }
    const auto rgba_source = memory_source(rgba);
    const LightLevels lit = measure_light_levels(*rgba_source, 1);
    ASSERT_TRUE(lit.modelled);
    EXPECT_EQ(lit.channels, (std::vector<uint8_t>{1, 1, 1, 0}));
    for (int64_t f = 0; f < F; ++f) EXPECT_NEAR(lit.levels[static_cast<size_t>(f)], ramp(f) / mean_ramp, 1e-6) << f;
    std::vector<float> frame(16 * 16 * 4);
    LevelledSource(*rgba_source, lit).read_rows(F - 1, 0, 16, frame.data());
    EXPECT_EQ(frame[3], 1.0f);
    EXPECT_NEAR(frame[0], 0.2 * mean_ramp, 1e-6);

    // One NaN in every block of one frame of a noisy shot: the levels barely move.
    auto noisy = lit_shot(true);
    const auto before = measure_light_levels(*memory_source(*noisy), 1);
    for (int64_t y = 0; y < kH; y += kH / 8)
        for (int64_t x = 0; x < kW; x += kW / 8) noisy->at(2, y, x, 0) = std::numeric_limits<float>::quiet_NaN();
    const auto after = measure_light_levels(*memory_source(*noisy), 1);
    ASSERT_TRUE(after.modelled);
    for (int64_t f = 0; f < kF; ++f)
        EXPECT_NEAR(after.levels[static_cast<size_t>(f)], before.levels[static_cast<size_t>(f)], 2e-3) << f;
}

// Fireflies do not reach the frames they are not in. Each block's level over the shot is the median
// of its frames, not their mean: with the mean, a firefly lowered its block's ratio in every frame,
// the median block of every frame changed, and five fireflies on cornell_light (4 spp) changed the
// light's smoothing from +-6 to +-4 frames, moving every pixel of the shot by up to 0.9% of the
// reference. Here a 32-frame shot under a swinging light, blocks of 4 x 3 pixels (a firefly of 500
// in one frame raises its block's mean over the shot several-fold), over several noise seeds.
TEST(LightLevels, FirefliesDoNotMoveTheOtherFramesLevels) {
    constexpr int64_t F = 32, H = 24, W = 32, C = 3;
    const std::vector<std::array<int64_t, 3>> fireflies = {{3, 2, 5}, {9, 11, 17}, {16, 6, 25}, {20, 18, 9}, {27, 21, 29}};
    int changed_width = 0;
    double worst = 0;
    for (unsigned seed = 0; seed < 8; ++seed) {
        std::mt19937 rng(seed);
        std::gamma_distribution<double> sample(4.0, 0.25);
        Sequence shot(Shape{F, H, W, C});
        for (int64_t f = 0; f < F; ++f)
            for (int64_t y = 0; y < H; ++y)
                for (int64_t x = 0; x < W; ++x)
                    for (int64_t c = 0; c < C; ++c)
                        shot.at(f, y, x, c) = static_cast<float>((1 + 0.3 * std::sin(2 * M_PI * f / 32.0)) *
                                                                 (0.2 + 0.6 * x / W) * sample(rng));
        const LightLevels before = measure_light_levels(*memory_source(shot), 1);
        for (const auto& [f, y, x] : fireflies)
            for (int64_t c = 0; c < C; ++c) shot.at(f, y, x, c) = 500.0f;
        const LightLevels after = measure_light_levels(*memory_source(shot), 1);
        ASSERT_TRUE(before.modelled && after.modelled) << seed;
        changed_width += before.half_width != after.half_width ? 1 : 0;
        for (int64_t f = 0; f < F; ++f) {
            bool lit = false;
            for (const auto& ff : fireflies) lit = lit || ff[0] == f;
            if (!lit) worst = std::max(worst, std::fabs(after.levels[f] / before.levels[f] - 1));
        }
    }
    // With each block's mean over the shot: the smoothing changed in 6 of the 8 seeds and a level by
    // up to 1.9%. With its median: none, and 0.39% at most (a firefly's own block still changes sides
    // of its frame's median, and the smoothing carries that to its neighbours).
    EXPECT_EQ(changed_width, 0);
    EXPECT_LT(worst, 0.008);
}
