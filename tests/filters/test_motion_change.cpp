// Motion alpha misses: a small ball crossing each pixel in a frame or two. The temporal-change test
// flags its path and nothing on pure noise (with fireflies) or under a global light change; the
// renderer's vectors and albedo pass mark what moves; the hybrid and auto decide "moving" from them,
// and auto hands the vectors on to the hybrid.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "filter_runner.hpp"
#include "filters/own_first_pass.hpp"
#include "statfilter/motion.hpp"
#include "statfilter/sequence_io.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

constexpr int64_t kFrames = 32, kHeight = 48, kWidth = 64;

// A lit wall (smooth, about 1) with multiplicative noise of relative sigma `noise`, its light scaled by
// 1 + light_swing * sin(frame) (a global light change), and optionally a bright ball of radius 5 that
// crosses the frame at 8 pixels a frame and bounces back.
std::unique_ptr<Sequence> wall(double noise, double light_swing, bool ball, unsigned seed = 3) {
    auto s = std::make_unique<Sequence>(Shape{kFrames, kHeight, kWidth, 3});
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0, 1);
    for (int64_t f = 0; f < kFrames; ++f) {
        const double light = 1 + light_swing * std::sin(2 * M_PI * f / kFrames);
        const int64_t leg = (8 * f) % 112;
        const double bx = 4 + (leg < 56 ? leg : 112 - leg), by = 24;
        for (int64_t y = 0; y < kHeight; ++y)
            for (int64_t x = 0; x < kWidth; ++x) {
                const bool on_ball = ball && std::hypot(x - bx, y - by) <= 5;
                const double clean = on_ball ? 4.0 : light * (0.8 + 0.4 * std::sin(x / 9.0) * std::cos(y / 7.0));
                for (int64_t c = 0; c < 3; ++c) s->at(f, y, x, c) = static_cast<float>(std::max(0.0, clean * (1 + noise * n(rng))));
            }
    }
    return s;
}

double share(const Sequence& map) {
    double sum = 0;
    for (int64_t y = 0; y < map.shape().height; ++y)
        for (int64_t x = 0; x < map.shape().width; ++x) sum += map.at(0, y, x, 0);
    return sum / static_cast<double>(map.shape().pixels());
}

}  // namespace

TEST(TemporalChange, FlagsAFastBallAndNotNoiseOrLight) {
    const auto ball = motion_from_temporal_change(*wall(0.5, 0.0, true), {});
    // The ball's path: rows 19-29 between the bounces; the map covers most of it and little else.
    int64_t on_path = 0, path = 0, off_path = 0;
    for (int64_t y = 0; y < kHeight; ++y)
        for (int64_t x = 0; x < kWidth; ++x) {
            const bool in = y >= 20 && y <= 28 && x >= 6 && x <= 58;
            path += in;
            on_path += in && ball->at(0, y, x, 0) > 0;
            off_path += !(y >= 16 && y <= 32) && ball->at(0, y, x, 0) > 0;
        }
    EXPECT_GT(on_path, path * 8 / 10);
    EXPECT_EQ(off_path, 0);

    auto noisy = wall(0.5, 0.0, false);
    // Fireflies: single samples 200 times the wall in a few frames.
    for (int64_t f = 0; f < kFrames; f += 3) noisy->at(f, (7 * f) % kHeight, (13 * f) % kWidth, 1) = 200.0f;
    EXPECT_EQ(share(*motion_from_temporal_change(*noisy, {})), 0.0);
    EXPECT_EQ(share(*motion_from_temporal_change(*wall(0.05, 0.35, false), {})), 0.0);  // a light swing is not motion
    EXPECT_EQ(share(*motion_from_temporal_change(*wall(0.0, 0.0, false), {})), 0.0);   // noise-free and still
    EXPECT_GT(share(*motion_from_temporal_change(*wall(0.0, 0.0, true), {})), 0.1);    // noise-free ball
    // Extremes: two frames, all zero.
    Sequence two(Shape{2, 8, 8, 1}), zero(Shape{5, 8, 8, 1});
    EXPECT_EQ(share(*motion_from_temporal_change(two, {})), 0.0);
    EXPECT_EQ(share(*motion_from_temporal_change(zero, {})), 0.0);
}

