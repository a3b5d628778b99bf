// The artifact detector on synthetic sequences whose errors are known: it finds a transient ghost
// and a steady bias, stays quiet where the denoised sequence is right, and refuses bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "statfilter/artifact_detection.hpp"
#include "statfilter/crop_windows.hpp"
#include "statfilter/error.hpp"
#include "statfilter/filter_registry.hpp"

using namespace statfilter;

namespace {

struct Scene {
    std::unique_ptr<Sequence> truth, noisy, denoised;
    std::unique_ptr<Sequence> wrong;  // 1 where the denoised sequence has an error
};

bool in_ghost(int64_t f, int64_t y, int64_t x) { return f >= 8 && f < 12 && y >= 10 && y < 20 && x >= 12 && x < 24; }
bool in_bias(int64_t y, int64_t x) { return y >= 28 && y < 36 && x >= 30 && x < 41; }

// A smooth image changing slowly over time, a noisy render of it (noise 15% of the signal), and a
// "denoised" version that is right except for a ghost in 4 frames and a steady 30% bias.
Scene make_scene(int64_t F = 24, int64_t H = 40, int64_t W = 48, bool errors = true) {
    const Shape s{F, H, W, 3};
    Scene sc;
    sc.truth = std::make_unique<Sequence>(s);
    sc.noisy = std::make_unique<Sequence>(s);
    sc.denoised = std::make_unique<Sequence>(s);
    sc.wrong = std::make_unique<Sequence>(Shape{F, H, W, 1});
    std::mt19937 rng(11);
    std::normal_distribution<double> normal;
    for (int64_t f = 0; f < F; ++f)
        for (int64_t y = 0; y < H; ++y)
            for (int64_t x = 0; x < W; ++x) {
                const bool ghost = errors && in_ghost(f, y, x), bias = errors && in_bias(y, x);
                sc.wrong->at(f, y, x, 0) = ghost || bias;
                for (int64_t c = 0; c < 3; ++c) {
                    const double v = 0.5 + 0.2 * std::sin(x / 7.0 + c) + 0.1 * std::cos(y / 5.0) + 0.05 * f / F;
                    sc.truth->at(f, y, x, c) = static_cast<float>(v);
                    sc.noisy->at(f, y, x, c) = static_cast<float>(v * (1 + 0.15 * normal(rng)));
                    double d = v * (1 + 0.005 * normal(rng));
                    if (ghost) d += 0.3;
                    if (bias) d *= 0.7;
                    sc.denoised->at(f, y, x, c) = static_cast<float>(d);
                }
            }
    return sc;
}

struct Confusion {
    double recall = 0, false_positive_rate = 0;
};

// False positives are counted away from the errors: the window average spreads an error one pixel
// (window / 2) beyond its edge, where the estimate is right to see it.
Confusion confusion(const Sequence& mask, const Sequence& wrong, int64_t margin = 1) {
    const Shape& s = mask.shape();
    double tp = 0, fn = 0, fp = 0, tn = 0;
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x) {
                const bool m = mask.at(f, y, x, 0) > 0, w = wrong.at(f, y, x, 0) > 0;
                bool near = false;
                for (int64_t dy = -margin; dy <= margin; ++dy)
                    for (int64_t dx = -margin; dx <= margin; ++dx) {
                        const int64_t yy = y + dy, xx = x + dx;
                        if (yy >= 0 && yy < s.height && xx >= 0 && xx < s.width) near |= wrong.at(f, yy, xx, 0) > 0;
                    }
                if (w)
                    (m ? tp : fn) += 1;
                else if (!near)
                    (m ? fp : tn) += 1;
            }
    return {tp / std::max(1.0, tp + fn), fp / std::max(1.0, fp + tn)};
}

}  // namespace

