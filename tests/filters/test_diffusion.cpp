// Anisotropic diffusion: stability, edge preservation, HDR range, and agreement with OpenCV's
// 8-bit implementation where both apply.
#include <gtest/gtest.h>

#include <opencv2/ximgproc.hpp>
#include <cstring>
#include <limits>
#include <random>

#include "filter_runner.hpp"
#include "statfilter/anisotropic_diffusion.hpp"
#include "statfilter/error.hpp"
#include "synthetic.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

// A vertical step edge (dark left, bright right) plus Gaussian noise, 3 channels, in [0, 255].
cv::Mat noisy_step(cv::Mat* clean_out, double noise = 12.0) {
    cv::Mat clean(48, 64, CV_32FC3), noisy(48, 64, CV_32FC3);
    std::mt19937 rng(3);
    std::normal_distribution<float> n(0, static_cast<float>(noise));
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            const float v = x < 32 ? 60.0f : 190.0f;
            clean.at<cv::Vec3f>(y, x) = cv::Vec3f(v, v, v);
            for (int c = 0; c < 3; ++c) noisy.at<cv::Vec3f>(y, x)[c] = std::clamp(v + n(rng), 0.0f, 255.0f);
        }
    if (clean_out) *clean_out = clean;
    return noisy;
}

double mse(const cv::Mat& a, const cv::Mat& b) {
    cv::Mat d;
    cv::absdiff(a, b, d);
    d = d.mul(d);
    const cv::Scalar s = cv::mean(d);
    return (s[0] + s[1] + s[2]) / 3;
}

// Contrast across the edge: mean right of it minus mean left of it, two columns each side.
double edge_contrast(const cv::Mat& img) {
    cv::Scalar l = cv::mean(img(cv::Rect(30, 0, 2, 48))), r = cv::mean(img(cv::Rect(32, 0, 2, 48)));
    return r[0] - l[0];
}

cv::Mat ours(const cv::Mat& in, DiffusionOptions o) {
    cv::Mat out = in.clone();
    diffuse_frame(out.ptr<float>(), out.cols, out.rows, 3, o);
    return out;
}

}  // namespace

TEST(Diffusion, AgreesWithOpenCvOnEightBitData) {
    cv::Mat clean;
    const cv::Mat noisy = noisy_step(&clean);
    cv::Mat noisy8, cv_out8, cv_out;
    noisy.convertTo(noisy8, CV_8UC3);
    // Perona-Malik, 8-bit only; its K is on a 0..1 scale (0.1 ~ 25 grey levels).
    cv::ximgproc::anisotropicDiffusion(noisy8, cv_out8, 0.1f, 0.1f, 20);
    cv_out8.convertTo(cv_out, CV_32FC3);
    DiffusionOptions o;
    o.flux = DiffusionFlux::PeronaMalik;
    o.log_domain = false;
    o.k = 1.5;  // x the gradient noise (about 17 grey levels here): K ~ 25
    o.dt = 0.1;
    o.iterations = 20;
    const cv::Mat mine = ours(noisy, o);
    // Both remove most of the noise and keep the edge; they agree far better than either agrees with the input.
    EXPECT_LT(mse(cv_out, clean), mse(noisy, clean) / 3);
    EXPECT_LT(mse(mine, clean), mse(noisy, clean) / 3);
    EXPECT_GT(edge_contrast(cv_out), 0.85 * 130);
    EXPECT_GT(edge_contrast(mine), 0.85 * 130);
    EXPECT_LT(mse(mine, cv_out), mse(noisy, cv_out) / 3);
}

// The study's flux grad/sqrt(1 + |grad|^2/K^2) is bounded (by K), not decreasing: an edge still
// loses a little every step, where Perona-Malik's exp(-(|grad|/K)^2) stops at it.
TEST(Diffusion, StudyFluxErodesEdgesMoreThanPeronaMalik) {
    cv::Mat clean;
    const cv::Mat noisy = noisy_step(&clean);
    DiffusionOptions o;
    o.flux = DiffusionFlux::Study;
    o.log_domain = false;
    o.k = 0.5;  // the study's flux falls off slowly (~K/|grad|): a lower K keeps the edge
    o.iterations = 20;
    const cv::Mat study = ours(noisy, o);
    EXPECT_LT(mse(study, clean), mse(noisy, clean) / 2);
    EXPECT_GT(edge_contrast(study), 0.6 * 130);
    o.flux = DiffusionFlux::PeronaMalik;
    o.k = 1.5;
    EXPECT_GT(edge_contrast(ours(noisy, o)), edge_contrast(study));
}

