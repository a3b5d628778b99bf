// The median and median absolute deviation of many series at once, against a plain sort of each
// series: the sorting network, the side-by-side lanes and their fallbacks must give the same values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "statfilter/robust_series.hpp"

using namespace statfilter;

namespace {

// The reference: sort, take the middle; the deviations sorted, their middle.
std::pair<double, double> by_sorting(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size(), mid = n / 2;
    const double m = n % 2 ? v[mid] : 0.5 * (v[mid] + v[mid - 1]);
    for (double& x : v) x = std::fabs(x - m);
    std::sort(v.begin(), v.end());
    return {m, n % 2 ? v[mid] : 0.5 * (v[mid] + v[mid - 1])};
}

// values[f * stride + j]: `count` series of `frames` samples, a few spare columns beyond them.
struct Block {
    int64_t frames, count, stride;
    std::vector<double> values;
    Block(int64_t f, int64_t c) : frames(f), count(c), stride(c + 3), values(static_cast<size_t>(f * (c + 3)), -1e300) {}
    double& at(int64_t f, int64_t j) { return values[static_cast<size_t>(f * stride + j)]; }
    std::vector<double> series(int64_t j) {
        std::vector<double> v;
        for (int64_t f = 0; f < frames; ++f) v.push_back(at(f, j));
        return v;
    }
};

void expect_as_sorted(Block& b) {
    std::vector<float> median(static_cast<size_t>(b.count) + 1, 7.0f), deviation(median.size(), 7.0f);
    medians_and_deviations(b.values.data(), b.stride, b.frames, b.count, 1.4826, median.data(), deviation.data());
    for (int64_t j = 0; j < b.count; ++j) {
        const auto [m, mad] = by_sorting(b.series(j));
        EXPECT_EQ(median[j], static_cast<float>(m)) << "series " << j << " of " << b.frames << " frames";
        EXPECT_EQ(deviation[j], static_cast<float>(1.4826 * mad)) << "series " << j << " of " << b.frames << " frames";
    }
    EXPECT_EQ(median[b.count], 7.0f) << "wrote beyond the last series";
}

}  // namespace

TEST(SortingNetwork, SortsEveryZeroOneInput) {
    // A comparator network that sorts every 0/1 input sorts every input (Knuth's 0-1 principle).
    for (int64_t n = 0; n <= 18; ++n) {
        const std::vector<Comparator> network = sorting_network(n);
        for (uint32_t bits = 0; bits < (1u << n); ++bits) {
            std::vector<int> v(static_cast<size_t>(n));
            for (int64_t i = 0; i < n; ++i) v[i] = (bits >> i) & 1;
            for (const Comparator& c : network)
                if (v[c.second] < v[c.first]) std::swap(v[c.first], v[c.second]);
            ASSERT_TRUE(std::is_sorted(v.begin(), v.end())) << "n " << n << " input " << bits;
        }
    }
}

TEST(SortingNetwork, SortsRandomInputsOfAnyLength) {
    std::mt19937 rng(5);
    for (int64_t n : {19, 31, 32, 33, 100, 200, 256, 300}) {
        const std::vector<Comparator> network = sorting_network(n);
        for (int trial = 0; trial < 20; ++trial) {
            std::vector<int> v(static_cast<size_t>(n));
            for (int& x : v) x = static_cast<int>(rng() % 50);  // ties too
            for (const Comparator& c : network) {
                ASSERT_LT(c.first, c.second);
                if (v[c.second] < v[c.first]) std::swap(v[c.first], v[c.second]);
            }
            ASSERT_TRUE(std::is_sorted(v.begin(), v.end())) << "n " << n;
        }
    }
}

TEST(RobustSeries, GivesTheValuesOfASortForAnyFrameAndSeriesCount) {
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.4, 0.1);
    // Past 256 frames each series is sorted alone; counts not a multiple of the lanes leave a tail.
    for (int64_t frames : {1, 2, 3, 4, 7, 32, 33, 200, 256, 257})
        for (int64_t count : {1, 3, 4, 5, 9, 17}) {
            Block b(frames, count);
            for (int64_t f = 0; f < frames; ++f)
                for (int64_t j = 0; j < count; ++j) b.at(f, j) = j % 3 == 2 ? std::round(noise(rng) * 10) : noise(rng);
            expect_as_sorted(b);
        }
}

TEST(RobustSeries, ExtremesConstantsAndNonFiniteSamples) {
    constexpr double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
    const int64_t frames = 32, count = 8;
    Block b(frames, count);
    for (int64_t f = 0; f < frames; ++f) {
        b.at(f, 0) = 0.25;                                         // constant: deviation exactly 0
        b.at(f, 1) = 0.0;                                          // zero
        b.at(f, 2) = f % 2 ? 1e300 : -1e300;                       // huge, no overflow in |x - m|
        b.at(f, 3) = 1e-300 * (f + 1);                             // tiny
        b.at(f, 4) = f == 5 ? 1e30 : 1.0 + 0.01 * (f % 7);         // a spike moves neither
        b.at(f, 5) = f == 9 ? inf : 0.5 + 0.001 * f;               // non-finite: as median_and_deviation
        b.at(f, 6) = f == 3 ? nan : 0.5 - 0.001 * f;
        b.at(f, 7) = -0.3 - 0.01 * ((f * 7) % 11);                 // negative
    }
    std::vector<float> median(count), deviation(count);
    medians_and_deviations(b.values.data(), b.stride, frames, count, 1.0, median.data(), deviation.data());
    EXPECT_EQ(median[0], 0.25f);
    EXPECT_EQ(deviation[0], 0.0f);
    EXPECT_EQ(median[1], 0.0f);
    EXPECT_EQ(deviation[1], 0.0f);
    EXPECT_EQ(median[2], 0.0f);  // the mean of -1e300 and 1e300
    EXPECT_EQ(deviation[2], static_cast<float>(1e300));  // beyond float: rounds to Inf, as a cast does
    for (int64_t j : {3, 4, 7}) {
        const auto [m, mad] = by_sorting(b.series(j));
        EXPECT_EQ(median[j], static_cast<float>(m)) << j;
        EXPECT_EQ(deviation[j], static_cast<float>(mad)) << j;
    }
    EXPECT_LT(median[4], 1.1f);
    for (int64_t j : {5, 6}) {
        std::vector<double> v = b.series(j);
        const auto [m, mad] = median_and_deviation(v);
        EXPECT_EQ(median[j], static_cast<float>(m)) << j;
        EXPECT_EQ(deviation[j], static_cast<float>(mad)) << j;
    }
    // The other series of a block holding a NaN (sorted one by one there) get the same values.
    const auto [m7, mad7] = by_sorting(b.series(7));
    EXPECT_EQ(median[7], static_cast<float>(m7));
    EXPECT_EQ(deviation[7], static_cast<float>(mad7));
}

TEST(RobustSeries, MedianOfOddAndEvenCounts) {
    std::vector<double> odd = {5, 1, 3}, even = {4, 1, 3, 2};
    EXPECT_EQ(median_of(odd), 3.0);
    EXPECT_EQ(median_of(even), 2.5);
    std::vector<double> v = {1, 2, 3, 4, 100};
    const auto [m, mad] = median_and_deviation(v);
    EXPECT_EQ(m, 3.0);
    EXPECT_EQ(mad, 1.0);
}