TEST(Detect, FindsATransientGhostAndASteadyBias) {
    const Scene sc = make_scene();
    const Detection d = detect_artifacts(*sc.denoised, sc.noisy.get(), DetectOptions{}, Progress());
    const Confusion c = confusion(*d.mask, *sc.wrong);
    std::printf("  recall %.3f, false positives %.4f, delta %.3f, noise ratio %.3f\n", c.recall,
                c.false_positive_rate, d.delta, d.noise_ratio);
    EXPECT_GT(c.recall, 0.9);
    EXPECT_LT(c.false_positive_rate, 0.01);
    // The ghost's frames are flagged, the same pixels in the other frames are not.
    int flagged_outside_ghost_frames = 0;
    for (int64_t f = 0; f < 24; ++f)
        if (f < 7 || f > 12) flagged_outside_ghost_frames += d.mask->at(f, 15, 18, 0) > 0;
    EXPECT_EQ(flagged_outside_ghost_frames, 0);
    for (int64_t f = 8; f < 12; ++f) EXPECT_EQ(d.mask->at(f, 15, 18, 0), 1.0f) << "frame " << f;
    // The automatic tolerance follows the noise: 15% noise averaged over 3x3 is about 4% relative.
    EXPECT_GE(d.delta, kDeltaFloor);
    EXPECT_GT(d.noise_ratio, 0.02);
    EXPECT_LT(d.noise_ratio, 0.08);
}

TEST(Detect, QuietWhereTheDenoisedSequenceIsRight) {
    const Scene sc = make_scene(24, 40, 48, false);
    const Detection d = detect_artifacts(*sc.denoised, sc.noisy.get(), DetectOptions{}, Progress());
    EXPECT_LT(static_cast<double>(d.flagged) / (24.0 * 40 * 48), 0.002);
    EXPECT_LT(d.mean_degree, 1.0);
}

TEST(Detect, ScoreAndMaskAgreeWithTheThreshold) {
    const Scene sc = make_scene();
    DetectOptions o;
    o.threshold = 0.05;
    const Detection d = detect_artifacts(*sc.denoised, sc.noisy.get(), o, Progress());
    int64_t count = 0;
    for (int64_t f = 0; f < 24; ++f)
        for (int64_t y = 0; y < 40; ++y)
            for (int64_t x = 0; x < 48; ++x) {
                const bool flag = d.score->at(f, y, x, 0) > 0.05f;
                EXPECT_EQ(d.mask->at(f, y, x, 0), flag ? 1.0f : 0.0f);
                count += flag;
            }
    EXPECT_EQ(count, d.flagged);
    // The degree map: D + 1 for pixels no degree explains, otherwise 0..D.
    for (int64_t y = 0; y < 40; ++y)
        for (int64_t x = 0; x < 48; ++x) {
            const float deg = d.degree_map->at(0, y, x, 0);
            EXPECT_GE(deg, 0.0f);
            EXPECT_LE(deg, 9.0f);
        }
}

TEST(Detect, ResultsDoNotDependOnTheMemoryBudget) {
    const Scene sc = make_scene();
    DetectOptions big, tiny;
    tiny.budget_bytes = 1;  // one row per band
    const Detection a = detect_artifacts(*sc.denoised, sc.noisy.get(), big, Progress());
    const Detection b = detect_artifacts(*sc.denoised, sc.noisy.get(), tiny, Progress());
    for (int64_t f = 0; f < 24; ++f)
        for (int64_t y = 0; y < 40; ++y)
            for (int64_t x = 0; x < 48; ++x) ASSERT_FLOAT_EQ(a.score->at(f, y, x, 0), b.score->at(f, y, x, 0));
    EXPECT_EQ(a.flagged, b.flagged);
}

TEST(Detect, DenoisedSourceAloneFindsASpike) {
    // The study's form: the regression sees the denoised sequence only; a one-frame spike is what no
    // low degree explains.
    const Scene sc = make_scene(24, 20, 20, false);
    sc.denoised->at(5, 10, 10, 0) += 2.0f;
    sc.denoised->at(5, 10, 10, 1) += 2.0f;
    sc.denoised->at(5, 10, 10, 2) += 2.0f;
    DetectOptions o;
    o.source = DetectSource::Denoised;
    o.window = 1;
    const Detection d = detect_artifacts(*sc.denoised, nullptr, o, Progress());
    EXPECT_EQ(d.mask->at(5, 10, 10, 0), 1.0f);
    // A polynomial that fits part of a spike rings into the frames next to it (one reason this source
    // finds fewer real errors than the residual one); frames far from it are clean.
    for (int64_t f = 12; f < 24; ++f) EXPECT_EQ(d.mask->at(f, 10, 10, 0), 0.0f) << f;
    EXPECT_DOUBLE_EQ(d.delta, kDeltaDenoisedOnly);
}

