// Motion maps and the hybrid: known moving objects, a global light change that is not motion, and
// the extremes (no motion, everything moving, one frame).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <map>
#include <random>

#include "filter_runner.hpp"
#include "filters/frame_stages.hpp"
#include "synthetic.hpp"
#include "statfilter/error.hpp"
#include "statfilter/motion.hpp"
#include "statfilter/sequence_io.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

constexpr int64_t kF = 24, kH = 40, kW = 60;

// A lit background (a gentle gradient) with noise; a bright 8x8 square slides along row 16..24 from
// x = 4 to x = 48 over the frames; `gain(f)` scales the whole frame (a global light change).
std::unique_ptr<Sequence> scene(bool square, double (*gain)(int64_t), std::unique_ptr<Sequence>* clean, double noise = 0.05) {
    auto noisy = std::make_unique<Sequence>(Shape{kF, kH, kW, 3});
    *clean = std::make_unique<Sequence>(Shape{kF, kH, kW, 3});
    std::mt19937 rng(11);
    std::normal_distribution<double> n(0, noise);
    for (int64_t f = 0; f < kF; ++f) {
        const int64_t sx = 4 + 44 * f / (kF - 1);
        for (int64_t y = 0; y < kH; ++y)
            for (int64_t x = 0; x < kW; ++x)
                for (int64_t c = 0; c < 3; ++c) {
                    double v = 0.5 + 0.3 * x / kW;
                    if (square && y >= 16 && y < 24 && x >= sx && x < sx + 8) v = 3.0;
                    v *= gain(f);
                    (*clean)->at(f, y, x, c) = static_cast<float>(v);
                    noisy->at(f, y, x, c) = static_cast<float>(v * (1 + n(rng)));
                }
    }
    return noisy;
}

double steady(int64_t) { return 1.0; }
double swinging(int64_t f) { return 1.0 + 0.35 * std::sin(2 * M_PI * f / kF); }

double mean_in(const Sequence& map, int64_t y0, int64_t y1, int64_t x0, int64_t x1, int64_t frame = 0) {
    double s = 0;
    for (int64_t y = y0; y < y1; ++y)
        for (int64_t x = x0; x < x1; ++x) s += map.at(frame, y, x, 0);
    return s / ((y1 - y0) * (x1 - x0));
}

}  // namespace

TEST(Motion, AlphaMarksThePathOfAMovingObjectOnly) {
    std::unique_ptr<Sequence> clean;
    const auto seq = scene(true, steady, &clean);
    const FilterRun r = run_filter("motion", *seq);
    const auto alpha = r.filter->results().image("alpha");
    EXPECT_LT(mean_in(*alpha, 17, 23, 10, 50), 0.3);   // the square's path
    EXPECT_GT(mean_in(*alpha, 0, 10, 0, kW), 0.98);     // far from it
    EXPECT_GT(mean_in(*alpha, 32, 40, 0, kW), 0.98);
    EXPECT_EQ(max_abs_diff(*r.output, *seq), 0.0);      // the motion filter passes frames through
}

TEST(Motion, GlobalLightChangeIsNotMotion) {
    std::unique_ptr<Sequence> clean;
    const auto seq = scene(false, swinging, &clean);
    const FilterRun ignored = run_filter("motion", *seq);
    const FilterRun kept = run_filter("motion", *seq, {{"global_light", "keep"}});
    EXPECT_LT(ignored.result("moving_fraction"), 0.02);
    EXPECT_GT(kept.result("moving_fraction"), 0.3);  // without the correction the light swing looks like motion
}

TEST(Motion, NoisyOutlierPixelsUnderALightChangeAreNotMotion) {
    // A light swing at render-like low noise (64 spp), with two columns of pixels half on the lit wall
    // and half on an empty background, as at a room's edge: a few of their samples hit the wall, so
    // their noise is sparse and far above the rest. Nothing moves.
    std::unique_ptr<Sequence> clean;
    auto seq = scene(false, swinging, &clean, 0.01);
    std::mt19937 rng(5);
    std::bernoulli_distribution hit(0.1);
    for (int64_t f = 0; f < kF; ++f)
        for (int64_t y = 0; y < kH; ++y)
            for (int64_t x : {8, 50})
                for (int64_t c = 0; c < 3; ++c) seq->at(f, y, x, c) = hit(rng) ? 2.0f * clean->at(f, y, x, c) : 0.0f;
    const FilterRun r = run_filter("motion", *seq);
    EXPECT_LT(r.result("moving_fraction"), 0.01);
    // The study's choice (all 5 leading components, one global noise level) calls those columns motion:
    // the components beyond the light's one are noise that PCA aligns with the outliers.
    const FilterRun study = run_filter("motion", *seq, {{"component_selection", "fixed"}, {"alpha_noise", "global"}});
    EXPECT_GT(study.result("moving_fraction"), 0.03);
}

