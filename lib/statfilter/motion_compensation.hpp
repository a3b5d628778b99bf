// Motion-compensated temporal averaging. When the camera or objects move, a pixel's time series
// mixes different surface points and a temporal basis has nothing coherent to keep. Dense optical
// flow (OpenCV's DIS) finds where each surface point of frame t sits in frame s: on the renderer's
// albedo and normal passes when given (nearly noise-free at any sample count), else on a denoised
// first pass. Each frame's neighbours within a window are warped onto it along that flow and
// averaged, each sample weighted by how well the warped first pass matches frame t's (occlusions,
// flow errors and moving shadows drop out) and zero when it falls outside the frame. Diffuse indirect
// light does not depend on the view, so along a surface point's track it changes only with the
// lighting: the average is the model that scene requires.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"
#include "statfilter/value_transform.hpp"

namespace statfilter {

// The renderer's passes as one guide for the flow: the first three channels of each pass given
// (normals mapped from [-1, 1] to [0, 1]), F x H x W x (3 per pass). Either pass may be null.
std::unique_ptr<Sequence> make_pass_guide(const Sequence* albedo, const Sequence* normal);
// One frame of one pass into such a guide: `pixels` pixels of `channels` floats in, written `stride`
// floats apart at out (the pass' group of three); normal: mapped from [-1, 1] to [0, 1].
void pass_guide_pixels(const float* pass, int64_t channels, bool normal, int64_t pixels, float* out, int64_t stride);

enum class FlowPreset { UltraFast, Fast, Medium };  // OpenCV's DIS presets: speed against accuracy
FlowPreset parse_flow_preset(const std::string& name);

struct AlignedAverageOptions {
    int half_width = 8;       // frames on each side of t
    // Mismatch of a warped sample's estimate with frame t's at which its weight is exp(-1/2): the root of
    // the summed squared channel distances, in log(1 + x / mean) units, of the warped value from the
    // range frame t's estimate takes within half a pixel (a flow off by a fraction of a pixel on an
    // edge is no mismatch).
    double sigma = 0.1;
    ValueTransform transform = ValueTransform::Log;  // the domain the samples are averaged in
    FlowPreset flow = FlowPreset::Medium;
    // Optional global light level of each frame (empty = constant): samples are divided by their
    // frame's level before averaging and the average multiplied by frame t's, so a light that
    // brightens or dims over the window is followed, not averaged away.
    std::vector<double> frame_gain;
    // Optional: the renderer's motion vectors (Cycles' Vector pass, F x H x W x 4: X, Y, Z, W in pixels,
    // docs/methods.md), used instead of optical flow. They are chained for frames further apart, and a
    // sample is dropped once a step fails the forward-backward check (occlusion, disocclusion). A pixel
    // whose vector at t is exactly zero (no geometry, or a static surface) follows the flow instead.
    const Sequence* vectors = nullptr;
};

struct AlignedAverageStats {
    double mean_frames = 0;     // mean summed weight per averaged pixel-frame (1 = the frame alone)
    double pixel_fraction = 0;  // share of pixels averaged (the others are left as they were)
};

// Writes into `output` the motion-compensated average of `input` at every pixel where `pixel_mask`
// (H x W, may be empty = all) is non-zero; other pixels of `output` are not touched. `estimate` is a
// denoised first pass of the input (same shape): warped samples are weighted by how well its warped
// value matches its value at t, which drops occlusions, flow errors and real changes of the light
// (a moving shadow) from the average. The flow is computed on `passes` (make_pass_guide) when given,
// else on the estimate itself. Frames, height and width must match the input's. `output` may be the
// estimate itself: the estimate is read in full before anything is written. A pixel that the other
// frames do not reach (their summed weight under half of one frame's) is left as `output` has it: a
// caller fills output with the first pass, which a lone noisy sample is no improvement on.
AlignedAverageStats aligned_average(const Sequence& input, const Sequence& estimate, const Sequence* passes,
                                    const std::vector<uint8_t>& pixel_mask, const AlignedAverageOptions& options,
                                    Sequence& output, const ProgressSpan& progress);

}  // namespace statfilter
