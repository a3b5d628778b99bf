// Variance-stabilising transforms applied to each time series before temporal PCA and undone after.
// Render noise grows with brightness; sqrt (Anscombe-like) and log compress bright pixels so the
// shared basis is not led by them. Signed versions keep negative inputs valid and invertible.
// Both are taken relative to a scale s measured from the data (y = log(1 + |x| / s),
// y = sqrt(|x| / s)), so filtering k x gives k times the result of filtering x: renderers write
// radiance in whatever units the scene uses.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "statfilter/sequence.hpp"
#include "statfilter/time_series_tiles.hpp"

namespace statfilter {

enum class ValueTransform { None, Sqrt, Log };

ValueTransform parse_value_transform(const std::string& name);

// y = T(x / scale) and its exact inverse x = scale T^-1(y). scale must be > 0.
void forward_transform(ValueTransform t, double scale, double* values, size_t count);
void inverse_transform(ValueTransform t, double scale, double* values, size_t count);
// scale 1: log1p(|x|) and sqrt(|x|), the transforms before they were made relative to the data.
// Callers should measure the scale with transform_level and pass it instead.
void forward_transform(ValueTransform t, double* values, size_t count);
void inverse_transform(ValueTransform t, double* values, size_t count);

// The data's level for the transform's scale: the median magnitude of the non-zero finite samples
// of the channels `group` (robust to fireflies and to a black background), taken over a fixed subset
// of at most ~2^20 samples of the frames transform_level_frames picks, so any tiling of later passes
// (and a streamed run, which reads just those frames) sees the same value; 1 when there are none.
double transform_level(const Sequence& seq, ChannelSelection group);
// The frame indices the level is measured on: up to four, spread over the shot (all when <= 4).
std::vector<int64_t> transform_level_frames(int64_t frames);

// The way back without Jensen's bias. A transform's plain inverse of a denoised series is biased
// (for log, exp(E[y]) < E[exp(y)]: the output is darker than the input). This inverts the F samples
// values[0], values[stride], ... (transformed domain) with one correction per series, chosen so that
// the series' linear-domain mean equals target_mean: log scales (x + s) by a factor, sqrt scales x,
// none shifts x. With non_negative, output samples are clamped at 0 and the correction re-solved so
// the mean still holds. A target of 0 with non_negative gives all zeros.
void inverse_transform_keeping_mean(ValueTransform t, double scale, double* values, int64_t frames, int64_t stride,
                                    double target_mean, bool non_negative);

// The same in two steps, for a stage that rebuilds a series' frames one at a time: the correction is
// solved once from the series' linear-domain samples (after the plain inverse), then applied to each.
struct MeanCorrection {
    enum Kind : uint8_t { Shift, Scale, Constant } kind = Shift;  // x + p; x + p (x + b); p
    bool clamp = false;                                            // clamp the output at 0
    double p = 0, b = 0;
    double apply(double x) const {
        const double o = kind == Constant ? p : (kind == Scale ? x + p * (x + b) : x + p);
        return clamp ? (o > 0 ? o : 0.0) : o;
    }
};
MeanCorrection solve_mean_correction(ValueTransform t, double scale, const double* linear, int64_t frames,
                                     double target_mean, bool non_negative);

}  // namespace statfilter