TEST(Diffusion, HdrFromOneMillionthToOneMillionInOneFrame) {
    // Four quadrants 1e-6, 1, 1e3, 1e6 with 20% relative noise: in the log domain each is smoothed
    // on its own scale and none leaks into another.
    const int W = 40, H = 40;
    std::vector<float> img(W * H * 3), clean(W * H * 3);
    std::mt19937 rng(5);
    std::normal_distribution<float> n(0, 0.2f);
    const float levels[4] = {1e-6f, 1.0f, 1e3f, 1e6f};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = levels[(y >= H / 2) * 2 + (x >= W / 2)];
                clean[(y * W + x) * 3 + c] = v;
                img[(y * W + x) * 3 + c] = v * (1 + n(rng));
            }
    std::vector<float> before = img;
    DiffusionOptions o;  // log domain
    o.epsilon = 1e-12;   // eps (about 2.5e-7 here) below the faintest level: 12 decades stay apart
    o.iterations = 30;
    diffuse_frame(img.data(), W, H, 3, o);
    for (int q = 0; q < 4; ++q) {
        double err_before = 0, err_after = 0;
        const int x0 = (q % 2) * W / 2 + 4, y0 = (q / 2) * H / 2 + 4;
        for (int y = y0; y < y0 + H / 2 - 8; ++y)
            for (int x = x0; x < x0 + W / 2 - 8; ++x) {
                const int i = (y * W + x) * 3;
                ASSERT_TRUE(std::isfinite(img[i]));
                err_before += std::pow((before[i] - clean[i]) / clean[i], 2);
                err_after += std::pow((img[i] - clean[i]) / clean[i], 2);
            }
        EXPECT_LT(err_after, err_before / 4) << "quadrant " << levels[q];
    }
}

TEST(Diffusion, UnstableStepIsRefusedAndConstantsStay) {
    DiffusionOptions o;
    o.dt = 0.3;
    std::vector<float> img(12, 1.0f);
    EXPECT_THROW(diffuse_frame(img.data(), 2, 2, 3, o), Error);
    o.dt = 0.25;
    diffuse_frame(img.data(), 2, 2, 3, o);
    for (float v : img) EXPECT_FLOAT_EQ(v, 1.0f);
    // Through the filter's parameter table, dt above 0.25 is out of range.
    auto f = create_filter("diffusion");
    EXPECT_THROW(f->params().set_float("dt", 0.3), Error);
}

TEST(Diffusion, FilterMatchesFrameByFrameDiffusion) {
    LowRank g;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    const FilterRun r = run_filter("diffusion", *noisy);
    std::vector<float> frame(static_cast<size_t>(g.height * g.width * g.channels));
    noisy->get_frame(7, frame.data());
    diffuse_frame(frame.data(), g.width, g.height, g.channels, DiffusionOptions());
    std::vector<float> filtered(frame.size());
    r.output->get_frame(7, filtered.data());
    for (size_t i = 0; i < frame.size(); ++i) ASSERT_EQ(frame[i], filtered[i]);
}

// The log domain measures the edges; the flux moves the linear values, so a frame keeps its sum
// (undoing diffused logs made 4-spp frames up to 18% darker) and a non-negative frame stays so.
TEST(Diffusion, LogDomainKeepsEachFramesLightAndSign) {
    const int W = 48, H = 40;
    std::vector<float> img(W * H * 3);
    std::mt19937 rng(9);
    std::gamma_distribution<float> gamma(1.0f, 1.0f);  // as skewed as a few samples per pixel
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 3; ++c) img[(y * W + x) * 3 + c] = (x < W / 2 ? 0.2f : 2.0f) * gamma(rng);
    img[5] = 0.0f;
    double before = 0, after = 0, plain = 0;
    for (float v : img) before += v;
    std::vector<float> conserved = img, values = img;
    DiffusionOptions o;
    diffuse_frame(conserved.data(), W, H, 3, o);
    o.conserve = false;  // the log values themselves diffused and undone
    diffuse_frame(values.data(), W, H, 3, o);
    for (size_t i = 0; i < img.size(); ++i) {
        after += conserved[i];
        plain += values[i];
        EXPECT_GE(conserved[i], 0.0f);
    }
    EXPECT_NEAR(after / before, 1.0, 1e-6);
    EXPECT_LT(plain / before, 0.97);  // the test can tell
    // Both smooth: the conserving scheme about as much as the other.
    auto roughness = [&](const std::vector<float>& a) {
        double r = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 1; x < W / 2; ++x) r += std::pow(a[(y * W + x) * 3] - a[(y * W + x - 1) * 3], 2);
        return r;
    };
    EXPECT_LT(roughness(conserved), 0.5 * roughness(img));
}

