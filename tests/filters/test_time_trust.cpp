// Trusting time after a prefilter (statfilter/time_trust.hpp): known answers on synthetic frames
// with a linear prefilter (a box blur, whose derivative dy/dx = 1/25 at every pixel is known), and the
// whole pipeline with a prefilter on a scene where the temporal filter ghosts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "filter_runner.hpp"
#include "moving_scenes.hpp"
#include "statfilter/time_trust.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

constexpr int64_t kW = 48, kH = 32, kC = 3;
constexpr size_t kSamples = kW * kH * kC;

// 5 x 5 box blur, clamped at the borders, in place.
void box_blur(float* frame) {
    std::vector<float> in(frame, frame + kSamples);
    for (int64_t y = 0; y < kH; ++y)
        for (int64_t x = 0; x < kW; ++x)
            for (int64_t c = 0; c < kC; ++c) {
                double sum = 0;
                for (int64_t dy = -2; dy <= 2; ++dy)
                    for (int64_t dx = -2; dx <= 2; ++dx) {
                        const int64_t yy = std::clamp<int64_t>(y + dy, 0, kH - 1), xx = std::clamp<int64_t>(x + dx, 0, kW - 1);
                        sum += in[static_cast<size_t>((yy * kW + xx) * kC + c)];
                    }
                frame[(y * kW + x) * kC + c] = static_cast<float>(sum / 25);
            }
}

struct Frames {
    std::vector<std::vector<float>> truth, noisy, prefiltered;
};

// A smooth truth seen with Gaussian noise of relative size `noise`, blurred per frame.
Frames make_frames(int64_t frames, double noise, double scale = 1) {
    Frames s;
    std::mt19937 rng(3);
    std::normal_distribution<double> n(0, noise);
    for (int64_t f = 0; f < frames; ++f) {
        std::vector<float> t(kSamples), x(kSamples);
        for (int64_t y = 0; y < kH; ++y)
            for (int64_t px = 0; px < kW; ++px)
                for (int64_t c = 0; c < kC; ++c) {
                    const size_t i = static_cast<size_t>((y * kW + px) * kC + c);
                    t[i] = static_cast<float>(scale * (1 + 0.5 * std::sin(px / 7.0 + c) * std::cos(y / 9.0)));
                    x[i] = static_cast<float>(t[i] + scale * n(rng));
                }
        std::vector<float> y = x;
        box_blur(y.data());
        s.truth.push_back(t);
        s.noisy.push_back(x);
        s.prefiltered.push_back(y);
    }
    return s;
}

double mse(const std::vector<float>& a, const std::vector<float>& b, int64_t x0 = 0, int64_t x1 = kW) {
    double sum = 0;
    int64_t n = 0;
    for (int64_t y = 0; y < kH; ++y)
        for (int64_t x = x0; x < x1; ++x)
            for (int64_t c = 0; c < kC; ++c, ++n) {
                const size_t i = static_cast<size_t>((y * kW + x) * kC + c);
                sum += (static_cast<double>(a[i]) - b[i]) * (static_cast<double>(a[i]) - b[i]);
            }
    return sum / static_cast<double>(n);
}

// Runs the trust blend over every frame; z in place.
std::vector<double> blend_all(const Frames& s, std::vector<std::vector<float>>& z, const TimeTrustOptions& options = {}) {
    const auto frames = static_cast<int64_t>(s.noisy.size());
    TimeTrust trust(Shape{frames, kH, kW, kC}, options);
    for (int64_t f = 0; f < frames; ++f)
        trust.probe(f, s.noisy[static_cast<size_t>(f)].data(), s.prefiltered[static_cast<size_t>(f)].data(), box_blur);
    for (int64_t f = 0; f < frames; ++f)
        trust.measure(f, s.noisy[static_cast<size_t>(f)].data(), s.prefiltered[static_cast<size_t>(f)].data(),
                      z[static_cast<size_t>(f)].data());
    std::vector<double> share;
    for (int64_t f = 0; f < frames; ++f)
        share.push_back(trust.blend(f, s.prefiltered[static_cast<size_t>(f)].data(), z[static_cast<size_t>(f)].data()));
    return share;
}