TEST(Motion, BetaFromZScoresAndFromAuxPasses) {
    std::unique_ptr<Sequence> clean;
    const auto seq = scene(true, steady, &clean, 0.02);
    const FilterRun r = run_filter("motion", *seq, {{"beta_source", "zscore"}});
    const auto beta = r.filter->results().image("beta");
    ASSERT_EQ(beta->shape(), (Shape{kF, kH, kW, 1}));
    const int64_t f = 12, sx = 4 + 44 * f / (kF - 1);
    EXPECT_GT(mean_in(*beta, 17, 23, sx + 1, sx + 7, f), 0.9);  // where the square is now
    EXPECT_LT(mean_in(*beta, 0, 10, 0, kW, f), 0.02);
    // The same from a noise-free "albedo" pass written to disk.
    const auto aux = local_motion_from_aux(*clean, 0.05, 0);
    EXPECT_GT(mean_in(*aux, 17, 23, sx + 1, sx + 7, f), 0.99);
    EXPECT_EQ(mean_in(*aux, 0, 10, 0, kW, f), 0.0);
}

TEST(Motion, ConstantSequenceHasNoMotionAndNoNaN) {
    Sequence constant(Shape{6, 5, 5, 3});
    for (int64_t f = 0; f < 6; ++f)
        for (int64_t y = 0; y < 5; ++y)
            for (int64_t x = 0; x < 5; ++x)
                for (int64_t c = 0; c < 3; ++c) constant.at(f, y, x, c) = 0.7f;
    const FilterRun r = run_filter("motion", constant, {{"beta_source", "zscore"}});
    EXPECT_EQ(r.result("moving_fraction"), 0.0);
    EXPECT_EQ(r.result("beta_fraction"), 0.0);  // sigma = 0 gives z = 0, not NaN
}

TEST(Hybrid, BeatsGlobalPcaWhereTheObjectMoves) {
    std::unique_ptr<Sequence> clean;
    const auto seq = scene(true, steady, &clean, 0.5);  // render-like noise: temporal filtering pays
    const FilterRun pca = run_filter("pca", *seq);
    // Motion-compensated (the default) and the study's blend of the moving basis and diffusion.
    const FilterRun hybrid = run_filter("hybrid", *seq);
    EXPECT_LT(mse(*hybrid.output, *clean), 0.9 * mse(*pca.output, *clean));
    EXPECT_EQ(hybrid.filter->results().get_string("motion_compensation"), "optical flow on the first pass");
    EXPECT_GT(hybrid.result("aligned_fraction"), 0.0);
    const FilterRun study = run_filter("hybrid", *seq, {{"motion_compensation", "off"}});
    EXPECT_LT(mse(*study.output, *clean), 0.9 * mse(*pca.output, *clean));
    EXPECT_GT(study.result("moving_basis_fraction") + study.result("diffusion_fraction"), 0.0);
}

TEST(Hybrid, NoMotionMeansGlobalPcaAlone) {
    std::unique_ptr<Sequence> clean;
    const auto seq = scene(false, swinging, &clean, 0.3);  // a light swing, nothing moving
    const FilterRun hybrid = run_filter("hybrid", *seq, {{"postfilter", ""}});  // the blend alone
    EXPECT_EQ(hybrid.result("moving_basis_fraction"), 0.0);
    EXPECT_EQ(hybrid.result("diffusion_fraction"), 0.0);
    EXPECT_LT(max_abs_diff(*hybrid.output, *run_filter("pca", *seq).output), 1e-6);
    // With the still-scene shortcut off it runs the full hybrid and still models no motion.
    const FilterRun full = run_filter("hybrid", *seq, {{"still_fraction", "0"}, {"motion_compensation", "off"}});
    EXPECT_EQ(full.filter->results().get_string("beta_source"), "zscore");
    // There its output is its temporal part's, which takes every temporal parameter the hybrid is
    // given (it once ran with its own keep_mean, firefly_z and transform_scale).
    const std::map<std::string, std::string> shared = {
        {"keep_mean", "0"}, {"firefly_z", "0"}, {"transform_scale", "2"}, {"postfilter", ""}};
    std::map<std::string, std::string> study = shared;
    study["still_fraction"] = "0";
    study["motion_compensation"] = "off";
    const FilterRun given = run_filter("hybrid", *seq, study);
    ASSERT_EQ(given.result("moving_basis_fraction") + given.result("diffusion_fraction"), 0.0);
    const FilterRun part = run_filter("error-threshold", *seq, shared);
    EXPECT_LT(max_abs_diff(*given.output, *part.output), 1e-6);
    EXPECT_GT(max_abs_diff(*part.output, *run_filter("error-threshold", *seq, {{"postfilter", ""}}).output), 1e-4);
}

