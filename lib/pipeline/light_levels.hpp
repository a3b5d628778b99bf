// The shot's light level frame by frame, and a source that hands the stages frames at one level.
// A light that brightens or dims over the shot changes every pixel together; left in, a temporal
// basis must spend a component on it, with a coefficient per pixel, and on a short or noisy shot the
// automatic rank drops it (8 frames of cornell_light at 4 spp: rank 0, the light's swing averaged
// away). Divided out, it is one number a frame, and multiplied back after the stage.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/frame_source.hpp"

namespace statfilter {

// Frames the level's smoothing fits a quadratic over on each side when deciding whether the light
// changes at all: the light of a shot changes smoothly; what changes a frame's level from one frame
// to the next (noise, an object's motion) does not, and multiplied back it would flicker on the still
// pixels.
constexpr int kLightLevelHalfWidth = 8;
// The half-widths a changing light's levels may be smoothed over (chosen by leave-one-out).
constexpr int kLightLevelHalfWidths[] = {2, 3, 4, 6, 8, 12, 16};

// The smallest swing of the smoothed level (max |level - 1|) worth modelling. Below it the light is
// taken as still and nothing is divided: a level off by 1% costs about 1e-4 of relMSE, less than the
// noise of the level itself on a short shot, and the output stays the named method's, bit for bit.
constexpr double kLeastLightSwing = 0.01;

// Fewer frames than this say too little of a light to follow it (and a fit over 2 or 3 frames has
// nothing left to measure its own noise by): the light is taken as still.
constexpr int64_t kLeastLightFrames = 4;

struct LightLevels {
    std::vector<double> levels;  // one a frame, mean 1; all 1 when the light is taken as still
    std::vector<uint8_t> channels;  // 1 where the channel is light (measured, divided); data passes 0
    double swing = 0;            // max |smoothed level - 1| over the frames
    double noise = 0;            // robust spread of a frame's raw level about the smoothed one
    int half_width = 0;          // frames a side the levels used are smoothed over (0: not modelled)
    bool modelled = false;       // levels are not all 1
};

// The frame's level is the median, over 8 x 8 blocks of the frame, of the block's mean over its median
// over the shot's frames (every row of a frame up to 256 rows high; above, a strip of 16 rows centred in
// each row of blocks). A median of blocks, not the frame's mean: a firefly or a moving object changes
// a few blocks, a light every one. Only the light channels count (is_light_channel: not alpha, not a
// data pass; every channel when none is light or they have no names). The light changes when the
// raw levels smoothed by a local quadratic over kLightLevelHalfWidth frames a side swing by more
// than kLeastLightSwing and three times the raw levels' spread about that fit (each left out of its
// own); then the levels used are the raw ones smoothed over the half-width of kLightLevelHalfWidths
// that predicts each frame's raw level best from the others (leave-one-out). Blocks that are black
// or hold a non-finite mean are left out; with none left, or fewer than kLeastLightFrames frames,
// the light is still.
LightLevels measure_light_levels(const FrameSource& source, int threads);

// The local quadratic fit of raw levels, frame by frame, and the half-width of kLightLevelHalfWidths
// with the least leave-one-out error (exposed for the tests).
std::vector<double> smooth_light_levels(const std::vector<double>& raw, int half_width);
int choose_light_half_width(const std::vector<double>& raw);

// Which channels are light, by their names (is_light_channel; all when none is, or unnamed).
std::vector<uint8_t> light_channels(const std::vector<std::string>& names, int64_t channels);

// The light channels of `inner`'s frames divided by their level (read_rows); `restore` multiplies a
// finished frame back.
class LevelledSource final : public FrameSource {
public:
    LevelledSource(const FrameSource& inner, const LightLevels& light)
        : inner_(inner), levels_(light.levels), light_(light.channels) {}
    const Shape& shape() const override { return inner_.shape(); }
    const Sequence& attributes() const override { return inner_.attributes(); }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override;
    void restore(int64_t f, float* pixels) const;

private:
    const FrameSource& inner_;
    std::vector<double> levels_;
    std::vector<uint8_t> light_;
};

}  // namespace statfilter