// A temporal result off by a ghost (+0.4) in the left half of every frame, right on the right.
std::vector<std::vector<float>> ghosted_left(std::vector<std::vector<float>> frames) {
    for (auto& frame : frames)
        for (int64_t y = 0; y < kH; ++y)
            for (int64_t x = 0; x < kW / 2; ++x)
                for (int64_t c = 0; c < kC; ++c) frame[static_cast<size_t>((y * kW + x) * kC + c)] += 0.4f;
    return frames;
}

}  // namespace

// A temporal result that is the truth is kept; one that is off by a ghost in the left half is not,
// there, and is kept on the right.
TEST(TimeTrust, KeepsWhatTheNoisyFramesSupportAndDropsAGhost) {
    const Frames s = make_frames(8, 0.3);
    std::vector<std::vector<float>> z = ghosted_left(s.truth);
    blend_all(s, z);
    for (size_t f = 0; f < z.size(); ++f) {
        const double ghost = mse(z[f], s.truth[f], 0, kW / 2 - 8), clean = mse(z[f], s.truth[f], kW / 2 + 8, kW);
        // the left: back to about the prefilter's own error, far below the ghost's 0.16
        EXPECT_LT(ghost, 1.5 * mse(s.prefiltered[f], s.truth[f], 0, kW / 2 - 8)) << "frame " << f;
        EXPECT_LT(ghost, 0.02) << "frame " << f;
        // the right: the temporal result kept (better than the prefilter alone)
        EXPECT_LT(clean, 0.3 * mse(s.prefiltered[f], s.truth[f], kW / 2 + 8, kW)) << "frame " << f;
    }
}

// The tile is the blend's resolution: one tile over the whole frame cannot drop the ghost in the left
// half and keep the true temporal result on the right, 16-pixel tiles can.
TEST(TimeTrust, TheTileSetsWhereTheGhostCanBeDropped) {
    const Frames s = make_frames(8, 0.3);
    const std::vector<std::vector<float>> ghosted = ghosted_left(s.truth);
    std::vector<std::vector<float>> fine = ghosted, whole = ghosted;
    TimeTrustOptions one_tile;
    one_tile.tile = 4 * std::max(kW, kH);
    blend_all(s, fine);
    blend_all(s, whole, one_tile);
    for (size_t f = 0; f < fine.size(); ++f)
        EXPECT_GT(mse(whole[f], s.truth[f], kW / 2 + 8, kW), 2 * mse(fine[f], s.truth[f], kW / 2 + 8, kW)) << "frame " << f;
}

// Without Stein's correction the fit would prefer the prefilter (made from the same noisy frame) even
// where the temporal result is the truth: the share stays near 1 there.
TEST(TimeTrust, SteinsCorrectionLetsATrueTemporalResultThrough) {
    const Frames s = make_frames(6, 0.5);
    std::vector<std::vector<float>> z = s.truth;
    for (double share : blend_all(s, z)) EXPECT_GT(share, 0.85);
}

namespace {

// A temporal result that is right on even frames and 10% too bright on odd ones: a fit that changes
// from frame to frame, so the pooled shares differ with the pool.
std::vector<float> biased_truth(const Frames& s, int64_t f) {
    std::vector<float> z = s.truth[static_cast<size_t>(f)];
    if (f % 2)
        for (float& v : z) v *= 1.1f;
    return z;
}

// Every frame probed (the prefilter: box_blur) and measured with the noisy frame itself as the
// "temporal result" (a temporal filter that removed nothing); with `temporal`, that result's own
// dependence probed too: the temporal result of the probe's frame is that frame.
void probe_and_measure_itself(TimeTrust& trust, const Frames& s, bool temporal) {
    const auto frames = static_cast<int64_t>(s.noisy.size());
    for (int64_t f = 0; f < frames; ++f)
        trust.probe(f, s.noisy[static_cast<size_t>(f)].data(), s.prefiltered[static_cast<size_t>(f)].data(), box_blur);
    if (temporal)
        for (int64_t f = 0; f < frames; ++f) {
            std::vector<float> probed = s.noisy[static_cast<size_t>(f)];
            trust.perturb_rows(f, 0, kH, probed.data());
            trust.probe_temporal(f, s.noisy[static_cast<size_t>(f)].data(), s.prefiltered[static_cast<size_t>(f)].data(),
                                 s.noisy[static_cast<size_t>(f)].data(), probed.data());
        }
    for (int64_t f = 0; f < frames; ++f)
        trust.measure(f, s.noisy[static_cast<size_t>(f)].data(), s.prefiltered[static_cast<size_t>(f)].data(),
                      s.noisy[static_cast<size_t>(f)].data());
}

}  // namespace