// A region diffused alone has the whole frame's diffusion there, bit for bit (the hybrid diffuses a
// frame only around the pixels it needs), in every flux and domain, at the frame's borders and corners
// and for a region of one pixel; the pixels outside the region are left as they were. diffuse_box
// gives the same values into a buffer of its own and leaves the frame as it was.
TEST(Diffusion, ARegionHasTheWholeFramesValues) {
    const int64_t W = 53, H = 41, C = 3;
    std::vector<float> frame(static_cast<size_t>(W * H * C));
    std::mt19937 rng(11);
    std::gamma_distribution<float> g(0.7f, 1.5f);
    for (int64_t i = 0; i < W * H * C; ++i) frame[static_cast<size_t>(i)] = g(rng) * (i % (W * C) < W * C / 2 ? 1.0f : 40.0f);
    frame[5] = std::numeric_limits<float>::quiet_NaN();  // a non-finite sample counts nowhere in the scale
    const PixelBox boxes[] = {{10, 7, 30, 25}, {0, 0, 6, 4}, {40, 30, 53, 41}, {22, 18, 23, 19}, {0, 0, 53, 41}};
    for (const bool perona : {true, false})
        for (const int domain : {0, 1, 2})  // linear; log conductances on linear values (conserve); log
            for (const int iterations : {0, 1, 10}) {
                DiffusionOptions o;
                o.flux = perona ? DiffusionFlux::PeronaMalik : DiffusionFlux::Study;
                o.log_domain = domain > 0;
                o.conserve = domain == 1;
                o.iterations = iterations;
                std::vector<float> whole = frame;
                diffuse_frame(whole.data(), W, H, C, o);
                for (const PixelBox& b : boxes) {
                    std::vector<float> part = frame;
                    diffuse_region(part.data(), W, H, C, b, o);
                    int64_t changed = 0;
                    for (int64_t y = 0; y < H; ++y)
                        for (int64_t x = 0; x < W; ++x)
                            for (int64_t c = 0; c < C; ++c) {
                                const size_t i = static_cast<size_t>((y * W + x) * C + c);
                                const bool inside = x >= b.x0 && x < b.x1 && y >= b.y0 && y < b.y1;
                                const float want = inside ? whole[i] : frame[i];
                                if (std::isnan(want)) {
                                    ASSERT_TRUE(std::isnan(part[i]));
                                } else {
                                    ASSERT_EQ(part[i], want) << "box " << b.x0 << "," << b.y0 << " pixel " << x << ","
                                                             << y << " iterations " << iterations;
                                }
                                changed += inside && part[i] != frame[i];
                            }
                    if (iterations > 0) {
                        EXPECT_GT(changed, 0);  // the test compares a diffusion, not a copy
                    }
                    // diffuse_box: the same values into a buffer of the box, the frame only read.
                    const std::vector<float> before = frame;
                    const int64_t bw = b.x1 - b.x0;
                    std::vector<float> own(static_cast<size_t>((b.y1 - b.y0) * bw * C), -1.0f);
                    DiffusionWorkspace ws;
                    diffuse_box(frame.data(), W, H, C, b, o, diffusion_scale(frame.data(), W, H, C, o, ws), ws, own.data(), bw);
                    ASSERT_EQ(std::memcmp(frame.data(), before.data(), frame.size() * sizeof(float)), 0);  // NaN too
                    for (int64_t y = b.y0; y < b.y1; ++y)
                        for (int64_t i = 0; i < bw * C; ++i) {
                            const float want = whole[static_cast<size_t>((y * W + b.x0) * C + i)];
                            const float got = own[static_cast<size_t>((y - b.y0) * bw * C + i)];
                            if (std::isnan(want)) ASSERT_TRUE(std::isnan(got));
                            else ASSERT_EQ(got, want) << "diffuse_box " << b.x0 << "," << b.y0 << " row " << y;
                        }
                }
            }
    std::vector<float> part = frame;
    EXPECT_THROW(diffuse_region(part.data(), W, H, C, PixelBox{0, 0, W + 1, H}, DiffusionOptions()), Error);
}

