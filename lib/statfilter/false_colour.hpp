// Image results for people: a value in [0, 1] as a colour on one ramp, dark blue (0) through teal to
// yellow (1). `statfilter denoise --save NAME=x.png`, a plan's image tasks and the detect preview
// all use it, so the same result is the same picture wherever it was made.
#pragma once
#include <memory>

#include "statfilter/sequence.hpp"

namespace statfilter {

// t is clamped to [0, 1]; a value that is not a number is 0.
void false_colour(float t, float* rgb);

// Every frame's first channel through the ramp: frames x H x W x 3 (channels R, G, B), with the
// image's frame numbers.
std::unique_ptr<Sequence> false_colour_preview(const Sequence& image);

}  // namespace statfilter
