// Where the hybrid's first pass (the flow's guide, the aligned average's reference, and what a pixel
// with nothing to average keeps) is the frame's own diffusion instead of I_T, frame by frame:
//   - the crossings (crossing_weight: the change test saw motion alpha did not), in every frame;
//   - in the moving region, a pixel whose departures from its temporal median are brief (the change
//     test fires in at most half_width frames of the shot) in the frames of its event that I_T misses
//     (TemporalChange::model_misses). alpha may see such an event (an object resting at a
//     pixel in the first frame only), and then I_T holds its ghost; an average along the flow over
//     2 x half_width + 1 frames referred to that ghost is outvoted by the frames without the event.
//     Sustained misses (a camera pan's edges) keep I_T: there the window's frames agree after the
//     alignment, and the frame's own diffusion would be the noisier reference.
#pragma once
#include <cstdint>
#include <vector>

#include "statfilter/anisotropic_diffusion.hpp"
#include "statfilter/motion.hpp"

namespace statfilter {

class OwnFirstPass {
public:
    // crossings: per pixel (may be empty); change: the test with its noise in (nullptr: no brief
    // pixels); moving: the moving region, per pixel.
    OwnFirstPass(const Shape& shape, std::vector<float> crossings, const TemporalChange* change,
                 const std::vector<uint8_t>& moving, int64_t half_width, DiffusionOptions diffusion);
    // Frame f: `frame` is the noisy frame (fireflies replaced; diffused here where needed, not written),
    // `model` I_T, `first_pass` blended; `workspace` the diffusion's buffers (a caller that does frame
    // after frame keeps them). Returns the number of pixels given their own diffusion.
    int64_t apply(int64_t f, float* frame, const float* model, float* first_pass, DiffusionWorkspace& workspace) const;
    // No pixel in any frame.
    bool never() const { return crossing_pixels_.empty() && brief_pixels_ == 0; }
    // Bytes per thread while apply runs, beyond the two frames it is handed.
    static double working_bytes(const Shape& shape);
    // Bytes held per pixel for the whole rebuild (the weights and masks).
    static double held_bytes_per_pixel() { return sizeof(float) + 2 + sizeof(int64_t); }
    // The boxes apply diffuses: bands of kBox rows, in each the runs of kBox-wide columns holding one
    // of the pixels (sorted indices of a width x height frame).
    static constexpr int64_t kBox = 32;
    static std::vector<PixelBox> boxes_around(const std::vector<int64_t>& pixels, int64_t width, int64_t height);

private:
    Shape shape_;
    std::vector<float> crossings_;
    std::vector<int64_t> crossing_pixels_;
    const TemporalChange* change_;
    std::vector<uint8_t> brief_;  // 1: in the moving region, departures brief
    int64_t brief_pixels_ = 0;
    DiffusionOptions diffusion_;
};

}  // namespace statfilter
