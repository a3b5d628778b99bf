// The per-frame pieces of motion-compensated averaging (statfilter/motion_compensation.hpp), for a
// caller that holds only a window of frames: how one frame's samples, guide and flow image are made,
// the shot-wide scale of the flow images, and the average of one frame t from its neighbours
// t - h .. t + h. aligned_average runs them over a shot in memory; the hybrid's streamed stage over
// a sliding window of frames. Both give the same numbers.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "statfilter/motion_compensation.hpp"
#include "statfilter/sequence.hpp"

namespace statfilter {

// Frame f's samples in the averaging domain: input / gain, then options.transform.
void aligned_values(const float* input, int64_t count, double gain, ValueTransform transform, float* out);
// Frame f's guide: log(1 + max(0, estimate / gain / mean)), which makes the weights' sigma a relative
// contrast at any exposure; mean is the first pass' mean over the shot (estimate_mean).
void aligned_guide(const float* estimate, int64_t count, double gain, double mean, float* out);
// The sum and count of a frame's positive finite samples (estimate_mean = sum of sums / count of all
// samples of the shot, 1 when nothing is positive).
double positive_sum(const float* frame, int64_t count);
double estimate_mean(double positive_sum, int64_t samples);

// The flow's 8-bit image of a frame (width x height bytes): the mix of each group of three channels,
// averaged over the groups, times scale, clamped to [0, 1] and quantised.
void flow_image(const float* frame, int64_t width, int64_t height, int64_t channels, double scale, uint8_t* out);

// The flow images' scale when they come from the guide: 1 / the 99.5th percentile of every 7th guide
// sample of the shot in storage order (frame-major), non-finite ones counted as 0. Exact, in two
// passes over the frames (a histogram of the samples' bits, then the bin holding the percentile), so
// a stream never holds the shot.
class GuideScale {
public:
    explicit GuideScale(int64_t frame_samples);
    // Pass 1, then pass 2: every frame's guide in order 0 .. F-1 each time.
    void count(int64_t f, const float* guide);
    void finish_counting();
    void collect(int64_t f, const float* guide);
    double scale();
    bool needs_second_pass() const { return counting_done_; }

private:
    template <class Visit>
    void each_sample(int64_t f, const float* guide, Visit&& visit) const;
    int64_t frame_samples_;
    std::vector<uint64_t> bins_;
    uint64_t total_ = 0, rank_ = 0, before_ = 0;
    uint32_t bin_ = 0;
    bool counting_done_ = false;
    std::vector<float> in_bin_;
};

// DIS's finest scale for a frame: the preset's, made finer while the field it computes there would
// have a short side under 48 pixels (six of DIS's 8-pixel patches), down to the frame itself. On small
// renders the presets' 1/4-frame field is a few patches across and blurs motion boundaries
// (docs/methods.md, "The flow's resolution on small frames"); at 1080p the preset's scale stands.
int flow_finest_scale(int preset_scale, int64_t width, int64_t height);

// One frame's data for the average, contiguous (row, pixel, channel).
struct AlignedWindow {
    std::function<const float*(int64_t)> values;   // aligned_values
    std::function<const float*(int64_t)> guide;    // aligned_guide
    std::function<const uint8_t*(int64_t)> image;  // flow_image
    // The renderer's vectors of a frame (Cycles' Vector pass: X, Y, Z, W a pixel, pixel-major), or
    // empty when there are none. Frame t's say which pixels follow them; a step from f to f +/- 1
    // reads both frames' (the forward-backward check).
    std::function<const float*(int64_t)> vectors;
};

// What one thread's averages work in, kept from frame to frame by a caller that averages many (at
// 1080p each average's buffers are 0.1 GB, which the system would otherwise map and zero afresh):
// the sums and weights, where each pixel is and how it is followed, the guide's half-pixel range and
// the flow field. Every buffer is written before it is read. (Not DIS: a reused instance starts from
// the state its last frames left, and its flows differ.)
struct AlignedScratch {
    AlignedScratch();
    ~AlignedScratch();
    AlignedScratch(AlignedScratch&&) noexcept;
    AlignedScratch& operator=(AlignedScratch&&) noexcept;
    std::vector<double> sum, weight;
    std::vector<uint8_t> tracked, by_vector;
    std::vector<float> range;
    struct Flow;  // where each pixel is and the flow field (OpenCV's types: aligned_frame.cpp)
    std::unique_ptr<Flow> flow;
};

class AlignedAverager {
public:
    // pixels: the pixels averaged (row-major indices); options as aligned_average's (its checks done;
    // its vectors come through the window, a frame at a time).
    AlignedAverager(const Shape& shape, std::vector<int64_t> pixels, const AlignedAverageOptions& options);
    const std::vector<int64_t>& pixels() const { return pixels_; }
    // The bytes average() holds for `pixels` averaged pixels of a frame of shape's size: each pixel's
    // sums and weight, where it is and whether it is followed; the flow field at full resolution and
    // DIS's own images (pyramid, gradients, the variational refinement's fields at its finest scale).
    static double working_bytes(const Shape& shape, int64_t pixels);
    // Frame t's average from the window's frames t - h .. t + h (inside the shot), written to out
    // (a frame, contiguous) at the averaged pixels times frame t's gain; a pixel with nothing finite to
    // average is not written. Returns the summed weights. Safe from several threads for different t.
    double average(int64_t t, const AlignedWindow& window, float* out) const;
    double average(int64_t t, const AlignedWindow& window, float* out, AlignedScratch& scratch) const;

private:
    Shape shape_;
    std::vector<int64_t> pixels_;
    AlignedAverageOptions options_;
};

}  // namespace statfilter
