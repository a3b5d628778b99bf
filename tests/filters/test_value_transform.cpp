// The value transform's numerics: relative to the data's level (denoise(k x) = k denoise(x)), zero
// in gives zero out, and the way back keeps the light (no Jensen bias, no negative sample).
#include <gtest/gtest.h>

#include <random>

#include <cmath>
#include <cstring>
#include <limits>

#include "filter_runner.hpp"
#include "statfilter/fast_log_exp.hpp"
#include "statfilter/value_transform.hpp"
#include "synthetic.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

// A lit room-like scene: a gradient with a brighter box, light swinging +-20% over time, a small
// bright square sliding across (so the motion paths run), and heavy-tailed noise of known mean:
// each sample is the clean value times a gamma(shape, 1/shape) variate (mean 1; shape 1 is as
// skewed as a few samples per pixel).
struct Scene {
    std::unique_ptr<Sequence> noisy, clean;
};

Scene gamma_scene(double shape = 2.0, bool moving = true, int64_t F = 24, int64_t H = 48, int64_t W = 64,
                  unsigned seed = 3) {
    Scene s;
    s.noisy = std::make_unique<Sequence>(Shape{F, H, W, 3});
    s.clean = std::make_unique<Sequence>(Shape{F, H, W, 3});
    std::mt19937 rng(seed);
    std::gamma_distribution<double> gamma(shape, 1.0 / shape);
    for (int64_t f = 0; f < F; ++f) {
        const double light = 1.0 + 0.2 * std::sin(2 * M_PI * f / F);
        const int64_t sx = 4 + (W - 16) * f / (F - 1);
        for (int64_t y = 0; y < H; ++y)
            for (int64_t x = 0; x < W; ++x)
                for (int64_t c = 0; c < 3; ++c) {
                    double v = (0.2 + 0.5 * x / W) * (1 + 0.3 * c);
                    if (x > W / 2 && y > H / 2) v *= 3;
                    if (moving && y >= 8 && y < 16 && x >= sx && x < sx + 8) v = 2.5;
                    v *= light;
                    s.clean->at(f, y, x, c) = static_cast<float>(v);
                    s.noisy->at(f, y, x, c) = static_cast<float>(v * gamma(rng));
                }
    }
    return s;
}

double mean_of(const Sequence& a) {
    const Shape& s = a.shape();
    double sum = 0;
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) sum += a.at(f, y, x, c);
    return sum / static_cast<double>(s.samples());
}

double min_of(const Sequence& a) {
    const Shape& s = a.shape();
    double m = 1e300;
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) m = std::min<double>(m, a.at(f, y, x, c));
    return m;
}

double max_abs(const Sequence& a) {
    const Shape& s = a.shape();
    double m = 0;
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) m = std::max<double>(m, std::fabs(a.at(f, y, x, c)));
    return m;
}

std::unique_ptr<Sequence> scaled(const Sequence& a, double k) {
    auto out = std::make_unique<Sequence>(a.shape());
    const Shape& s = a.shape();
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c)
                    out->at(f, y, x, c) = static_cast<float>(k * a.at(f, y, x, c));
    return out;
}

bool oidn_available() {
    for (const FilterEntry* e : all_filters())
        if (e->name == "oidn") return e->available();
    return false;
}

// Every method and preset, as the CLI names them.
struct Method {
    std::string label, filter;
    std::map<std::string, std::string> params;
};

std::vector<Method> methods() {
    std::vector<Method> m = {
        {"pca", "pca", {}},
        {"error-threshold", "error-threshold", {}},
        {"moving-basis", "moving-basis", {}},
        {"hybrid", "hybrid", {}},
        {"hybrid (motion_compensation off)", "hybrid", {{"motion_compensation", "off"}}},
        {"diffusion", "diffusion", {}},
        {"auto fast", "auto", {{"quality", "fast"}}},
        {"auto balanced", "auto", {{"quality", "balanced"}}},
    };
    if (oidn_available()) m.push_back({"auto high", "auto", {{"quality", "high"}}});
    return m;
}

}  // namespace

