// The firefly search (lib/temporal_outliers.cpp) judges each series on its own, with the rows around
// its tile for the neighbours' residuals: the list it finds is the same whatever the budget cuts the
// frame into (one tile, or many, each with its halo rows), and it holds the planted fireflies.
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "statfilter/sequence.hpp"
#include "statfilter/temporal_outliers.hpp"

namespace statfilter {
namespace {

TEST(TemporalOutliers, TheSameFirefliesForAnyBudget) {
    const Shape s{16, 120, 37, 3};  // 4440 pixels: 5 tiles of the least size (1024 pixels)
    Sequence seq(s);
    std::mt19937 rng(3);
    std::gamma_distribution<float> noise(4.0f, 0.25f);  // mean 1, a 4-spp-like spread
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) seq.at(f, y, x, c) = (0.2f + 0.01f * x) * noise(rng);
    // Fireflies: lone samples hundreds of times the level, at the corners and beside the tiles' edges
    // (pixels 1024 and 2048: rows 27 and 55).
    const std::vector<std::array<int64_t, 3>> planted = {{2, 0, 0}, {5, 27, 25}, {9, 119, 36}, {11, 27, 24}, {15, 55, 13}, {7, 56, 13}};
    for (const auto& [f, y, x] : planted) seq.at(f, y, x, 1) = 300.0f;
    OutlierOptions o;
    o.z = 6;
    o.budget_bytes = 1e9;  // one tile
    const std::vector<TemporalOutlier> whole = find_temporal_outliers(seq, ChannelSelection::one(1), o);
    for (const auto& [f, y, x] : planted) {
        const int64_t series = y * s.width + x;
        bool found = false;
        for (const TemporalOutlier& t : whole) found = found || (t.frame == f && t.series == series);
        EXPECT_TRUE(found) << "the firefly at frame " << f << ", pixel " << x << "," << y;
    }
    EXPECT_LE(whole.size(), planted.size() + 8);  // a few of the noise's own tail at most
    // A low threshold takes in the noise's tail too: many borderline series, each decided by its own
    // median and deviation, which a tile's edge would shift if its halo rows were missing.
    o.z = 2.5;
    const std::vector<TemporalOutlier> many = find_temporal_outliers(seq, ChannelSelection::one(1), o);
    EXPECT_GT(many.size(), 50u);
    for (const double budget : {4e5, 1.0}) {  // 3 tiles a worker's share; the least tiles (1024 pixels)
        o.budget_bytes = budget;
        const std::vector<TemporalOutlier> tiled = find_temporal_outliers(seq, ChannelSelection::one(1), o);
        ASSERT_EQ(tiled.size(), many.size()) << "budget " << budget;
        for (size_t i = 0; i < many.size(); ++i) {
            EXPECT_EQ(tiled[i].frame, many[i].frame) << "budget " << budget;
            EXPECT_EQ(tiled[i].series, many[i].series) << "budget " << budget;
            EXPECT_EQ(tiled[i].value, many[i].value) << "budget " << budget;
        }
    }
}

}  // namespace
}  // namespace statfilter
