// The error threshold method: per-pixel truncation from pooled coefficient energy.
#include <gtest/gtest.h>

#include "filter_runner.hpp"
#include "pipeline/parallel.hpp"
#include "synthetic.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

// Left half: a strong rank-2 temporal signal; right half: constant. Both with the same noise.
std::unique_ptr<Sequence> half_moving(std::unique_ptr<Sequence>* clean) {
    LowRank g;
    g.rank = 2;
    g.amplitude = 1.0;
    g.noise = 0.05;
    auto noisy = make_low_rank(g, clean);
    for (int64_t f = 0; f < g.frames; ++f)
        for (int64_t y = 0; y < g.height; ++y)
            for (int64_t x = g.width / 2; x < g.width; ++x)
                for (int64_t c = 0; c < g.channels; ++c) {
                    const float offset = noisy->at(f, y, x, c) - (*clean)->at(f, y, x, c);
                    (*clean)->at(f, y, x, c) = 1.0f;
                    noisy->at(f, y, x, c) = 1.0f + offset;
                }
    return noisy;
}

double mean_rank(const Sequence& map, int64_t x0, int64_t x1) {
    double sum = 0;
    for (int64_t y = 0; y < map.shape().height; ++y)
        for (int64_t x = x0; x < x1; ++x) sum += map.at(0, y, x, 0);
    return sum / (map.shape().height * (x1 - x0));
}

}  // namespace

TEST(ErrorThreshold, RankMapFollowsWhereTheSignalIs) {
    std::unique_ptr<Sequence> clean;
    const auto noisy = half_moving(&clean);
    const FilterRun r = run_filter("error-threshold", *noisy);
    const auto map = r.filter->results().image("rank_map");
    ASSERT_EQ(map->shape(), (Shape{1, 30, 40, 1}));
    EXPECT_EQ(map->channel_names()[0], "rank");
    // Away from the border the pooling window straddles.
    EXPECT_GT(mean_rank(*map, 0, 14), 1.8);
    EXPECT_LT(mean_rank(*map, 26, 40), 0.2);
    EXPECT_LT(mse(*r.output, *clean), mse(*noisy, *clean) / 5);
    // Beats one global rank on such a scene.
    EXPECT_LT(mse(*r.output, *clean), mse(*run_filter("pca", *noisy, {{"rank", "auto"}}).output, *clean));
}

TEST(ErrorThreshold, ZeroThresholdKeepsEveryComponentLikePca) {
    LowRank g;
    g.noise = 0.1;
    const auto noisy = make_low_rank(g);
    const FilterRun et = run_filter("error-threshold", *noisy, {{"threshold", "0"}, {"max_rank", "4"}});
    EXPECT_DOUBLE_EQ(et.result("mean_rank"), 4.0);
    EXPECT_LT(max_abs_diff(*et.output, *run_filter("pca", *noisy, {{"rank", "4"}}).output), 1e-6);
}

TEST(ErrorThreshold, FewFramesFallBackToTheGlobalNoiseEstimate) {
    LowRank g;
    g.frames = 4;
    g.noise = 0.05;
    const auto noisy = make_low_rank(g);
    const FilterRun r = run_filter("error-threshold", *noisy, {{"max_rank", "8"}});  // no tail left
    EXPECT_TRUE(all_finite(*r.output));
    EXPECT_LE(r.result("mean_rank"), 3.0);
}

TEST(ErrorThreshold, ConstantAndSingleFrameAreUnchanged) {
    Sequence constant(Shape{8, 5, 6, 1});
    for (int64_t f = 0; f < 8; ++f)
        for (int64_t y = 0; y < 5; ++y)
            for (int64_t x = 0; x < 6; ++x) constant.at(f, y, x, 0) = 2.5f;
    EXPECT_EQ(max_abs_diff(*run_filter("error-threshold", constant).output, constant), 0.0);
    LowRank g;
    g.frames = 1;
    const auto one = make_low_rank(g);
    EXPECT_EQ(max_abs_diff(*run_filter("error-threshold", *one).output, *one), 0.0);
}

// A black region beside a bright one: its pooled energies are exact zeros, so its rank is 0 (a
// running sum's rounding residue used to decide it, differently with the threads), and the rank map
// is the same bits on any number of threads.
TEST(ErrorThreshold, ABlackRegionsRanksAreZeroWhateverTheThreads) {
    LowRank g;
    g.amplitude = 0.5;
    g.noise = 0.05;
    g.height = 24;
    g.width = 48;
    auto scene = make_low_rank(g);
    for (int64_t f = 0; f < g.frames; ++f)
        for (int64_t y = 0; y < g.height; ++y)
            for (int64_t x = 0; x < g.width; ++x)
                for (int64_t c = 0; c < g.channels; ++c) {
                    float& v = scene->at(f, y, x, c);
                    v = x < 16 ? v * 3e4f : 0.0f;  // bright on the left, black from column 16
                }
    std::vector<std::shared_ptr<const Sequence>> maps;
    for (const int threads : {1, 2, 3}) {
        const ThreadLimit limit(threads);
        maps.push_back(run_filter("error-threshold", *scene, {{"firefly_z", "0"}}).filter->results().image("rank_map"));
    }
    const Sequence& map = *maps.front();
    EXPECT_GT(mean_rank(map, 0, 10), 1.0);
    EXPECT_EQ(mean_rank(map, 16 + 9 / 2, g.width), 0.0);  // boxes that hold only black pixels
    for (size_t i = 1; i < maps.size(); ++i) EXPECT_EQ(max_abs_diff(*maps[i], map), 0.0) << i;
}