TEST(ValueTransform, ScaledRoundTripAndLevel) {
    for (ValueTransform t : {ValueTransform::None, ValueTransform::Sqrt, ValueTransform::Log}) {
        std::vector<double> v = {-3e6, -1.5, 0.0, 2e-7, 0.25, 7.0, 1e9};
        const std::vector<double> original = v;
        forward_transform(t, 0.37, v.data(), v.size());
        inverse_transform(t, 0.37, v.data(), v.size());
        for (size_t i = 0; i < v.size(); ++i) EXPECT_NEAR(v[i], original[i], 1e-12 * std::fabs(original[i]) + 1e-300);
    }
    // Relative to its scale: log(1 + x / s) of k x with scale k s is log(1 + x / s).
    double a = 3.0, b = 3e8;
    forward_transform(ValueTransform::Log, 2.0, &a, 1);
    forward_transform(ValueTransform::Log, 2e8, &b, 1);
    EXPECT_DOUBLE_EQ(a, b);
    Sequence s(Shape{2, 1, 2, 2});
    s.at(0, 0, 0, 0) = 1, s.at(0, 0, 1, 0) = -3, s.at(1, 0, 0, 0) = 0, s.at(1, 0, 1, 0) = 4, s.at(0, 0, 0, 1) = 100;
    EXPECT_DOUBLE_EQ(transform_level(s, ChannelSelection::one(0)), 3.0);  // median of 1, 3, 4: zeros left out
    EXPECT_DOUBLE_EQ(transform_level(s, ChannelSelection::all(s.shape())), 4.0);  // of 1, 3, 4, 100
    EXPECT_DOUBLE_EQ(transform_level(Sequence(Shape{2, 2, 2, 1}), ChannelSelection::one(0)), 1.0);  // all zero
}

TEST(ValueTransform, InverseKeepsTheMeanAndTheSign) {
    // A log-domain series smoothed to its mean: the plain inverse is darker than the input.
    std::vector<double> x = {0.0, 0.1, 4.0, 0.3, 0.0, 2.0};
    double mean = 0;
    for (double v : x) mean += v / x.size();
    std::vector<double> y = x;
    forward_transform(ValueTransform::Log, 0.5, y.data(), y.size());
    double ym = 0;
    for (double v : y) ym += v / y.size();
    std::vector<double> flat(x.size(), ym), plain = flat;
    inverse_transform(ValueTransform::Log, 0.5, plain.data(), plain.size());
    EXPECT_LT(plain[0], 0.8 * mean);  // Jensen: exp(E y) < E exp(y)
    inverse_transform_keeping_mean(ValueTransform::Log, 0.5, flat.data(), 6, 1, mean, true);
    for (double v : flat) EXPECT_NEAR(v, mean, 1e-12);
    // A reconstruction that undershoots below zero: clamped, and the mean still holds.
    for (ValueTransform t : {ValueTransform::None, ValueTransform::Sqrt, ValueTransform::Log}) {
        std::vector<double> r = {-0.4, -0.1, 0.05, 0.5, 1.2, 2.0};  // strided by 2 in a buffer
        std::vector<double> buffer;
        for (double v : r) buffer.push_back(v), buffer.push_back(99.0);
        inverse_transform_keeping_mean(t, 0.7, buffer.data(), 6, 2, 0.6, true);
        double sum = 0;
        for (int i = 0; i < 6; ++i) {
            EXPECT_GE(buffer[2 * i], 0.0);
            EXPECT_EQ(buffer[2 * i + 1], 99.0);
            sum += buffer[2 * i];
        }
        EXPECT_NEAR(sum / 6, 0.6, 1e-12) << static_cast<int>(t);
        // Zero target, non-negative: zero out. Signed data: the mean by a shift, negatives allowed.
        std::vector<double> z = r;
        inverse_transform_keeping_mean(t, 0.7, z.data(), 6, 1, 0.0, true);
        for (double v : z) EXPECT_EQ(v, 0.0);
        std::vector<double> signed_series = r;
        inverse_transform_keeping_mean(t, 0.7, signed_series.data(), 6, 1, -0.2, false);
        double s = 0;
        for (double v : signed_series) s += v / 6;
        EXPECT_NEAR(s, -0.2, 1e-12);
    }
}