TEST(TemporalChange, TheHybridAndAutoSeeTheBall) {
    const auto ball = wall(0.5, 0.0, true);
    const FilterRun alpha_only = run_filter("hybrid", *ball, {{"change_z", "0"}});
    const FilterRun hybrid = run_filter("hybrid", *ball);
    EXPECT_GT(hybrid.result("motion_fraction"), alpha_only.result("motion_fraction") + 0.05);
    EXPECT_GT(hybrid.result("aligned_fraction"), 0.1);
    const FilterRun chosen = run_filter("auto", *ball);
    EXPECT_EQ(chosen.filter->results().get_string("method"), "hybrid then diffusion");
    // A light swing over a still wall stays a still scene.
    const FilterRun light = run_filter("auto", *wall(0.2, 0.35, false));
    EXPECT_EQ(light.filter->results().get_string("method"), "pca then diffusion");
}

// A dark disc rests on the noisy wall in the first frame only: the test counts one departing frame at
// its pixels (none elsewhere), and of frame 0 a model that lacks the disc misses exactly there while a
// model that has it (the clean frame) misses nothing; a sustained change counts every frame it lasts.
TEST(TemporalChange, CountsDeparturesAndFindsWhereAModelMisses) {
    auto noisy = wall(0.3, 0.0, false), clean = wall(0.0, 0.0, false);
    const auto disc = [](int64_t y, int64_t x) { return std::hypot(x - 30.0, y - 24.0) <= 6; };
    for (Sequence* s : {noisy.get(), clean.get()})
        for (int64_t y = 0; y < kHeight; ++y)
            for (int64_t x = 0; x < kWidth; ++x)
                if (disc(y, x))
                    for (int64_t c = 0; c < 3; ++c) s->at(0, y, x, c) *= 0.1f;
    const auto change = temporal_change_test(*noisy, {});
    const int64_t P = kHeight * kWidth, C = 3;
    int64_t inside = 0, counted = 0, outside = 0;
    for (int64_t p = 0; p < P; ++p) {
        const uint32_t d = change->departures()[static_cast<size_t>(p)];
        if (disc(p / kWidth, p % kWidth) && std::hypot(p % kWidth - 30.0, p / kWidth - 24.0) <= 3) {
            ++inside;
            counted += d == 1;
        } else if (!disc(p / kWidth, p % kWidth)) {
            outside += d > 0;
        }
    }
    EXPECT_EQ(counted, inside);  // the disc's core: one frame each
    EXPECT_EQ(outside, 0);
    // Frame 0 against models of it: the wall without the disc, and the clean frame with it.
    std::vector<float> frame(static_cast<size_t>(P * C)), without(frame.size()), with(frame.size());
    const auto still = wall(0.0, 0.0, false);
    for (int64_t p = 0; p < P; ++p)
        for (int64_t c = 0; c < C; ++c) {
            frame[static_cast<size_t>(p * C + c)] = noisy->at(0, p / kWidth, p % kWidth, c);
            without[static_cast<size_t>(p * C + c)] = still->at(0, p / kWidth, p % kWidth, c);
            with[static_cast<size_t>(p * C + c)] = clean->at(0, p / kWidth, p % kWidth, c);
        }
    std::vector<uint8_t> misses;
    change->model_misses(0, frame.data(), without.data(), misses);
    int64_t missed_core = 0, missed_outside = 0;
    for (int64_t p = 0; p < P; ++p) {
        const double r = std::hypot(p % kWidth - 30.0, p / kWidth - 24.0);
        missed_core += r <= 3 && misses[static_cast<size_t>(p)];
        missed_outside += r > 6 && misses[static_cast<size_t>(p)];
    }
    EXPECT_EQ(missed_core, inside);
    EXPECT_EQ(missed_outside, 0);
    change->model_misses(0, frame.data(), with.data(), misses);
    EXPECT_EQ(std::count(misses.begin(), misses.end(), uint8_t{1}), 0);
    // The disc staying from frame 20 on: departures count its 12 frames.
    auto late = wall(0.3, 0.0, false);
    for (int64_t f = 20; f < kFrames; ++f)
        for (int64_t y = 0; y < kHeight; ++y)
            for (int64_t x = 0; x < kWidth; ++x)
                if (disc(y, x))
                    for (int64_t c = 0; c < 3; ++c) late->at(f, y, x, c) *= 0.1f;
    EXPECT_EQ(temporal_change_test(*late, {})->departures()[static_cast<size_t>(24 * kWidth + 30)], 12u);
}