// A frame more than half zeros (a render over black) has no edge scale: diffusion leaves it as it is,
// and diffuse_box hands the box's own values on, not the buffer's old contents.
TEST(Diffusion, AFlatFramesBoxIsItsOwnValues) {
    const int64_t W = 30, H = 20, C = 3;
    std::vector<float> frame(static_cast<size_t>(W * H * C), 0.0f);
    for (int64_t y = 14; y < H; ++y)
        for (int64_t i = 0; i < W * C; ++i) frame[static_cast<size_t>(y * W * C + i)] = 0.5f + 0.01f * static_cast<float>(i);
    DiffusionOptions o;
    DiffusionWorkspace ws;
    const DiffusionScale scale = diffusion_scale(frame.data(), W, H, C, o, ws);
    ASSERT_FALSE(scale.k > 0);
    const PixelBox box{3, 12, 17, 18};
    const int64_t bw = box.x1 - box.x0;
    std::vector<float> own(static_cast<size_t>((box.y1 - box.y0) * bw * C), -7.0f);
    diffuse_box(frame.data(), W, H, C, box, o, scale, ws, own.data(), bw);
    for (int64_t y = box.y0; y < box.y1; ++y)
        for (int64_t i = 0; i < bw * C; ++i)
            ASSERT_EQ(own[static_cast<size_t>((y - box.y0) * bw * C + i)], frame[static_cast<size_t>((y * W + box.x0) * C + i)])
                << "row " << y;
    std::vector<float> whole = frame;
    diffuse_frame(whole.data(), W, H, C, o);
    EXPECT_EQ(whole, frame);
}

// A workspace kept from call to call (a frame stage diffusing frame after frame) gives the bits a
// new one gives, whatever it held before: a larger frame, a region, another domain, a flat frame.
TEST(Diffusion, AKeptWorkspaceGivesTheBitsOfANewOne) {
    std::mt19937 rng(5);
    std::gamma_distribution<float> g(0.7f, 1.5f);
    const auto frame_of = [&](int64_t w, int64_t h, bool flat) {
        std::vector<float> f(static_cast<size_t>(w * h * 3), 2.0f);
        if (!flat)
            for (float& v : f) v = g(rng);
        return f;
    };
    struct Call {
        int64_t w, h;
        bool flat, region, log_domain;
    };
    const Call calls[] = {{53, 41, false, false, true}, {20, 17, false, false, true}, {53, 41, false, true, true},
                          {20, 17, false, false, false}, {20, 17, true, false, true}, {7, 3, false, true, true},
                          {53, 41, false, false, true}};
    DiffusionWorkspace kept;
    for (const Call& c : calls) {
        DiffusionOptions o;
        o.log_domain = c.log_domain;
        o.iterations = 4;
        const std::vector<float> input = frame_of(c.w, c.h, c.flat);
        std::vector<float> fresh = input, reused = input;
        const PixelBox box{1, 1, c.w - 2, c.h - 1};
        if (c.region) {
            diffuse_region(fresh.data(), c.w, c.h, 3, box, o);
            diffuse_region(reused.data(), c.w, c.h, 3, box, o, kept);
        } else {
            diffuse_frame(fresh.data(), c.w, c.h, 3, o);
            diffuse_frame(reused.data(), c.w, c.h, 3, o, kept);
        }
        for (size_t i = 0; i < input.size(); ++i) ASSERT_EQ(reused[i], fresh[i]) << c.w << " x " << c.h << " sample " << i;
        if (!c.flat) {
            EXPECT_NE(fresh, input);  // a diffusion, not a copy
        }
    }
}

// The filter run on one frame at a time, in place (as a postfilter is), reuses its buffers from frame
// to frame and gives each frame's own diffusion.
TEST(Diffusion, TheFilterFrameByFrameInPlaceGivesEachFramesDiffusion) {
    LowRank g;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    auto filter = create_filter("diffusion");
    const Shape one{1, g.height, g.width, g.channels};
    std::vector<float> pixels(static_cast<size_t>(g.height * g.width * g.channels)), want(pixels.size());
    for (int64_t f = 0; f < 4; ++f) {
        noisy->get_frame(f, pixels.data());
        want = pixels;
        diffuse_frame(want.data(), g.width, g.height, g.channels, DiffusionOptions());
        Sequence frame(pixels.data(), one, contiguous_strides(one));
        filter->execute(frame, frame, Progress());
        for (size_t i = 0; i < pixels.size(); ++i) ASSERT_EQ(pixels[i], want[i]) << "frame " << f;
    }
}