// denoise(k x) = k denoise(x): the transform, the noise estimates, motion and diffusion all act
// relative to the data. Tolerance: 1e-3 of the output's largest magnitude (float rounding of k x
// moves samples by ~1e-7 relative, and a rank or motion decision near its threshold by a little
// more); measured differences are far below it. With `flips`, that many samples in 10^4 may be
// further apart than that, and the mean difference stays under 1e-4 of it: where frames are averaged
// along the flow, a decision taken within float rounding of its threshold goes one way at one scale
// and the other at another. A sample whose firefly score sits at the threshold is replaced or not,
// and it is a whole sample of a ~10-frame average (4 and 15 samples of 221184 at k = 1e3, up to 0.2%
// of the largest output); and the flow's window changes (`auto balanced` at k = 1e-3, after the light
// levels' blocks became medians, whose levels agree across scales to 1e-9: `hybrid.aligned_frames`
// 7.425367 -> 7.425305, 431 samples of one frame apart by up to 1.4% of the largest output and 155
// of another, one at the frame's border by 21%; 0.26% of all samples, a mean of 3e-5 of it). A
// dependence on the units, such as a log1p of unscaled values, moves every sample: the mean catches it.
void expect_scale_equivariant(const Scene& s, const std::vector<Method>& methods, double flips = 0) {
    for (const Method& m : methods) {
        const FilterRun base = run_filter(m.filter, *s.noisy, m.params);
        const double size = max_abs(*base.output);
        ASSERT_GT(size, 0) << m.label;
        for (double k : {1e-6, 1e-3, 1e3, 1e6}) {
            const FilterRun r = run_filter(m.filter, *scaled(*s.noisy, k), m.params);
            const auto back = scaled(*r.output, 1.0 / k);
            if (flips > 0) {
                EXPECT_LE(share_apart(*back, *base.output, 1e-3 * size), flips * 1e-4) << m.label << " k " << k;
                double sum = 0;
                each_abs_diff(*back, *base.output, [&](double d) { sum += d; });
                EXPECT_LT(sum / static_cast<double>(back->shape().samples()), 1e-4 * size) << m.label << " k " << k;
            } else {
                EXPECT_LT(max_abs_diff(*back, *base.output), 1e-3 * size) << m.label << " k " << k;
            }
        }
    }
}

TEST(ValueTransform, EveryMethodIsScaleEquivariant) {
    // Light swinging, nothing moving: the hybrid and the balanced preset take their still-scene path.
    expect_scale_equivariant(gamma_scene(2.0, false), methods());
}

// With something moving: the motion-compensated average weighs samples in units of the first pass'
// mean, and the local motion z-scores (motion_compensation=off) are taken on log1p(|l| / s) with s
// the transform's scale (transform_scale x transform_level), so neither depends on the input's units.
TEST(ValueTransform, MotionPathsAreScaleEquivariant) {
    expect_scale_equivariant(gamma_scene(2.0, true), {{"hybrid", "hybrid", {}},
                                                      {"hybrid (motion_compensation off)", "hybrid", {{"motion_compensation", "off"}}},
                                                      {"auto balanced", "auto", {{"quality", "balanced"}}}},
                             40.0);
}

TEST(ValueTransform, TheStudysBlendOnExponentialNoiseStaysWithinOnePercent) {
    const Scene s = gamma_scene(1.0, true, 32, 64, 80, 9);
    const FilterRun r = run_filter("hybrid", *s.noisy, {{"motion_compensation", "off"}});
    EXPECT_NEAR(mean_of(*r.output) / mean_of(*s.noisy), 1.0, 0.01);
    EXPECT_GE(min_of(*r.output), 0.0);
}

TEST(ValueTransform, ZeroInZeroOut) {
    const Sequence zero(Shape{16, 24, 32, 3});
    for (const Method& m : methods()) {
        const FilterRun r = run_filter(m.filter, zero, m.params);
        EXPECT_EQ(max_abs(*r.output), 0.0) << m.label;
    }
}

// Gamma noise of known mean (1 x the clean value): the output's mean over the shot is within 0.5%
// of the input's and of the true one, and no sample is negative. Before, the log domain's inverse
// made pca 3-5% darker here and its reconstructions dipped below zero.
TEST(ValueTransform, EveryMethodKeepsTheLight) {
    for (double shape : {1.0, 4.0}) {
        const Scene s = gamma_scene(shape, true, 32, 64, 80, 9);
        const double truth = mean_of(*s.clean), input = mean_of(*s.noisy);
        ASSERT_NEAR(input / truth, 1.0, 0.005);  // the noise is unbiased: the test can tell
        for (const Method& m : methods()) {
            // The study's blend picks the single-frame path where a sample's z-score is high, which on
            // exponential noise selects the bright samples (+0.6% here): a known limit of that
            // reading, kept for comparison, not a default (docs/quality.md). Bounded below instead.
            if (m.label == "hybrid (motion_compensation off)" && shape == 1.0) continue;
            const FilterRun r = run_filter(m.filter, *s.noisy, m.params);
            const double out = mean_of(*r.output);
            EXPECT_NEAR(out / input, 1.0, 0.005) << m.label << " shape " << shape;
            EXPECT_NEAR(out / truth, 1.0, 0.01) << m.label << " shape " << shape;
            EXPECT_GE(min_of(*r.output), 0.0) << m.label << " shape " << shape;
        }
    }
}

