// Separate filter objects on separate threads give the sequential result bit for bit: the hybrid
// with motion compensation (optical flow per frame inside OpenCV's parallel loops) run on two
// std::threads at once against the same runs one after the other. The second test is the one for
// ThreadSanitizer: OpenCV's pool (TBB on Debian) and OpenBLAS's are not instrumented, so TSan cannot
// see their synchronisation and flags every parallel loop; with both serial (OpenCV here,
// OPENBLAS_NUM_THREADS=1 in the environment) the only concurrency left is the two filters' threads.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <string>
#include <thread>

#include <opencv2/core/utility.hpp>

#include "filter_runner.hpp"
#include "moving_scenes.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

bool bitwise_equal(const Sequence& a, const Sequence& b) {
    if (a.shape() != b.shape()) return false;
    const Shape& s = a.shape();
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) {
                    const float u = a.at(f, y, x, c), v = b.at(f, y, x, c);
                    if (std::memcmp(&u, &v, sizeof u) != 0) return false;
                }
    return true;
}

void two_hybrids_on_two_threads() {
    // Two different shots (a pan of one and of two pixels a frame), so a shared state would show.
    const Pan one = pan_scene(16, 48, 64, 1, 0.5), two = pan_scene(16, 48, 64, 2, 0.5);
    const std::map<std::string, std::string> params = {{"motion_compensation", "auto"}};
    const FilterRun first = run_filter("hybrid", *one.noisy, params);
    const FilterRun second = run_filter("hybrid", *two.noisy, params);
    ASSERT_EQ(first.filter->results().get_string("motion_compensation"), "optical flow on the first pass");
    ASSERT_GT(first.result("aligned_fraction"), 0.5);
    // Concurrency bugs show in some runs only: several trials, each must match.
    for (int trial = 0; trial < 4; ++trial) {
        FilterRun a, b;
        std::thread ta([&] { a = run_filter("hybrid", *one.noisy, params); });
        std::thread tb([&] { b = run_filter("hybrid", *two.noisy, params); });
        ta.join();
        tb.join();
        EXPECT_TRUE(bitwise_equal(*a.output, *first.output)) << "trial " << trial << ", first shot";
        EXPECT_TRUE(bitwise_equal(*b.output, *second.output)) << "trial " << trial << ", second shot";
    }
}

}  // namespace

TEST(MotionThreads, TwoHybridsOnTwoThreadsMatchTheSequentialRuns) { two_hybrids_on_two_threads(); }

TEST(MotionThreads, TwoHybridsOnTwoThreadsWithOpenCVSerial) {
    struct SerialOpenCV {
        const int threads = cv::getNumThreads();
        SerialOpenCV() { cv::setNumThreads(1); }
        ~SerialOpenCV() { cv::setNumThreads(threads); }
    } serial;
    two_hybrids_on_two_threads();
}