TEST(Hybrid, EverythingMovingAndOneFrame) {
    LowRank g;
    g.rank = 0;
    g.noise = 1.0;  // pure noise every frame: nothing is coherent over time
    const auto chaos = make_low_rank(g);
    const FilterRun r = run_filter("hybrid", *chaos);
    EXPECT_TRUE(all_finite(*r.output));
    g.frames = 1;
    const auto one = make_low_rank(g);
    // One frame: nothing temporal to do; the blend returns it, the default postfilter diffuses it.
    EXPECT_EQ(max_abs_diff(*run_filter("hybrid", *one, {{"postfilter", ""}}).output, *one), 0.0);
    const auto diffused = run_filter("diffusion", *one, {{"iterations", "3"}, {"k", "3"}});
    EXPECT_EQ(max_abs_diff(*run_filter("hybrid", *one).output, *diffused.output), 0.0);
}

TEST(Auto, PicksByHowMuchMoves) {
    std::unique_ptr<Sequence> clean;
    const std::map<std::string, std::string> refine = {{"postfilter", kRefinePostfilter},
                                                       {"postfilter_params", kRefinePostfilterParams}};
    const auto still = scene(false, steady, &clean, 0.3);
    const FilterRun a = run_filter("auto", *still);
    EXPECT_EQ(a.filter->results().get_string("method"), "pca then diffusion");
    EXPECT_EQ(a.filter->results().get_string("quality"), "balanced");
    EXPECT_EQ(a.filter->results().get_string("light_levels").rfind("still", 0), 0u);
    EXPECT_EQ(max_abs_diff(*a.output, *run_filter("pca", *still, refine).output), 0.0);
    // A light that swings is divided out before the method and multiplied back after
    // (tests/filters/test_light_levels.cpp): then the preset is not the method alone.
    const auto lit = scene(false, swinging, &clean, 0.3);
    const FilterRun l = run_filter("auto", *lit);
    EXPECT_EQ(l.filter->results().get_string("method"), "pca then diffusion");
    EXPECT_EQ(l.filter->results().get_string("light_levels").rfind("divided out", 0), 0u);
    EXPECT_NEAR(l.result("light_swing"), 0.35, 0.05);
    const auto moving = scene(true, steady, &clean, 0.3);
    const FilterRun b = run_filter("auto", *moving);
    EXPECT_EQ(b.filter->results().get_string("method"), "hybrid then diffusion");
    const std::map<std::string, std::string> fast_mc = {{"mc_flow", "ultrafast"}, {"mc_half_width", "4"}};
    EXPECT_EQ(max_abs_diff(*b.output, *run_filter("hybrid", *moving, fast_mc).output), 0.0);
    // A postfilter named on auto replaces the preset's.
    const FilterRun c = run_filter("auto", *moving, {{"postfilter", "copy"}});
    EXPECT_EQ(c.filter->results().get_string("method"), "hybrid");
    auto no_post = fast_mc;
    no_post["postfilter"] = "";
    EXPECT_EQ(max_abs_diff(*c.output, *run_filter("hybrid", *moving, no_post).output), 0.0);
}