// A temporal result made from the noisy frame itself (here: the noisy frame, a temporal filter that
// removed nothing) depends on it as the prefilter does. Counting only the prefilter's dependence, the
// fit takes it for support and keeps the noise; counting both (probe_temporal, with the temporal
// result of the probe's frames), it falls back to the prefiltered frame.
TEST(TimeTrust, ATemporalResultMadeFromTheNoisyFrameCountsItsOwnDependence) {
    const Frames s = make_frames(6, 0.3);
    const auto frames = static_cast<int64_t>(s.noisy.size());
    for (const bool both : {false, true}) {
        TimeTrust trust(Shape{frames, kH, kW, kC});
        probe_and_measure_itself(trust, s, both);
        for (int64_t f = 0; f < frames; ++f) {
            std::vector<float> z = s.noisy[static_cast<size_t>(f)];
            const double share = trust.blend(f, s.prefiltered[static_cast<size_t>(f)].data(), z.data());
            const double error = mse(z, s.truth[static_cast<size_t>(f)]);
            if (both) {
                EXPECT_LT(share, 0.2) << "frame " << f;
                EXPECT_LT(error, 1.5 * mse(s.prefiltered[static_cast<size_t>(f)], s.truth[static_cast<size_t>(f)])) << "frame " << f;
            } else {
                EXPECT_GT(share, 0.8) << "frame " << f;
                EXPECT_GT(error, 0.5 * mse(s.noisy[static_cast<size_t>(f)], s.truth[static_cast<size_t>(f)])) << "frame " << f;
            }
        }
    }
}

// The temporal result's dependence counts only where the stage says it followed the motion
// (set_motion_path, with TemporalProbe::WhereMoving): with the same "temporal result" as above (the
// noisy frame itself), the left 16 columns, reach 1, fall back to the prefiltered frame as with the
// full term; the right 32, reach 0, keep the noise as without it. Tile borders at 16 pixels, so each
// tile is wholly one or the other.
TEST(TimeTrust, TheTemporalResultsDependenceCountsWhereTheStageFollowedTheMotion) {
    const Frames s = make_frames(6, 0.3);
    const auto frames = static_cast<int64_t>(s.noisy.size());
    TimeTrustOptions options;
    options.temporal_probe = TimeTrustOptions::TemporalProbe::WhereMoving;
    TimeTrust trust(Shape{frames, kH, kW, kC}, options);
    std::vector<float> reach(static_cast<size_t>(kH * kW), 0.0f);
    for (int64_t y = 0; y < kH; ++y)
        for (int64_t x = 0; x < 16; ++x) reach[static_cast<size_t>(y * kW + x)] = 1.0f;
    trust.set_motion_path(reach);
    EXPECT_THROW(trust.set_motion_path(std::vector<float>(7, 1.0f)), Error);
    probe_and_measure_itself(trust, s, true);
    // The mean squared distance of columns [x0, x1) of a frame from another's.
    const auto part = [](const std::vector<float>& a, const std::vector<float>& b, int64_t x0, int64_t x1) {
        double sum = 0;
        for (int64_t y = 0; y < kH; ++y)
            for (int64_t x = x0; x < x1; ++x)
                for (int64_t c = 0; c < kC; ++c) {
                    const auto i = static_cast<size_t>((y * kW + x) * kC + c);
                    sum += (static_cast<double>(a[i]) - b[i]) * (static_cast<double>(a[i]) - b[i]);
                }
        return sum / static_cast<double>(kH * (x1 - x0) * kC);
    };
    for (int64_t f = 0; f < frames; ++f) {
        const auto& noisy = s.noisy[static_cast<size_t>(f)];
        const auto& prefiltered = s.prefiltered[static_cast<size_t>(f)];
        std::vector<float> z = noisy;
        trust.blend(f, prefiltered.data(), z.data());
        // Left (reach 1): nearer the prefiltered frame than the noisy one; right (reach 0): the reverse.
        // The blend interpolates w between tile centres, so the columns next to the border are left out.
        EXPECT_LT(part(z, prefiltered, 0, 8), 0.25 * part(z, noisy, 0, 8)) << "frame " << f;
        EXPECT_LT(part(z, noisy, 32, kW), 0.25 * part(z, prefiltered, 32, kW)) << "frame " << f;
    }
}