// The ball crosses each pixel of its path in a frame or two: no temporal basis follows that, so I_T
// ghosts there, and a first pass made from I_T would steer the flow to the ghost. Where the change
// test saw what alpha did not, the first pass is the frame's own diffusion (and only there: not under
// a light swing). On the ball's path the hybrid stays better than diffusing each frame alone, on the
// still wall far better. (On this bright ball the flow finds it either way; tests/filters/
// test_real_renders.cpp has the render where the old first pass doubled the moving region's error.)
TEST(TemporalChange, TheHybridDoesNotGhostAFastBall) {
    const auto noisy = wall(0.5, 0.0, true), clean = wall(0.0, 0.0, true);
    const FilterRun hybrid = run_filter("hybrid", *noisy);
    const FilterRun alone = run_filter("diffusion", *noisy);
        EXPECT_GT(hybrid.result("own_first_pass_fraction"), 0.05);
    const auto error = [&](const Sequence& out, bool on_path) {
        double sum = 0;
        int64_t n = 0;
        for (int64_t f = 0; f < kFrames; ++f)
            for (int64_t y = 0; y < kHeight; ++y)
                for (int64_t x = 0; x < kWidth; ++x) {
                    if ((y >= 16 && y <= 32) != on_path) continue;
                    for (int64_t c = 0; c < 3; ++c) {
                        const double r = clean->at(f, y, x, c), d = out.at(f, y, x, c) - r;
                        sum += d * d / (r * r + 1e-2);
                        ++n;
                    }
                }
        return sum / static_cast<double>(n);
    };
    EXPECT_LT(error(*hybrid.output, true), error(*alone.output, true));
    EXPECT_LT(error(*hybrid.output, false), 0.5 * error(*alone.output, false));
    // A light swing over a still wall is no change: I_T stays the first pass everywhere.
    const FilterRun light = run_filter("hybrid", *wall(0.2, 0.35, false), {{"still_fraction", "0"}});
        EXPECT_EQ(light.result("own_first_pass_fraction"), 0.0);
}

