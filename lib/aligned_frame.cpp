#include "statfilter/aligned_frame.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include "statfilter/error.hpp"
#include "statfilter/fast_log_exp.hpp"

namespace statfilter {
namespace {

// DIS (Kroeger et al. 2016) needs a few of its 8-pixel patches across the frame; below this the flow
// is taken as zero (a frame that small has nothing to align).
constexpr int64_t kMinFlowSide = 16;

// A luminance-like mix of a pixel's first three channels (a shorter one repeats its last).
inline double mix3(const float* px, int64_t channels) {
    const auto c = [&](int64_t i) { return static_cast<double>(px[std::min(i, channels - 1)]); };
    return 0.3 * c(0) + 0.5 * c(1) + 0.2 * c(2);
}

int dis_preset(FlowPreset preset) {
    switch (preset) {
        case FlowPreset::UltraFast: return cv::DISOpticalFlow::PRESET_ULTRAFAST;
        case FlowPreset::Fast: return cv::DISOpticalFlow::PRESET_FAST;
        case FlowPreset::Medium: break;
    }
    return cv::DISOpticalFlow::PRESET_MEDIUM;
}

// Bilinear sample of channel c of an interleaved (row, pixel, channel) frame; (fx, fy) inside the frame.
inline float bilinear(const float* frame, int64_t width, int64_t height, int64_t channels, float fx, float fy, int64_t c) {
    const int64_t x0 = static_cast<int64_t>(fx), y0 = static_cast<int64_t>(fy);
    const int64_t x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const float ax = fx - static_cast<float>(x0), ay = fy - static_cast<float>(y0);
    const auto v = [&](int64_t x, int64_t y) { return frame[(y * width + x) * channels + c]; };
    return (1 - ay) * ((1 - ax) * v(x0, y0) + ax * v(x1, y0)) + ay * ((1 - ax) * v(x0, y1) + ax * v(x1, y1));
}

// Cycles' Vector pass, X, Y, Z, W per pixel in pixels with Y pointing up: the surface point seen at
// (x, y) (rows counted downward) is at (x + X, y - Y) in the previous frame and at (x - Z, y + W) in
// the next (measured on the renders, docs/methods.md). The step from `frame` one frame in direction
// `dir` (-1 previous, +1 next), read bilinearly at (fx, fy) inside the frame; v: that frame's vectors.
inline cv::Vec2f vector_step(const float* v, int64_t width, int64_t height, int dir, float fx, float fy) {
    if (dir < 0) return {bilinear(v, width, height, 4, fx, fy, 0), -bilinear(v, width, height, 4, fx, fy, 1)};
    return {-bilinear(v, width, height, 4, fx, fy, 2), bilinear(v, width, height, 4, fx, fy, 3)};
}

inline bool inside(int64_t width, int64_t height, const cv::Vec2f& q) {
    return q[0] >= 0 && q[1] >= 0 && q[0] <= static_cast<float>(width - 1) && q[1] <= static_cast<float>(height - 1);
}

// Moves `where` (a surface point in `frame`) one frame in direction `dir` along the vectors; false when
// it leaves the frame or the step fails the forward-backward check: the vector back from where it lands
// must return it (|d + b|^2 <= 0.01 (|d|^2 + |b|^2) + 0.5, Sundaram et al. 2010). Where a surface is
// occluded in the next frame, or uncovered in this one, the two vectors belong to different surfaces.
// from: the vectors of the frame it is in; to: those of the frame it moves to.
inline bool follow_vectors(const float* from, const float* to, int64_t width, int64_t height, int dir, cv::Vec2f& where) {
    const cv::Vec2f d = vector_step(from, width, height, dir, where[0], where[1]);
    const cv::Vec2f q = where + d;
    if (!(std::isfinite(q[0]) && std::isfinite(q[1])) || !inside(width, height, q)) return false;
    const cv::Vec2f b = vector_step(to, width, height, -dir, q[0], q[1]);
    const cv::Vec2f e = d + b;
    if (!(e.dot(e) <= 0.01f * (d.dot(d) + b.dot(b)) + 0.5f)) return false;
    where = q;
    return true;
}

// Frame t's guide within half a pixel of each averaged pixel, per channel: the lowest and highest of
// the pixel's value and its midpoints with its 8 neighbours (lo, hi interleaved, pixel-major). A flow
// is right to a fraction of a pixel at best, so a warped sample that lands inside this range is
// consistent with frame t even on an edge or a texture; only the part beyond it counts as mismatch.
// Without it an antialiased edge mismatches by its whole contrast and loses its samples, which a
// slow pan pays for everywhere (camera_pan needed a lenient sigma that let a fast ball's wrong
// samples in).
void half_pixel_range(const float* guide, int64_t width, int64_t height, int64_t channels,
                      const std::vector<int64_t>& pixels, std::vector<float>& range) {
    range.resize(pixels.size() * static_cast<size_t>(channels) * 2);
    float* r = range.data();
    for (const int64_t p : pixels) {
        const int64_t x = p % width, y = p / width;
        for (int64_t c = 0; c < channels; ++c, r += 2) {
            const float g = guide[p * channels + c];
            float lo = g, hi = g;
            for (int64_t yy = std::max<int64_t>(0, y - 1); yy <= std::min(height - 1, y + 1); ++yy)
                for (int64_t xx = std::max<int64_t>(0, x - 1); xx <= std::min(width - 1, x + 1); ++xx) {
                    const float m = 0.5f * (g + guide[(yy * width + xx) * channels + c]);
                    if (std::isfinite(m)) lo = std::min(lo, m), hi = std::max(hi, m);
                }
            r[0] = lo;
            r[1] = hi;
        }
    }
}

// How far v lies outside [lo, hi] (NaN stays NaN: no weight).
inline double outside(double v, const float* lo_hi) {
    if (v > lo_hi[1]) return v - lo_hi[1];
    if (v < lo_hi[0]) return lo_hi[0] - v;
    return v == v ? 0.0 : v;
}

// The percentile the flow images are scaled by.
constexpr double kGuideQuantile = 0.995;
constexpr int64_t kGuideStride = 7;  // every 7th sample: plenty for a percentile, and cheap

inline uint32_t bits_of(float v) {
    uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

}  // namespace

void aligned_values(const float* input, int64_t count, double gain, ValueTransform transform, float* out) {
    std::vector<double> row(static_cast<size_t>(count));
    for (int64_t i = 0; i < count; ++i) row[static_cast<size_t>(i)] = input[i] / gain;
    forward_transform(transform, row.data(), row.size());
    for (int64_t i = 0; i < count; ++i) out[i] = static_cast<float>(row[static_cast<size_t>(i)]);
}

void aligned_guide(const float* estimate, int64_t count, double gain, double mean, float* out) {
    // In blocks through fast_math's vectorised log1p (NaN becomes 0: std::max keeps its first argument).
    constexpr int64_t block = 1024;
    double v[block];
    for (int64_t i0 = 0; i0 < count; i0 += block) {
        const int64_t m = std::min(block, count - i0);
        for (int64_t i = 0; i < m; ++i) v[i] = std::max(0.0, estimate[i0 + i] / gain / mean);
        fast_math::signed_log1p(v, static_cast<size_t>(m), 1.0);
        for (int64_t i = 0; i < m; ++i) out[i0 + i] = static_cast<float>(v[i]);
    }
}

double positive_sum(const float* frame, int64_t count) {
    double sum = 0;
    for (int64_t i = 0; i < count; ++i)
        if (frame[i] > 0 && std::isfinite(frame[i])) sum += frame[i];
    return sum;
}

double estimate_mean(double sum, int64_t samples) { return sum > 0 ? sum / static_cast<double>(samples) : 1.0; }

void flow_image(const float* frame, int64_t width, int64_t height, int64_t channels, double scale, uint8_t* out) {
    const int64_t groups = std::max<int64_t>(1, channels / 3);
    for (int64_t p = 0; p < width * height; ++p) {
        double v = 0;
        for (int64_t k = 0; k < groups; ++k) v += mix3(frame + p * channels + 3 * k, std::min<int64_t>(3, channels - 3 * k));
        v = std::isfinite(v) ? scale * v / static_cast<double>(groups) : 0.0;
        out[p] = static_cast<uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
    }
}

GuideScale::GuideScale(int64_t frame_samples) : frame_samples_(frame_samples), bins_(size_t{1} << 16, 0) {}

template <class Visit>
void GuideScale::each_sample(int64_t f, const float* guide, Visit&& visit) const {
    const int64_t first = f * frame_samples_;
    for (int64_t j = (kGuideStride - first % kGuideStride) % kGuideStride; j < frame_samples_; j += kGuideStride)
        visit(std::isfinite(guide[j]) ? guide[j] : 0.0f);
}

void GuideScale::count(int64_t f, const float* guide) {
    each_sample(f, guide, [&](float v) {
        ++bins_[bits_of(v) >> 16];
        ++total_;
    });
}

void GuideScale::finish_counting() {
    counting_done_ = true;
    if (total_ == 0) return;
    rank_ = static_cast<uint64_t>(kGuideQuantile * static_cast<double>(total_ - 1));
    uint64_t seen = 0;
    for (uint32_t b = 0; b < bins_.size(); ++b) {
        if (seen + bins_[b] > rank_) {
            bin_ = b;
            before_ = seen;
            break;
        }
        seen += bins_[b];
    }
    bins_.clear();
}

void GuideScale::collect(int64_t f, const float* guide) {
    each_sample(f, guide, [&](float v) {
        if ((bits_of(v) >> 16) == bin_) in_bin_.push_back(v);
    });
}

double GuideScale::scale() {
    if (total_ == 0 || in_bin_.empty()) return 1.0;
    const auto q = in_bin_.begin() + static_cast<std::ptrdiff_t>(rank_ - before_);
    std::nth_element(in_bin_.begin(), q, in_bin_.end());
    return *q > 0 ? 1.0 / *q : 1.0;
}

AlignedAverager::AlignedAverager(const Shape& shape, std::vector<int64_t> pixels, const AlignedAverageOptions& options)
    : shape_(shape), pixels_(std::move(pixels)), options_(options) {}

int flow_finest_scale(int preset_scale, int64_t width, int64_t height) {
    constexpr int64_t kMinFieldSide = 48;
    int scale = std::max(0, preset_scale);
    while (scale > 0 && (std::min(width, height) >> scale) < kMinFieldSide) --scale;
    return scale;
}

double AlignedAverager::working_bytes(const Shape& s, int64_t pixels) {
    const double n = static_cast<double>(pixels), P = static_cast<double>(s.pixels());
    // sum (C doubles), weight, where (2 floats), tracked, by_vector, the guide's half-pixel range
    // (2 C floats); the flow (2 floats a pixel),
    // DIS's upsampled fields (2 floats) and ~16 bytes a pixel of its pyramid and refinement.
    return n * (static_cast<double>(s.channels) * (sizeof(double) + 2 * sizeof(float)) + sizeof(double) + 2 * sizeof(float) + 2) +
           P * (2 * sizeof(float) + 2 * sizeof(float) + 16);
}

struct AlignedScratch::Flow {
    std::vector<cv::Vec2f> where;
    cv::Mat field;
};
AlignedScratch::AlignedScratch() = default;
AlignedScratch::~AlignedScratch() = default;
AlignedScratch::AlignedScratch(AlignedScratch&&) noexcept = default;
AlignedScratch& AlignedScratch::operator=(AlignedScratch&&) noexcept = default;

double AlignedAverager::average(int64_t t, const AlignedWindow& window, float* out) const {
    AlignedScratch scratch;
    return average(t, window, out, scratch);
}

double AlignedAverager::average(int64_t t, const AlignedWindow& window, float* out, AlignedScratch& scratch) const {
    const Shape& s = shape_;
    const int64_t F = s.frames, C = s.channels;
    const size_t n = pixels_.size();
    const bool estimate_flow = s.width >= kMinFlowSide && s.height >= kMinFlowSide;
    const double inv_two_sigma2 = 1.0 / (2.0 * options_.sigma * options_.sigma);
    const double gain_t = options_.frame_gain.empty() ? 1.0 : options_.frame_gain[static_cast<size_t>(t)];
    const bool has_vectors = static_cast<bool>(window.vectors);
    const auto image = [&](int64_t f) {
        return cv::Mat(static_cast<int>(s.height), static_cast<int>(s.width), CV_8UC1, const_cast<uint8_t*>(window.image(f)));
    };
    // The buffers from the caller's scratch (kept from frame to frame). DIS is made afresh: an instance
    // used before starts from state its last frames left (measured: other flows, other outputs).
    if (!scratch.flow) scratch.flow = std::make_unique<AlignedScratch::Flow>();
    const cv::Ptr<cv::DISOpticalFlow> dis_made = cv::DISOpticalFlow::create(dis_preset(options_.flow));
    cv::DISOpticalFlow& dis = *dis_made;
    dis.setFinestScale(flow_finest_scale(dis.getFinestScale(), s.width, s.height));
    cv::Mat& flow = scratch.flow->field;
    std::vector<double>& sum = scratch.sum;
    std::vector<double>& weight = scratch.weight;
    sum.assign(n * static_cast<size_t>(C), 0.0);
    weight.assign(n, 0.0);
    std::vector<double> sample(static_cast<size_t>(C));
    std::vector<cv::Vec2f>& where = scratch.flow->where;  // each pixel's surface point in frame f
    std::vector<uint8_t>& tracked = scratch.tracked;  // still followed (vectors consistent so far)
    std::vector<uint8_t>& by_vector = scratch.by_vector;  // followed along the vectors, else the flow
    where.resize(n);
    tracked.resize(n);
    by_vector.resize(n);
    const float* gt = window.guide(t);
    std::vector<float>& range = scratch.range;
    half_pixel_range(gt, s.width, s.height, C, pixels_, range);
    const auto accumulate = [&](int64_t f) {
        const float* vf = window.values(f);
        const float* gf = window.guide(f);
        for (size_t i = 0; i < n; ++i) {
            if (!tracked[i]) continue;  // occluded or uncovered on the way: not the same surface
            const float fx = where[i][0], fy = where[i][1];
            if (!inside(s.width, s.height, where[i])) continue;  // outside frame f (NaN flow lands here too)
            double mismatch = 0;
            bool finite = true;
            for (int64_t c = 0; c < C; ++c) {
                const double e = outside(bilinear(gf, s.width, s.height, C, fx, fy, c), &range[(i * static_cast<size_t>(C) + static_cast<size_t>(c)) * 2]);
                mismatch += e * e;
                sample[static_cast<size_t>(c)] = bilinear(vf, s.width, s.height, C, fx, fy, c);
                finite = finite && std::isfinite(sample[static_cast<size_t>(c)]);
            }
            const double w = std::exp(-mismatch * inv_two_sigma2);
            if (!(w > 1e-4) || !finite) continue;  // another surface or light, or a non-finite sample
            for (int64_t c = 0; c < C; ++c) sum[i * static_cast<size_t>(C) + static_cast<size_t>(c)] += w * sample[static_cast<size_t>(c)];
            weight[i] += w;
        }
    };
    const auto start_at_t = [&] {
        for (size_t i = 0; i < n; ++i)
            where[i] = cv::Vec2f(static_cast<float>(pixels_[i] % s.width), static_cast<float>(pixels_[i] / s.width));
        std::fill(tracked.begin(), tracked.end(), uint8_t{1});
    };
    // Which pixels follow the vectors: those with a vector at t (Cycles writes exact zeros where no
    // geometry is hit, and a static surface has them too); the others follow the flow.
    int64_t by_flow = 0;
    const float* vectors_t = has_vectors ? window.vectors(t) : nullptr;
    for (size_t i = 0; i < n; ++i) {
        const float* v = vectors_t ? vectors_t + pixels_[i] * 4 : nullptr;
        by_vector[i] = v && (v[0] != 0 || v[1] != 0 || v[2] != 0 || v[3] != 0);
        by_flow += !by_vector[i];
    }
    // Frame t itself, then its neighbours outward, one side after the other: each step starts from the
    // previous one (chained vectors; the flow warm-started from the last one of this side, never from
    // another frame's), so the result does not depend on how frames are shared out between threads.
    start_at_t();
    accumulate(t);
    for (const int dir : {-1, 1}) {
        start_at_t();
        flow.release();  // DIS starts from the flow it is handed: from zero on each side
        const int64_t last = dir < 0 ? std::max<int64_t>(0, t - options_.half_width) : std::min<int64_t>(F - 1, t + options_.half_width);
        for (int64_t f = t + dir; dir < 0 ? f >= last : f <= last; f += dir) {
            if (vectors_t) {
                const float* from = window.vectors(f - dir);
                const float* to = window.vectors(f);
                for (size_t i = 0; i < n; ++i)
                    if (by_vector[i] && tracked[i]) tracked[i] = follow_vectors(from, to, s.width, s.height, dir, where[i]);
            }
            if (by_flow > 0 && estimate_flow) {
                try {
                    dis.calc(image(t), image(f), flow);
                } catch (const cv::Exception& e) {
                    throw Error(Status::Internal, std::string("optical flow failed: ") + e.what());
                }
                for (size_t i = 0; i < n; ++i) {
                    if (by_vector[i]) continue;
                    const int64_t p = pixels_[i];
                    const cv::Vec2f d = flow.at<cv::Vec2f>(static_cast<int>(p / s.width), static_cast<int>(p % s.width));
                    where[i] = cv::Vec2f(static_cast<float>(p % s.width) + d[0], static_cast<float>(p / s.width) + d[1]);
                }
            }
            accumulate(f);
        }
    }
    // A pixel the other frames barely reached (its own sample's weight 1 and less than half of one
    // neighbour's beside it) keeps its value, the caller's first pass, as one with nothing to average
    // does: an "average" of one noisy sample is that sample, noisier than the first pass (balanced on
    // the shared scenes: relMSE up to 11% lower, none higher by more than 0.1%; docs/methods.md).
    constexpr double kLeastWeight = 1.5;
    double total = 0;
    for (size_t i = 0; i < n; ++i) {
        if (weight[i] > 0) total += weight[i];  // the result aligned_frames: the weight the frames had
        if (!(weight[i] >= kLeastWeight)) continue;  // nothing (or next to nothing) to average
        for (int64_t c = 0; c < C; ++c) sample[static_cast<size_t>(c)] = sum[i * static_cast<size_t>(C) + static_cast<size_t>(c)] / weight[i];
        inverse_transform(options_.transform, sample.data(), sample.size());
        for (int64_t c = 0; c < C; ++c) out[pixels_[i] * C + c] = static_cast<float>(sample[static_cast<size_t>(c)] * gain_t);
    }
    return total;
}

}  // namespace statfilter
