// Where temporal filtering can be trusted.
//  alpha(x), one value per pixel, 1 = stationary: from the energy of the leading temporal
//    components at each pixel (the study sums |B_1..B_k|, the leading spatial basis vectors),
//    measured in units of the noise those components would carry anyway (the larger of the global
//    noise level and the pixel's own, from its energy beyond those components). A global light change
//    also lands in the leading components; it is explained across all series by a constant plus a
//    multiple of the mean image, so that part is removed first (global_light=ignore).
//  beta(x, t), per pixel and frame, 1 = moving now: robust temporal z-scores of the pixel's
//    luminance, averaged over a small window and thresholded, then dilated; or, when the renderer's
//    albedo/normal passes are given, their departure from the pixel's temporal median, which noise
//    cannot fake.
#pragma once
#include <memory>
#include <string>

#include "statfilter/prepared_series.hpp"
#include "statfilter/temporal_basis.hpp"

namespace statfilter {

struct GlobalMotionOptions {
    int components = 5;            // the caller passes only components that carry signal (see motion_params)
    bool local_noise = true;       // noise unit: max(global, this pixel's pooled energy beyond the components)
    bool ignore_global_light = true;
    double low = 2.0, high = 8.0;  // ramp from alpha 1 to 0, in multiples of the noise energy
    int window = 5;                // side of the box the energy is averaged over
};

// alpha as a 1-frame, 1-channel sequence.
std::shared_ptr<Sequence> global_motion_map(PreparedSeries& series, const TemporalBasis& basis, double noise_sigma,
                                            const GlobalMotionOptions& options, const ProgressSpan& progress);

struct LocalMotionOptions {
    double z_threshold = 2.5;
    int window = 5;    // side of the box the squared z-scores are averaged over
    int dilate = 2;    // pixels
};

// beta from z-scores: a F-frame, 1-channel sequence of 0/1.
std::shared_ptr<Sequence> local_motion_from_zscores(const Sequence& input, const LocalMotionOptions& options);

// beta from auxiliary passes (albedo, normal...): moving where any channel departs from the pixel's
// temporal median by more than threshold plus three robust standard deviations of that pixel (edges
// that flicker in every frame are not motion), opened to drop thin edge lines; the maps of several
// passes are combined with max.
std::shared_ptr<Sequence> local_motion_from_aux(const Sequence& aux, double threshold, int dilate);

void combine_max(Sequence& into, const Sequence& other);

}  // namespace statfilter