// Where the stage followed no motion in a tile (set_motion_path zero on all its pixels), the fit is
// pooled over still_pool frames either side, elsewhere over pool: with the left tile on the path,
// its columns are those of a blend pooled over 2 frames, the other two tiles' those of one pooled
// over 6, to the bit (same sums, same order); and the two differ there, so the pool is seen.
TEST(TimeTrust, AFitOffTheMotionPathPoolsOverStillPoolFrames) {
    const Frames s = make_frames(14, 0.3);
    const auto frames = static_cast<int64_t>(s.noisy.size());
    const auto run = [&](int64_t pool, int64_t still_pool, bool path) {
        TimeTrustOptions options;
        options.pool = pool;
        options.still_pool = still_pool;
        TimeTrust trust(Shape{frames, kH, kW, kC}, options);
        if (path) {
            std::vector<float> weight(static_cast<size_t>(kH * kW), 0.0f);
            for (int64_t y = 0; y < kH; ++y) weight[static_cast<size_t>(y * kW + 3)] = 0.5f;  // one column of tile 0
            trust.set_motion_path(weight);
        }
        for (int64_t f = 0; f < frames; ++f)
            trust.probe(f, s.noisy[static_cast<size_t>(f)].data(), s.prefiltered[static_cast<size_t>(f)].data(), box_blur);
        for (int64_t f = 0; f < frames; ++f)  // the temporal result: the truth, biased on odd frames
            trust.measure(f, s.noisy[static_cast<size_t>(f)].data(), s.prefiltered[static_cast<size_t>(f)].data(),
                          biased_truth(s, f).data());
        std::vector<std::vector<float>> out;
        for (int64_t f = 0; f < frames; ++f) {
            out.push_back(biased_truth(s, f));
            trust.blend(f, s.prefiltered[static_cast<size_t>(f)].data(), out.back().data());
        }
        return out;
    };
    const auto mixed = run(2, 6, true), narrow = run(2, 2, false), wide = run(6, 6, false);
    // Columns [0, 8) take tile 0 alone, [24, 48) only tiles 1 and 2 (the blend interpolates between centres).
    double apart = 0;
    for (int64_t f = 0; f < frames; ++f)
        for (int64_t y = 0; y < kH; ++y)
            for (int64_t x = 0; x < kW; ++x)
                for (int64_t c = 0; c < kC; ++c) {
                    const auto i = static_cast<size_t>((y * kW + x) * kC + c);
                    const auto g = static_cast<size_t>(f);
                    if (x < 8) ASSERT_EQ(mixed[g][i], narrow[g][i]) << "frame " << f << " x " << x;
                    if (x >= 24) {
                        ASSERT_EQ(mixed[g][i], wide[g][i]) << "frame " << f << " x " << x;
                        apart = std::max(apart, std::fabs(static_cast<double>(wide[g][i]) - narrow[g][i]));
                    }
                }
    EXPECT_GT(apart, 1e-3);
}