// The presets: fast is global PCA whatever moves; balanced runs the hybrid with fast motion
// compensation where something moves (the flow on the albedo/normal passes when given, on its first pass
// otherwise); high runs OIDN first when it can,
// else the hybrid at its default (more accurate) flow, with the passes.
TEST(Auto, QualityPresets) {
    std::unique_ptr<Sequence> clean;
    const auto moving = scene(true, steady, &clean, 0.3);
    const FilterRun fast = run_filter("auto", *moving, {{"quality", "fast"}});
    EXPECT_EQ(fast.filter->results().get_string("method"), "pca");
    EXPECT_EQ(fast.filter->results().get_string("transform"), "none");  // the log costs more than the PCA
    EXPECT_EQ(max_abs_diff(*fast.output, *run_filter("pca", *moving, {{"transform", "none"}}).output), 0.0);
    // A transform the user names wins over the preset's.
    const FilterRun fast_log = run_filter("auto", *moving, {{"quality", "fast"}, {"transform", "log"}});
    EXPECT_EQ(max_abs_diff(*fast_log.output, *run_filter("pca", *moving).output), 0.0);

    const auto dir = std::filesystem::temp_directory_path() / ("statfilter-auto-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    WriteOptions w;
    w.half = false;
    write_sequence(*clean, (dir / "albedo.####.exr").string(), w);
    const std::string albedo = (dir / "albedo.####.exr").string();
    // balanced aligns the frames along a flow measured on the passes when they are given (it lowered
    // relMSE on every moving scene of the shared data), on its own first pass otherwise.
    const FilterRun balanced = run_filter("auto", *moving, {{"albedo", albedo}});
    EXPECT_EQ(balanced.filter->results().get_string("method"), "hybrid then diffusion");
    EXPECT_EQ(balanced.filter->results().get_string("hybrid.motion_compensation"), "optical flow on the albedo/normal passes");
    EXPECT_NE(balanced.filter->results().get_string("reason").find("on the albedo/normal passes"), std::string::npos);
    const FilterRun without = run_filter("auto", *moving, {});
    EXPECT_EQ(without.filter->results().get_string("hybrid.motion_compensation"), "optical flow on the first pass");
    EXPECT_LT(mse(*balanced.output, *clean), mse(*without.output, *clean));

    bool oidn = false;
    for (const FilterEntry* e : all_filters()) oidn = oidn || (e->name == "oidn" && e->available());
    const FilterRun high = run_filter("auto", *moving, {{"albedo", albedo}, {"quality", "high"}});
    std::filesystem::remove_all(dir);
    if (oidn) {
        EXPECT_EQ(high.filter->results().get_string("method"), "hybrid then oidn");  // OIDN run last
    } else {
        EXPECT_EQ(high.filter->results().get_string("method"), "hybrid then diffusion");
        EXPECT_EQ(high.filter->results().get_string("hybrid.motion_compensation"),
                  "optical flow on the albedo/normal passes");
        EXPECT_NE(high.filter->results().get_string("reason").find("OIDN not used"), std::string::npos);
    }
    // A still scene is global PCA at every quality (after OIDN at high, when it can run).
    const auto still = scene(false, swinging, &clean, 0.3);
    EXPECT_EQ(run_filter("auto", *still, {{"quality", "high"}}).filter->results().get_string("method"),
              oidn ? "pca then oidn" : "pca then diffusion");
    EXPECT_EQ(run_filter("auto", *still, {{"quality", "balanced"}}).filter->results().get_string("transform"), "log");
    EXPECT_THROW(run_filter("auto", *still, {{"quality", "best"}}), Error);
}

TEST(Hybrid, AnySingleFrameFilterCanBeItsSingleFrameStage) {
    std::unique_ptr<Sequence> clean;
    const auto seq = scene(true, steady, &clean, 0.5);
    const std::map<std::string, std::string> blend = {{"postfilter", ""}, {"motion_compensation", "off"}};
    const FilterRun diffused = run_filter("hybrid", *seq, blend);  // the blend alone
    // "copy" is single-frame too: the moving-now pixels then keep their noisy values; far from the
    // moving square the two agree exactly, since only pixels with a single-frame weight change.
    auto with_copy = blend;
    with_copy["single_frame"] = "copy";
    const FilterRun copied = run_filter("hybrid", *seq, with_copy);
    EXPECT_GT(copied.result("diffusion_fraction"), 0.0);
    EXPECT_GT(max_abs_diff(*copied.output, *diffused.output), 0.0);
    double far = 0;
    for (int64_t f = 0; f < kF; ++f)
        for (int64_t y = 0; y < 6; ++y)
            for (int64_t x = 0; x < kW; ++x)
                for (int64_t c = 0; c < 3; ++c)
                    far = std::max(far, std::fabs(double(copied.output->at(f, y, x, c)) - diffused.output->at(f, y, x, c)));
    EXPECT_EQ(far, 0.0);
    EXPECT_THROW(run_filter("hybrid", *seq, {{"single_frame", "pca"}, {"motion_compensation", "off"}}), Error);
}