// Tiling does not change the scale or the fireflies: both are measured on the whole group first.
TEST(ValueTransform, TiledResultEqualsUntiledWithTheTransform) {
    const Scene s = gamma_scene(1.0, false, 16, 64, 80);
    for (const char* name : {"pca", "error-threshold", "moving-basis"}) {
        const FilterRun whole = run_filter(name, *s.noisy, {{"memory_mb", "4096"}});
        const FilterRun tiled = run_filter(name, *s.noisy, {{"memory_mb", "1"}});
        EXPECT_LT(max_abs_diff(*whole.output, *tiled.output), 1e-5 * max_abs(*whole.output)) << name;
    }
}

namespace {

// Distance in units in the last place between two finite doubles of the same sign.
double ulps(double a, double b) {
    if (a == b) return 0;
    int64_t ia, ib;
    std::memcpy(&ia, &a, sizeof ia);
    std::memcpy(&ib, &b, sizeof ib);
    return std::fabs(static_cast<double>(ia - ib));
}

}  // namespace

// The transforms' own log1p, expm1 and exp(-x) (statfilter/fast_log_exp.hpp) stay within the 4 ulp their
// header promises of the library's, over the whole range, signs, zeros, infinities and NaN included.
TEST(ValueTransform, FastLogAndExpStayWithinFourUlpOfTheLibrary) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> exponent(-60.0, 60.0), unit(0.0, 1.0);
    std::vector<double> x;
    for (int i = 0; i < 200000; ++i) x.push_back((unit(rng) < 0.5 ? -1 : 1) * std::pow(10.0, exponent(rng) / 6.0));
    for (double v : {0.0, -0.0, 1e-300, 5e-324, 1.0, 2.0, 0.5, 1e300, std::numeric_limits<double>::max(), 700.0, 709.0, 710.0})
        x.push_back(v), x.push_back(-v);
    x.push_back(std::numeric_limits<double>::infinity());
    x.push_back(-std::numeric_limits<double>::infinity());
    x.push_back(std::numeric_limits<double>::quiet_NaN());
    for (const double scale : {1.0, 0.37, 250.0}) {
        std::vector<double> forward = x, back = x;
        fast_math::signed_log1p(forward.data(), forward.size(), 1.0 / scale);
        fast_math::signed_expm1(back.data(), back.size(), scale);
        double worst_log = 0, worst_exp = 0;
        for (size_t i = 0; i < x.size(); ++i) {
            const double want_log = std::copysign(std::log1p(std::fabs(x[i]) * (1.0 / scale)), x[i]);
            const double want_exp = scale * std::copysign(std::expm1(std::fabs(x[i])), x[i]);
            if (std::isnan(want_log)) EXPECT_TRUE(std::isnan(forward[i])) << x[i];
            else if (std::isinf(want_log)) EXPECT_EQ(forward[i], want_log) << x[i];
            else worst_log = std::max(worst_log, ulps(forward[i], want_log));
            if (std::isnan(want_exp)) EXPECT_TRUE(std::isnan(back[i])) << x[i];
            else if (std::isinf(want_exp)) EXPECT_EQ(back[i], want_exp) << x[i];
            else worst_exp = std::max(worst_exp, ulps(back[i], want_exp));
        }
        std::vector<double> decay;
        for (double v : x) decay.push_back(std::fabs(v) * scale);
        decay.push_back(-1.0);
        const std::vector<double> decay_in = decay;
        fast_math::exp_of_negative(decay.data(), decay.size());
        double worst_decay = 0;
        for (size_t i = 0; i < decay.size(); ++i) {
            const double want = std::exp(-decay_in[i]);
            if (std::isnan(want)) EXPECT_TRUE(std::isnan(decay[i]));
            else if (want == 0 || std::isinf(want)) EXPECT_EQ(decay[i], want) << decay_in[i];
            else worst_decay = std::max(worst_decay, ulps(decay[i], want));
        }
        EXPECT_LE(worst_decay, 4) << "scale " << scale;
        EXPECT_LE(worst_log, 4) << "scale " << scale;
        EXPECT_LE(worst_exp, 4) << "scale " << scale;
    }
}