// The scheme written out plainly, whole images at a time in double with the standard library's
// log1p, expm1 and exp, against the library's (rows at a time, its own vectorised log and exp) on
// frames down to one row or one column, 1, 3 and 4 channels, every domain and flux: the same values
// to the last few ulp of the log, so every border and every row's neighbours are the scheme's.
TEST(Diffusion, MatchesTheSchemeWrittenOutOnSmallFrames) {
    std::mt19937 rng(11);
    std::gamma_distribution<double> g(0.6, 2.0);
    struct Size {
        int64_t w, h;
    };
    const Size sizes[] = {{1, 1}, {6, 1}, {1, 6}, {2, 2}, {5, 3}, {4, 7}, {9, 8}};
    for (const Size sz : sizes)
        for (const int64_t C : {1, 3, 4})
            for (const int domain : {0, 1, 2})  // log (conserve), log-values, linear
                for (const DiffusionFlux flux : {DiffusionFlux::PeronaMalik, DiffusionFlux::Study}) {
                    const int64_t W = sz.w, H = sz.h, n = W * H * C;
                    DiffusionOptions o;
                    o.flux = flux;
                    o.iterations = 5;
                    o.log_domain = domain != 2;
                    o.conserve = domain == 0;
                    std::vector<float> mine(static_cast<size_t>(n));
                    for (float& v : mine) v = static_cast<float>(g(rng));
                    mine[0] = 1e5f;  // an HDR outlier: the log domain's reason
                    const std::vector<float> input = mine;
                    const DiffusionScale scale = diffusion_scale(input.data(), W, H, C, o);
                    diffuse_frame(mine.data(), W, H, C, o);
                    // The reference.
                    std::vector<double> u(input.begin(), input.end());
                    const auto to_log = [&](double v) { return std::copysign(std::log1p(std::fabs(v) / scale.eps), v); };
                    if (o.log_domain && !o.conserve)
                        for (double& v : u) v = to_log(v);
                    if (scale.k > 0)
                        for (int it = 0; it < o.iterations; ++it) {
                            std::vector<double> e = u;  // the values the edges are measured on
                            if (o.log_domain && o.conserve)
                                for (double& v : e) v = to_log(v);
                            const auto weight = [&](int64_t a, int64_t b) {  // pixels a and b
                                double g2 = 0;
                                for (int64_t c = 0; c < C; ++c) g2 += (e[b * C + c] - e[a * C + c]) * (e[b * C + c] - e[a * C + c]);
                                const double r = g2 / C / (scale.k * scale.k);
                                return o.dt * (flux == DiffusionFlux::PeronaMalik ? std::exp(-r) : 1.0 / std::sqrt(1.0 + r));
                            };
                            std::vector<double> next = u;
                            for (int64_t y = 0; y < H; ++y)
                                for (int64_t x = 0; x < W; ++x) {
                                    const int64_t p = y * W + x;
                                    std::vector<int64_t> neighbours;
                                    if (x > 0) neighbours.push_back(p - 1);
                                    if (x + 1 < W) neighbours.push_back(p + 1);
                                    if (y > 0) neighbours.push_back(p - W);
                                    if (y + 1 < H) neighbours.push_back(p + W);
                                    for (const int64_t q : neighbours) {
                                        const double w = weight(p, q);
                                        for (int64_t c = 0; c < C; ++c) next[p * C + c] += w * (u[q * C + c] - u[p * C + c]);
                                    }
                                }
                            u = next;
                        }
                    if (o.log_domain && !o.conserve)
                        for (double& v : u) v = std::copysign(scale.eps * std::expm1(std::fabs(v)), v);
                    for (int64_t i = 0; i < n; ++i)
                        ASSERT_NEAR(mine[static_cast<size_t>(i)], u[static_cast<size_t>(i)], 1e-5 * std::fabs(u[static_cast<size_t>(i)]) + 1e-30)
                            << W << " x " << H << " x " << C << ", domain " << domain << ", sample " << i;
                    if (W * H > 1 && scale.k > 0) {
                        EXPECT_NE(mine, input) << W << " x " << H << " x " << C;  // a diffusion, not a copy
                    }
                }
}