// The share depends on the data, not its units; zero in gives zero out.
TEST(TimeTrust, ScaleEquivariantAndZeroSafe) {
    std::vector<std::vector<float>> reference;
    for (double k : {1e-6, 1.0, 1e6}) {
        const Frames s = make_frames(5, 0.3, k);
        std::vector<std::vector<float>> z = s.truth;
        for (auto& frame : z)
            for (size_t i = 0; i < frame.size(); i += 7) frame[i] += static_cast<float>(0.3 * k);
        blend_all(s, z);
        if (reference.empty()) {
            reference = z;
            for (auto& frame : reference)
                for (float& v : frame) v = static_cast<float>(v / k);
            continue;
        }
        for (size_t f = 0; f < z.size(); ++f)
            for (size_t i = 0; i < z[f].size(); ++i)
                ASSERT_NEAR(z[f][i] / k, reference[f][i], 1e-4 * std::abs(reference[f][i]) + 1e-6) << "k " << k;
    }
    Frames zero;
    zero.truth = zero.noisy = zero.prefiltered = std::vector<std::vector<float>>(3, std::vector<float>(kSamples, 0.0f));
    std::vector<std::vector<float>> z = zero.truth;
    for (double share : blend_all(zero, z)) EXPECT_TRUE(std::isfinite(share));
    for (const auto& frame : z)
        for (float v : frame) ASSERT_EQ(v, 0.0f);
}

// Through a filter: pca after a diffusion prefilter ghosts behind a camera pan; with the trust blend
// the error is lower, and off it is what it was.
TEST(TimeTrust, ThroughTheFilterLowersTheErrorWhereThePcaGhosts) {
    const Pan scene = pan_scene(12, 32, 48, 2, 0.3);
    const std::map<std::string, std::string> base = {{"rank", "1"}, {"prefilter", "diffusion"}};
    auto with = base, without = base;
    with["prefilter_trust"] = "1";
    without["prefilter_trust"] = "0";
    const FilterRun on = run_filter("pca", *scene.noisy, with), off = run_filter("pca", *scene.noisy, without);
    auto error = [&](const Sequence& out) {
        double sum = 0;
        const Shape& sh = out.shape();
        for (int64_t f = 0; f < sh.frames; ++f)
            for (int64_t y = 0; y < sh.height; ++y)
                for (int64_t x = 0; x < sh.width; ++x)
                    for (int64_t c = 0; c < sh.channels; ++c) {
                        const double d = out.at(f, y, x, c) - scene.clean->at(f, y, x, c);
                        sum += d * d;
                    }
        return sum;
    };
    EXPECT_LT(error(*on.output), 0.7 * error(*off.output));
    EXPECT_GE(on.result("prefilter_trust.share"), 0.0);
    EXPECT_LT(on.result("prefilter_trust.share"), 0.9);
    EXPECT_FALSE(off.filter->results().has("prefilter_trust.share"));
}

// A firefly of one noisy frame is no witness: left out of its tile's fit, it does not pull the frames
// pooled with it back towards their prefiltered frames. Before, its one sample outweighed every other
// of the pool and moved the neighbouring frames' output by several per cent. The prefilter here keeps
// a tenth of it where it fell (a denoiser removes most of a firefly; OIDN spreads little of it).
TEST(TimeTrust, AFireflyDoesNotMoveTheFramesPooledWithIt) {
    const Frames clean = make_frames(8, 0.3);
    Frames hit = clean;
    const size_t firefly = static_cast<size_t>((10 * kW + 20) * kC + 1);
    hit.noisy[3][firefly] = 500.0f;
    hit.prefiltered[3][firefly] += 50.0f;
    std::vector<std::vector<float>> before = clean.truth, after = clean.truth;
    blend_all(clean, before);
    blend_all(hit, after);
    for (size_t f = 0; f < after.size(); ++f) {
        if (f == 3) continue;
        double worst = 0;
        for (size_t i = 0; i < kSamples; ++i)
            worst = std::max(worst, std::fabs(static_cast<double>(after[f][i]) - before[f][i]) / clean.truth[f][i]);
        EXPECT_LE(worst, 0.01) << "frame " << f;
    }
    // With no sample left out (outlier_z 0) the same firefly moves them: the test can fail.
    TimeTrustOptions all;
    all.outlier_z = 0;
    std::vector<std::vector<float>> kept = clean.truth, base = clean.truth;
    blend_all(clean, base, all);
    blend_all(hit, kept, all);
    double moved = 0;
    for (size_t f : {size_t{2}, size_t{4}})
        for (size_t i = 0; i < kSamples; ++i)
            moved = std::max(moved, std::fabs(static_cast<double>(kept[f][i]) - base[f][i]) / clean.truth[f][i]);
    EXPECT_GT(moved, 0.02);
}
