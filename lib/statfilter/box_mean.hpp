// The mean over a side x side box around each pixel of one plane, mirrored at the edges (as
// cv::BORDER_REFLECT: fedcba|abcdef), each sum taken directly, left to right and top to bottom.
// A running sum (cv::boxFilter) leaves a rounding residue that depends on where it started (a
// thread's stripe, a band of rows), and on a flat region of zeros that residue alone decided the
// error threshold's per-pixel ranks: they changed with the thread count and the bands. Here every
// output depends on its box's values only, whatever the threads or the rows around it.
#pragma once
#include <cstdint>

namespace statfilter {

// plane: height x width, row-major, pooled in place; side <= 1 leaves it as it is. An even side's box
// spans x - side/2 .. x - side/2 + side - 1 (the anchor cv::boxFilter takes by default).
void box_mean(double* plane, int64_t height, int64_t width, int side, int threads);
void box_mean(float* plane, int64_t height, int64_t width, int side, int threads);

}  // namespace statfilter