// Vectors mark the pixels they carry half a pixel or more over the shot when vector_drift asks them
// to; the hybrid and auto take them as the input "vectors" (auto hands them on to the hybrid, which
// aligns along them). By default they only align: a wall whose light does not change stays a still
// scene however far its vectors say it slides.
TEST(MotionVectors, MarkWhatMovesAndReachTheHybridThroughAuto) {
    Sequence vectors(Shape{kFrames, kHeight, kWidth, 4});
    for (int64_t f = 0; f < kFrames; ++f)
        for (int64_t y = 0; y < 10; ++y)
            for (int64_t x = 0; x < kWidth; ++x) vectors.at(f, y, x, 2) = y < 5 ? 0.1f : 0.01f;  // 3.1 and 0.31 px
    const auto map = motion_from_vectors(vectors, 0.5);
    EXPECT_EQ(map->at(0, 2, 7, 0), 1.0f);
    EXPECT_EQ(map->at(0, 7, 7, 0), 0.0f);
    EXPECT_NEAR(share(*map), 5.0 / kHeight, 1e-9);
    Sequence three(Shape{kFrames, kHeight, kWidth, 3});
    EXPECT_THROW(motion_from_vectors(three, 0.5), Error);

    const auto still = wall(0.2, 0.0, false);
    Sequence out(still->shape());
    auto aligning = create_filter("auto");
    aligning->set_input("vectors", &vectors);
    aligning->execute(*still, out, Progress());
    EXPECT_EQ(aligning->results().get_string("method"), "pca then diffusion");
    auto filter = create_filter("auto");
    filter->params().set_string("vector_drift", "0.5");
    filter->set_input("vectors", &vectors);
    filter->execute(*still, out, Progress());
    EXPECT_EQ(filter->results().get_string("method"), "hybrid then diffusion");
    EXPECT_EQ(filter->results().get_string("hybrid.motion_compensation"), "the renderer's motion vectors");
    EXPECT_THROW(filter->set_input("vector", &vectors), Error);
    // The vectors' size must match the input's.
    Sequence small(Shape{kFrames, 8, 8, 4});
    auto hybrid = create_filter("hybrid");
    hybrid->set_input("vectors", &small);
    EXPECT_THROW(hybrid->execute(*still, out, Progress()), Error);
}

