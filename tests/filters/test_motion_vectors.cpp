// The renderer's motion vectors (Cycles' Vector pass) as the flow of motion compensation: a camera pan
// followed through chained vectors in Cycles' convention (and not with the signs flipped), an object
// that uncovers the background dropped by the forward-backward check, pixels without vectors on the
// optical flow, shapes checked.
#include <gtest/gtest.h>

#include <cmath>

#include "filter_runner.hpp"
#include "moving_scenes.hpp"
#include "synthetic.hpp"
#include "statfilter/error.hpp"
#include "statfilter/motion_compensation.hpp"

using namespace statfilter;
using namespace statfilter::test;

namespace {

// Vectors of content moving by (dx, dy) pixels a frame (rows downward), in Cycles' convention: the
// point at (x, y) is at (x + X, y - Y) in the previous frame and at (x - Z, y + W) in the next.
void set_motion(Sequence& v, int64_t f, int64_t y, int64_t x, float dx, float dy) {
    v.at(f, y, x, 0) = -dx;
    v.at(f, y, x, 1) = dy;
    v.at(f, y, x, 2) = -dx;
    v.at(f, y, x, 3) = dy;
}

std::unique_ptr<Sequence> uniform_vectors(const Shape& s, float dx, float dy) {
    auto v = std::make_unique<Sequence>(Shape{s.frames, s.height, s.width, 4});
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x) set_motion(*v, f, y, x, dx, dy);
    return v;
}

double interior_mse(const Sequence& a, const Sequence& b, int64_t margin) {
    const Shape& s = a.shape();
    double e = 0;
    int64_t n = 0;
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = margin; y < s.height - margin; ++y)
            for (int64_t x = margin; x < s.width - margin; ++x)
                for (int64_t c = 0; c < s.channels; ++c, ++n) e += std::pow(double(a.at(f, y, x, c)) - b.at(f, y, x, c), 2);
    return e / static_cast<double>(n);
}

AlignedAverageStats average(const Sequence& input, const Sequence& estimate, Sequence& out, const AlignedAverageOptions& o) {
    const Progress progress;
    return aligned_average(input, estimate, nullptr, {}, o, out, {progress, 0, 1, "test"});
}

}  // namespace

// The pan moves the content left by 2 pixels a frame: the vectors line up all 9 frames (chained up to
// 4 steps) and the average removes most of the noise; flipped signs follow the wrong way and smear.
TEST(MotionVectors, ChainedVectorsFollowACameraPan) {
    const Pan s = pan_scene(9, 48, 64, 2, 0.3);
    const auto right = uniform_vectors(s.noisy->shape(), -2, 0), wrong = uniform_vectors(s.noisy->shape(), 2, 0);
    AlignedAverageOptions o;
    o.half_width = 4;
    o.sigma = 1e9;  // no weighting by the first pass: only the vectors align
    o.vectors = right.get();
    Sequence out(s.noisy->shape()), flipped(s.noisy->shape());
    const AlignedAverageStats stats = average(*s.noisy, *s.clean, out, o);
    o.vectors = wrong.get();
    average(*s.noisy, *s.clean, flipped, o);
    const double noisy = interior_mse(*s.noisy, *s.clean, 10);
    EXPECT_GT(stats.mean_frames, 6.0);
    EXPECT_LT(interior_mse(out, *s.clean, 10), 0.2 * noisy);
    EXPECT_GT(interior_mse(flipped, *s.clean, 10), 3.0 * interior_mse(out, *s.clean, 10));
}

// A bright square slides right by 3 pixels a frame over a dark background that is still (its vectors
// a negligible 1e-4 pixels a frame: given, not absent), noise-free. The background it uncovers lands
// on the square in the earlier frames, whose vectors point elsewhere: the forward-backward check drops
// those samples, so the uncovered background stays exactly 1 and the square exactly 10, with no
// weighting by the first pass at all.
TEST(MotionVectors, ForwardBackwardCheckDropsOccludedSamples) {
    const Shape shape{9, 32, 64, 1};
    Sequence clean(shape);
    auto vectors = std::make_unique<Sequence>(Shape{9, 32, 64, 4});
    for (int64_t f = 0; f < 9; ++f)
        for (int64_t y = 0; y < 32; ++y)
            for (int64_t x = 0; x < 64; ++x) {
                const bool square = y >= 10 && y < 22 && x >= 10 + 3 * f && x < 22 + 3 * f;
                clean.at(f, y, x, 0) = square ? 10.0f : 1.0f;
                set_motion(*vectors, f, y, x, square ? 3.0f : 1e-4f, 0.0f);
            }
    AlignedAverageOptions o;
    o.half_width = 4;
    o.sigma = 1e9;
    o.transform = ValueTransform::None;
    o.vectors = vectors.get();
    Sequence out(shape);
    out.copy_samples_from(clean);  // the first pass, which a pixel the other frames do not reach keeps
    average(clean, clean, out, o);
    EXPECT_LT(max_abs_diff(out, clean), 1e-4);
}

// Cycles writes exact zeros where no geometry is hit: such pixels follow the optical flow instead, so
// all-zero vectors give exactly the flow's result (the pan is then followed all the same).
TEST(MotionVectors, PixelsWithoutVectorsFollowTheFlow) {
    const Pan s = pan_scene(9, 48, 64, 1, 0.3);
    const Sequence none(Shape{9, 48, 64, 4});
    AlignedAverageOptions o;
    o.half_width = 4;
    Sequence flow(s.noisy->shape()), zero(s.noisy->shape());
    average(*s.noisy, *s.clean, flow, o);
    o.vectors = &none;
    average(*s.noisy, *s.clean, zero, o);
    EXPECT_EQ(max_abs_diff(flow, zero), 0.0);
    EXPECT_LT(interior_mse(zero, *s.clean, 8), 0.25 * interior_mse(*s.noisy, *s.clean, 8));
}

TEST(MotionVectors, ShapesAreChecked) {
    const Pan s = pan_scene(4, 20, 24, 0, 0.0);
    Sequence three(Shape{4, 20, 24, 3}), short_(Shape{3, 20, 24, 4});
    AlignedAverageOptions o;
    Sequence out(s.clean->shape());
    o.vectors = &three;
    EXPECT_THROW(average(*s.clean, *s.clean, out, o), Error);
    o.vectors = &short_;
    EXPECT_THROW(average(*s.clean, *s.clean, out, o), Error);
}
