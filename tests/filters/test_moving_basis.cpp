// Moving basis: the banded-operator implementation against a plain per-window weighted PCA.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "filter_runner.hpp"
#include "pipeline/moving_basis_operator.hpp"
#include "synthetic.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

// Per-window weighted PCA done the plain way: gather the window, centre with the weights, scale by
// sqrt(w), eigendecompose with OpenCV, reconstruct every frame of the window.
cv::Mat window_pca(const Sequence& in, FrameWindow w, const std::vector<double>& weights, int rank) {
    const Shape& s = in.shape();
    const int W = static_cast<int>(w.size()), n = static_cast<int>(s.pixels() * s.channels);
    cv::Mat X(W, n, CV_64F);
    for (int i = 0; i < W; ++i)
        for (int64_t p = 0; p < s.pixels(); ++p)
            for (int64_t c = 0; c < s.channels; ++c)
                X.at<double>(i, static_cast<int>(p * s.channels + c)) = in.at(w.first + i, p / s.width, p % s.width, c);
    cv::Mat mean = cv::Mat::zeros(1, n, CV_64F);
    for (int i = 0; i < W; ++i) mean += weights[i] * X.row(i);
    cv::Mat Z(W, n, CV_64F);
    for (int i = 0; i < W; ++i) Z.row(i) = std::sqrt(weights[i]) * (X.row(i) - mean);
    cv::Mat gram = Z * Z.t(), values, vectors;
    cv::eigen(gram, values, vectors);  // rows of vectors, descending
    cv::Mat U = vectors.rowRange(0, rank).t();
    cv::Mat Zk = U * (U.t() * Z);
    cv::Mat out(W, n, CV_64F);
    for (int i = 0; i < W; ++i) out.row(i) = Zk.row(i) / std::sqrt(weights[i]) + mean;
    return out;
}

std::unique_ptr<Sequence> moving_basis_reference(const Sequence& in, int64_t h, double sigma, int rank,
                                                 const std::string& mode) {
    const Shape& s = in.shape();
    const int64_t F = s.frames;
    auto out = std::make_unique<Sequence>(s);
    const int n = static_cast<int>(s.pixels() * s.channels);
    cv::Mat sum = cv::Mat::zeros(static_cast<int>(F), n, CV_64F);
    std::vector<double> blend(static_cast<size_t>(F), 0.0);
    for (int64_t c = 0; c < F; ++c) {
        const FrameWindow w = frame_window(c, h, F);
        const cv::Mat rec = window_pca(in, w, window_weights(w, c, sigma, mode == "basis"), rank);
        if (mode != "reconstruction") {
            rec.row(static_cast<int>(c - w.first)).copyTo(sum.row(static_cast<int>(c)));
            blend[c] = 1;
            continue;
        }
        for (int64_t t = w.first; t <= w.last; ++t) {
            const double b = std::exp(-0.5 * (t - c) * (t - c) / (sigma * sigma));
            sum.row(static_cast<int>(t)) += b * rec.row(static_cast<int>(t - w.first));
            blend[t] += b;
        }
    }
    for (int64_t f = 0; f < F; ++f)
        for (int64_t p = 0; p < s.pixels(); ++p)
            for (int64_t ch = 0; ch < s.channels; ++ch)
                out->at(f, p / s.width, p % s.width, ch) =
                    static_cast<float>(sum.at<double>(static_cast<int>(f), static_cast<int>(p * s.channels + ch)) / blend[f]);
    return out;
}

}  // namespace

TEST(MovingBasis, MatchesPlainPerWindowPca) {
    LowRank g;
    g.frames = 20;
    g.height = 12;
    g.width = 10;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    for (const std::string mode : {"basis", "uniform", "reconstruction"})
        for (int rank : {1, 2}) {
            const FilterRun r = run_linear("moving-basis", *noisy, {{"weights", mode}, {"rank", std::to_string(rank)},
                                                              {"half_width", "4"}, {"sigma", "2"}});
            EXPECT_LT(max_abs_diff(*r.output, *moving_basis_reference(*noisy, 4, 2.0, rank, mode)), 2e-5)
                << mode << " rank " << rank;
        }
}

TEST(MovingBasis, FullRankWindowsReproduceTheInput) {
    LowRank g;
    g.frames = 9;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    const FilterRun r = run_linear("moving-basis", *noisy, {{"rank", "100"}, {"half_width", "3"}});
    EXPECT_LT(max_abs_diff(*r.output, *noisy), 1e-5);
}

TEST(MovingBasis, WindowsWiderThanTheSequenceAndSingleFrames) {
    LowRank g;
    g.frames = 5;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    const FilterRun wide = run_linear("moving-basis", *noisy, {{"rank", "1"}, {"half_width", "50"}, {"weights", "uniform"}});
    // A window covering everything is global PCA.
    EXPECT_LT(max_abs_diff(*wide.output, *run_linear("pca", *noisy, {{"rank", "1"}}).output), 1e-5);
    g.frames = 1;
    const auto one = make_low_rank(g);
    EXPECT_EQ(max_abs_diff(*run_linear("moving-basis", *one).output, *one), 0.0);
}

TEST(MovingBasis, FrameWindowIsOneSidedAtTheEnds) {
    EXPECT_EQ(frame_window(0, 3, 10).first, 0);
    EXPECT_EQ(frame_window(0, 3, 10).last, 3);
    EXPECT_EQ(frame_window(9, 3, 10).first, 6);
    EXPECT_EQ(frame_window(9, 3, 10).last, 9);
    EXPECT_EQ(frame_window(5, 3, 10).size(), 7);
}