TEST(Detect, BadInputIsRefusedClearly) {
    const Scene sc = make_scene(6, 8, 8);
    DetectOptions o;
    o.degree = 6;
    try {
        detect_artifacts(*sc.denoised, sc.noisy.get(), o, Progress());
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("degree 6 needs at least 7 frames; the sequence has 6"), std::string::npos)
            << e.what();
    }
    Sequence other(Shape{6, 8, 9, 3});
    EXPECT_THROW(detect_artifacts(*sc.denoised, &other, DetectOptions{}, Progress()), Error);
    EXPECT_THROW(detect_artifacts(*sc.denoised, nullptr, DetectOptions{}, Progress()), Error);  // residual needs noisy
    o = DetectOptions{};
    o.degree = 3;
    sc.noisy->at(2, 3, 4, 1) = std::nanf("");
    try {
        detect_artifacts(*sc.denoised, sc.noisy.get(), o, Progress());
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Numeric);
    }
}

TEST(Detect, OneFrameAndConstantSequences) {
    // One frame: degree 0 only; the constant residual is explained at degree 0.
    const Scene one = make_scene(1, 8, 8, false);
    DetectOptions o;
    o.degree = 0;
    const Detection d = detect_artifacts(*one.denoised, one.noisy.get(), o, Progress());
    EXPECT_EQ(d.score->shape().frames, 1);
    // Constant and equal: nothing to flag, no NaN.
    Sequence a(Shape{5, 4, 4, 1}), b(Shape{5, 4, 4, 1});
    o.degree = 2;
    const Detection z = detect_artifacts(a, &b, o, Progress());
    EXPECT_EQ(z.flagged, 0);
    for (int64_t f = 0; f < 5; ++f) EXPECT_EQ(z.score->at(f, 1, 1, 0), 0.0f);
}

TEST(DetectFilter, RunsThroughTheRegistryWithANamedNoisyInput) {
    const Scene sc = make_scene();
    auto filter = create_filter("detect");
    EXPECT_THROW(filter->set_input("albedo", sc.noisy.get()), Error);
    filter->set_input("noisy", sc.noisy.get());
    Sequence out(sc.denoised->shape());
    filter->execute(*sc.denoised, out, Progress());
    const Results& r = filter->results();
    EXPECT_EQ(r.get_string("source"), "residual");
    EXPECT_GT(r.get_float("flagged_fraction"), 0.005);
    EXPECT_GE(r.get_float("window_fraction"), r.get_float("flagged_fraction"));
    const CropPlan plan = crop_plan_from_json(r.get_string("crops"));
    EXPECT_EQ(plan.width, 48);
    EXPECT_EQ(plan.height, 40);
    EXPECT_EQ(static_cast<double>(plan.flagged()), r.get_float("flagged_pixel_frames"));
    EXPECT_EQ(r.image("mask")->shape(), (Shape{24, 40, 48, 1}));
    EXPECT_EQ(r.image("degree_map")->shape(), (Shape{1, 40, 48, 1}));
    // The output is the input, unchanged.
    for (int64_t c = 0; c < 3; ++c) EXPECT_EQ(out.at(3, 4, 5, c), sc.denoised->at(3, 4, 5, c));
    // Without the noisy input, source=auto falls back to the denoised sequence alone.
    filter->set_input("noisy", nullptr);
    filter->execute(*sc.denoised, out, Progress());
    EXPECT_EQ(filter->results().get_string("source"), "denoised");
    filter->params().set_string("source", "residual");
    EXPECT_THROW(filter->execute(*sc.denoised, out, Progress()), Error);
}
