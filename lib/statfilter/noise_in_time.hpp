// Whether a shot's noise changes from frame to frame. Every temporal filter here relies on it: a
// renderer that samples every frame with the same random seed (Blender's Cycles unless its seed is
// animated) leaves the same noise pattern on every still pixel, which no model of time can tell
// from the picture. Measured on pairs of consecutive frames, in log(1 + x / m) units (m: each frame's
// median positive sample, so a change of the light level between the two is no difference): the
// robust deviation of the change from one frame to the next against that of a pixel from the mean of
// its four neighbours, each scaled to one sample's noise. Independent noise gives a ratio near 1
// (0.88-0.99 on every level and reference of the development renders); the same seed on every frame
// leaves the change of the picture alone, near 0 on a still camera (0.00-0.32 on same-seed shots
// made from those renders: docs/methods.md, "Noise that is the same in every frame").
#pragma once
#include <cstdint>

namespace statfilter {

struct NoiseInTime {
    double temporal = 0;  // robust noise of a sample measured along time (0 when not measured)
    double spatial = 0;   // robust noise of a sample measured across the frame
    int64_t pairs = 0;    // frame pairs measured
    // temporal / spatial; 1 where nothing was measured (no pairs, or no noise across the frame)
    double ratio() const { return pairs > 0 && spatial > 0 ? temporal / spatial : 1.0; }
};

// Below this ratio the noise counts as the same in every frame: between the 0.32 of the most
// changing same-seed shot measured and the 0.88 of the least independent one.
constexpr double kSameNoiseRatio = 0.5;

// One pair: rows x width x channels samples of two consecutive frames a and b (contiguous, the same
// rows of each). Non-finite and negative samples are left out.
NoiseInTime measure_noise_in_time(const float* a, const float* b, int64_t rows, int64_t width, int64_t channels);

// The median, component by component, of several pairs' figures (pairs counts them).
NoiseInTime combine_noise_in_time(const NoiseInTime* pairs, int64_t count);

}  // namespace statfilter