// The albedo pass says where geometry moves even when the indirect light barely shows it: a dark
// square the light does not tell apart slides across the albedo; the hybrid's moving share rises
// from (about) nothing to the square's path.
TEST(MotionPasses, TheAlbedoPassSaysWhereThingsMove) {
    const auto still = wall(0.2, 0.0, false);
    Sequence albedo(Shape{kFrames, kHeight, kWidth, 3});
    for (int64_t f = 0; f < kFrames; ++f)
        for (int64_t y = 0; y < kHeight; ++y)
            for (int64_t x = 0; x < kWidth; ++x)
                for (int64_t c = 0; c < 3; ++c)
                    albedo.at(f, y, x, c) = (y >= 10 && y < 20 && x >= 2 * f && x < 2 * f + 10) ? 0.1f : 0.8f;
    const auto dir = std::filesystem::temp_directory_path() / ("statfilter-passes-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    WriteOptions w;
    w.half = false;
    const std::string pattern = (dir / "albedo.####.exr").string();
    write_sequence(albedo, pattern, w);
    const FilterRun with_pass = run_filter("hybrid", *still, {{"albedo", pattern}});
    std::filesystem::remove_all(dir);
    const FilterRun without = run_filter("hybrid", *still);
    EXPECT_LT(without.result("motion_fraction"), 0.01);
    EXPECT_GT(with_pass.result("motion_fraction"), 0.1);
}

// Hysteresis: a faint change (scores between grow_z and z_threshold) moves where it joins a strong
// one, as the rim of an object's path does, and not where it stands alone, as chance does in a still
// region. Without growing neither faint patch moves; a plain low threshold takes both.
TEST(TemporalChange, GrowsFromAStrongChangeIntoAFaintOneButNotIntoAFaintOneAlone) {
    auto s = wall(0.3, 0.0, false);
    const auto darken = [&](int64_t f, int64_t y0, int64_t y1, int64_t x0, int64_t x1, float by) {
        for (int64_t y = y0; y < y1; ++y)
            for (int64_t x = x0; x < x1; ++x)
                for (int64_t c = 0; c < 3; ++c) s->at(f, y, x, c) *= by;
    };
    const float faint = 0.8f;  // scores between 3 and 5 (a 20% darker patch)
    darken(8, 10, 22, 6, 18, 0.1f);      // strong, in frame 8
    darken(8, 10, 22, 18, 30, faint);    // faint, joined to it
    darken(20, 28, 40, 44, 56, faint);   // faint, alone, in frame 20
    const auto flagged = [](const Sequence& map, int64_t y0, int64_t y1, int64_t x0, int64_t x1) {
        double sum = 0;
        for (int64_t y = y0; y < y1; ++y)
            for (int64_t x = x0; x < x1; ++x) sum += map.at(0, y, x, 0);
        return sum / static_cast<double>((y1 - y0) * (x1 - x0));
    };
    const auto run = [&](double z, double grow) {
        TemporalChangeOptions o;
        o.z_threshold = z, o.grow_z = grow;
        return motion_from_temporal_change(*s, o);
    };
    // Inner parts of each patch (the 5 x 5 medians blur their edges), and noise-only rows.
    const auto strong = [&](const Sequence& m) { return flagged(m, 12, 20, 8, 16); };
    const auto joined = [&](const Sequence& m) { return flagged(m, 12, 20, 21, 28); };
    const auto alone = [&](const Sequence& m) { return flagged(m, 30, 38, 46, 54); };
    const auto rest = [&](const Sequence& m) { return flagged(m, 42, 48, 0, 64); };
    const auto grown = run(5, 3), plain = run(5, 0), low = run(3, 0);
    EXPECT_GT(strong(*grown), 0.95);
    EXPECT_GT(joined(*grown), 0.6);
    EXPECT_EQ(alone(*grown), 0.0);
    EXPECT_EQ(rest(*grown), 0.0);
    EXPECT_GT(strong(*plain), 0.95);
    EXPECT_EQ(joined(*plain), 0.0);
    EXPECT_EQ(alone(*plain), 0.0);
    // A plain threshold of 3 finds both faint patches, and lone noisy pixels with them.
    EXPECT_GT(joined(*low), 0.6);
    EXPECT_GT(alone(*low), 0.6);
    EXPECT_GT(rest(*low), 0.0);
    EXPECT_EQ(rest(*plain), 0.0);
}

// The boxes the frame's own diffusion runs on hold every pixel that needs it, inside the frame, apart
// from each other, and for a moving edge cover a small part of the bounding box the pixels span.
TEST(OwnFirstPass, TheBoxesHoldEveryPixelAndLittleElse) {
    const int64_t W = 301, H = 203;
    std::vector<int64_t> pixels;
    for (int64_t y = 0; y < H; ++y)
        for (int64_t x = 0; x < W; ++x)
            if (std::abs(x - (y + 40)) < 3 || (x == W - 1 && y == H - 1) || (x == 0 && y == 0)) pixels.push_back(y * W + x);
    const std::vector<PixelBox> boxes = OwnFirstPass::boxes_around(pixels, W, H);
    int64_t area = 0;
    for (size_t i = 0; i < boxes.size(); ++i) {
        const PixelBox& b = boxes[i];
        ASSERT_TRUE(b.x0 >= 0 && b.y0 >= 0 && b.x1 <= W && b.y1 <= H && b.x0 < b.x1 && b.y0 < b.y1) << "box " << i;
        area += (b.x1 - b.x0) * (b.y1 - b.y0);
        for (size_t j = 0; j < i; ++j) {
            const PixelBox& o = boxes[j];
            EXPECT_FALSE(b.x0 < o.x1 && o.x0 < b.x1 && b.y0 < o.y1 && o.y0 < b.y1) << "boxes " << j << " and " << i;
        }
    }
    for (const int64_t p : pixels) {
        const int64_t x = p % W, y = p / W;
        EXPECT_TRUE(std::any_of(boxes.begin(), boxes.end(),
                                [&](const PixelBox& b) { return x >= b.x0 && x < b.x1 && y >= b.y0 && y < b.y1; }))
            << "pixel " << x << "," << y;
    }
    EXPECT_LT(area, W * H / 3);  // the diagonal's bounding box is the whole frame
    EXPECT_TRUE(OwnFirstPass::boxes_around({}, W, H).empty());
}
