// The shot's light level frame by frame, and a source that hands the stages frames at one level.
// A light that brightens or dims over the shot changes every pixel together; left in, a temporal
// basis must spend a component on it, with a coefficient per pixel, and on a short or noisy shot the
// automatic rank drops it (8 frames of cornell_light at 4 spp: rank 0, the light's swing averaged
// away). Divided out, it is one number a frame, and multiplied back after the stage.
#pragma once
#include <vector>

#include "pipeline/frame_source.hpp"

namespace statfilter {

// Frames the level's smoothing fits a quadratic over on each side: the light of a shot changes
// smoothly; what changes a frame's mean from one frame to the next (noise, an object's motion) does
// not, and multiplied back it would flicker on the still pixels.
constexpr int kLightLevelHalfWidth = 8;

// Each frame's mean over strips of 16 rows every 128 (every row of a frame up to 256 rows high), over
// the shot's mean, smoothed by a local quadratic in time over kLightLevelHalfWidth frames a side.
// All 1 when a frame has no positive mean or a smoothed level is not positive (nothing is divided).
std::vector<double> measure_light_levels(const FrameSource& source, int threads);

// The local quadratic fit of raw levels, frame by frame (exposed for the tests).
std::vector<double> smooth_light_levels(const std::vector<double>& raw, int half_width);

// The frames of `inner` divided by their level (read_rows); `restore` multiplies a finished frame back.
class LevelledSource final : public FrameSource {
public:
    LevelledSource(const FrameSource& inner, std::vector<double> levels) : inner_(inner), levels_(std::move(levels)) {}
    const Shape& shape() const override { return inner_.shape(); }
    const Sequence& attributes() const override { return inner_.attributes(); }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override;
    void restore(int64_t f, float* pixels) const;

private:
    const FrameSource& inner_;
    std::vector<double> levels_;
};

}  // namespace statfilter
