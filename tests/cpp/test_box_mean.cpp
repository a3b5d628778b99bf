// The box mean the per-pixel ranks and alpha pool with: the same values as OpenCV's box filter up to
// rounding; and, unlike a running sum, the same bits whatever the threads or the rows around a band,
// exact zeros where a box holds only zeros beside huge values, and a NaN kept inside its own boxes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "statfilter/box_mean.hpp"

namespace statfilter {
namespace {

std::vector<double> random_plane(int64_t h, int64_t w, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> v(static_cast<size_t>(h * w));
    for (double& x : v) x = std::pow(10.0, 8.0 * u(rng) - 4.0);  // 1e-4 .. 1e4
    return v;
}

// The mean over a box written out in long double, mirrored indices spelled out.
double exact_mean(const std::vector<double>& v, int64_t h, int64_t w, int side, int64_t y, int64_t x) {
    const auto mirror = [](int64_t i, int64_t n) { return i < 0 ? -i - 1 : (i >= n ? 2 * n - i - 1 : i); };
    long double sum = 0;
    for (int64_t dy = 0; dy < side; ++dy)
        for (int64_t dx = 0; dx < side; ++dx)
            sum += v[static_cast<size_t>(mirror(y - side / 2 + dy, h) * w + mirror(x - side / 2 + dx, w))];
    return static_cast<double>(sum / (static_cast<long double>(side) * side));
}

TEST(BoxMean, IsTheMeanOfItsBoxAsOpenCVsBoxFilterWithoutItsResidue) {
    for (const int side : {2, 3, 9}) {
        const int64_t h = 23, w = 31;
        const std::vector<double> input = random_plane(h, w, 7);
        std::vector<double> ours = input, theirs = input;
        box_mean(ours.data(), h, w, side, 1);
        cv::Mat m(static_cast<int>(h), static_cast<int>(w), CV_64F, theirs.data());
        cv::boxFilter(m, m, -1, cv::Size(side, side), cv::Point(-1, -1), true, cv::BORDER_REFLECT);
        double largest = 0;
        for (double x : input) largest = std::max(largest, x);
        for (int64_t y = 0; y < h; ++y)
            for (int64_t x = 0; x < w; ++x) {
                const double exact = exact_mean(input, h, w, side, y, x);
                const size_t i = static_cast<size_t>(y * w + x);
                // Ours: rounding relative to the box's own values. OpenCV's running sum: relative to
                // the largest value the sum has passed (its residue; the reason for box_mean).
                EXPECT_NEAR(ours[i], exact, 1e-14 * exact) << side << " " << y << " " << x;
                EXPECT_NEAR(theirs[i], exact, 1e-14 * largest) << side << " " << y << " " << x;
            }
    }
}

TEST(BoxMean, SameBitsWhateverTheThreadsOrTheBand) {
    const int64_t h = 40, w = 17;
    const int side = 9, halo = side / 2;
    std::vector<double> whole = random_plane(h, w, 11);
    const std::vector<double> input = whole;
    box_mean(whole.data(), h, w, side, 1);
    for (const int threads : {2, 3, 8}) {
        std::vector<double> again = input;
        box_mean(again.data(), h, w, side, threads);
        EXPECT_EQ(again, whole) << threads << " threads";
    }
    // A band of rows 10..20 with its halo: its own rows are the whole plane's, bit for bit.
    const int64_t y0 = 10, y1 = 20, a = y0 - halo, b = y1 + halo;
    std::vector<double> band(input.begin() + a * w, input.begin() + b * w);
    box_mean(band.data(), b - a, w, side, 2);
    for (int64_t y = y0; y < y1; ++y)
        for (int64_t x = 0; x < w; ++x) EXPECT_EQ(band[static_cast<size_t>((y - a) * w + x)], whole[static_cast<size_t>(y * w + x)]);
}

TEST(BoxMean, ZerosBesideHugeValuesStayExactlyZero) {
    const int64_t h = 12, w = 40;
    const int side = 5;
    std::vector<double> v(static_cast<size_t>(h * w), 0.0);
    for (int64_t y = 0; y < h; ++y)
        for (int64_t x = 0; x < 10; ++x) v[static_cast<size_t>(y * w + x)] = 1e30 * (1 + 0.37 * ((x * 7 + y * 3) % 11));
    box_mean(v.data(), h, w, side, 2);
    for (int64_t y = 0; y < h; ++y) {
        EXPECT_GT(v[static_cast<size_t>(y * w + 11)], 0.0);  // its box reaches the bright columns
        for (int64_t x = 12; x < w; ++x) EXPECT_EQ(v[static_cast<size_t>(y * w + x)], 0.0) << y << " " << x;
    }
}

TEST(BoxMean, ANaNStaysInsideItsBoxes) {
    const int64_t h = 9, w = 9;
    std::vector<float> v(static_cast<size_t>(h * w), 2.0f);
    v[static_cast<size_t>(4 * w + 4)] = std::numeric_limits<float>::quiet_NaN();
    box_mean(v.data(), h, w, 3, 1);
    for (int64_t y = 0; y < h; ++y)
        for (int64_t x = 0; x < w; ++x) {
            const bool reached = std::abs(y - 4) <= 1 && std::abs(x - 4) <= 1;
            if (reached) EXPECT_TRUE(std::isnan(v[static_cast<size_t>(y * w + x)]));
            else EXPECT_FLOAT_EQ(v[static_cast<size_t>(y * w + x)], 2.0f) << y << " " << x;
        }
}

TEST(BoxMean, BoxesWiderThanThePlaneMirrorAgain) {
    // One row [1, 3], side 5: columns -2..2 mirror to 1, 0, 0, 1, 1 -> 3 + 1 + 1 + 3 + 3 = 11; the
    // five rows all mirror to row 0: 5 x 11 / 25.
    std::vector<double> v = {1.0, 3.0};
    box_mean(v.data(), 1, 2, 5, 1);
    EXPECT_DOUBLE_EQ(v[0], 55.0 / 25.0);
    std::vector<double> one = {4.0};
    box_mean(one.data(), 1, 1, 7, 2);
    EXPECT_DOUBLE_EQ(one[0], 4.0);
    std::vector<double> same = {1.0, 2.0};
    box_mean(same.data(), 1, 2, 1, 1);  // side 1: nothing to pool
    EXPECT_EQ(same, (std::vector<double>{1.0, 2.0}));
}

}  // namespace
}  // namespace statfilter
