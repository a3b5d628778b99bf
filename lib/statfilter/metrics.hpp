// Error of a filtered sequence against a reference, as the project measures it (DESIGN section 7).
#pragma once
#include "statfilter/sequence.hpp"

namespace statfilter {

struct Comparison {
    double rel_mse = 0;          // mean((x - ref)^2 / (ref^2 + 0.01)) over every sample
    double rel_mse_moving = 0;   // the same over pixels whose reference varies most over time
    double rel_mse_static = 0;   // ... and over the rest
    double moving_fraction = 0;  // share of pixels in the moving region (temporal std > 3x median)
    double psnr = 0;             // dB, on tonemapped values x / (1 + x)
    double flicker = 0;          // mean |(x_t - x_t-1) - (ref_t - ref_t-1)|, tonemapped
    double jitter = 0;           // mean |x_t+1 - 2 x_t + x_t-1| of tonemapped luminance on still pixels
};

Comparison compare_sequences(const Sequence& test, const Sequence& reference);

}  // namespace statfilter
