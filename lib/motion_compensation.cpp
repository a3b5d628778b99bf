#include "statfilter/motion_compensation.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include "statfilter/error.hpp"

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

// One 8-bit image per frame for the flow: the mix of each group of three channels, averaged over the
// groups, times `scale`. The guide is (nearly) noise-free, so 8 bits lose nothing the flow could use.
cv::Mat flow_image(const float* frame, int64_t width, int64_t height, int64_t channels, double scale) {
    const int64_t groups = std::max<int64_t>(1, channels / 3);
    cv::Mat image(static_cast<int>(height), static_cast<int>(width), CV_8UC1);
    for (int64_t p = 0; p < width * height; ++p) {
        double v = 0;
        for (int64_t k = 0; k < groups; ++k) v += mix3(frame + p * channels + 3 * k, std::min<int64_t>(3, channels - 3 * k));
        v = std::isfinite(v) ? scale * v / static_cast<double>(groups) : 0.0;
        image.at<uint8_t>(static_cast<int>(p / width), static_cast<int>(p % width)) =
            static_cast<uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
    }
    return image;
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
// `dir` (-1 previous, +1 next), read bilinearly at (fx, fy) inside the frame.
inline cv::Vec2f vector_step(const float* vectors, int64_t width, int64_t height, int64_t frame, int dir, float fx, float fy) {
    const float* v = vectors + frame * width * height * 4;
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
inline bool follow_vectors(const float* vectors, int64_t width, int64_t height, int64_t frame, int dir, cv::Vec2f& where) {
    const cv::Vec2f d = vector_step(vectors, width, height, frame, dir, where[0], where[1]);
    const cv::Vec2f q = where + d;
    if (!(std::isfinite(q[0]) && std::isfinite(q[1])) || !inside(width, height, q)) return false;
    const cv::Vec2f b = vector_step(vectors, width, height, frame + dir, -dir, q[0], q[1]);
    const cv::Vec2f e = d + b;
    if (!(e.dot(e) <= 0.01f * (d.dot(d) + b.dot(b)) + 0.5f)) return false;
    where = q;
    return true;
}

}  // namespace

FlowPreset parse_flow_preset(const std::string& name) {
    if (name == "ultrafast") return FlowPreset::UltraFast;
    if (name == "fast") return FlowPreset::Fast;
    if (name == "medium") return FlowPreset::Medium;
    throw Error(Status::InvalidArgument, "flow preset '" + name + "': expected ultrafast, fast or medium");
}

std::unique_ptr<Sequence> make_pass_guide(const Sequence* albedo, const Sequence* normal) {
    const Sequence* first = albedo ? albedo : normal;
    if (!first) throw Error(Status::InvalidArgument, "motion compensation needs an albedo or a normal pass");
    const Shape& a = first->shape();
    if (albedo && normal) {
        const Shape& n = normal->shape();
        if (n.frames != a.frames || n.height != a.height || n.width != a.width)
            throw Error(Status::InvalidArgument, "the albedo pass is " + to_string(a) + ", the normal pass " + to_string(n));
    }
    const int64_t passes = (albedo ? 1 : 0) + (normal ? 1 : 0);
    auto guide = std::make_unique<Sequence>(Shape{a.frames, a.height, a.width, 3 * passes});
    int64_t group = 0;
    for (const Sequence* pass : {albedo, normal}) {
        if (!pass) continue;
        const bool is_normal = pass == normal;
        for (int64_t f = 0; f < a.frames; ++f)
            for (int64_t y = 0; y < a.height; ++y)
                for (int64_t x = 0; x < a.width; ++x)
                    for (int64_t c = 0; c < 3; ++c) {
                        // A pass with fewer than three channels repeats its last one.
                        const float v = pass->at(f, y, x, std::min(c, pass->shape().channels - 1));
                        guide->at(f, y, x, 3 * group + c) = is_normal ? 0.5f * v + 0.5f : v;
                    }
        ++group;
    }
    return guide;
}

AlignedAverageStats aligned_average(const Sequence& input, const Sequence& estimate, const Sequence* passes,
                                    const std::vector<uint8_t>& pixel_mask, const AlignedAverageOptions& options,
                                    Sequence& output, const ProgressSpan& progress) {
    const Shape& s = input.shape();
    if (estimate.shape() != s)
        throw Error(Status::InvalidArgument, "the first pass is " + to_string(estimate.shape()) + ", the input " + to_string(s));
    if (passes) {
        const Shape& g = passes->shape();
        if (g.frames != s.frames || g.height != s.height || g.width != s.width)
            throw Error(Status::InvalidArgument, "the guide passes are " + to_string(g) + ", the input " + to_string(s));
    }
    if (!options.frame_gain.empty() && static_cast<int64_t>(options.frame_gain.size()) != s.frames)
        throw Error(Status::InvalidArgument, "aligned_average: one light level per frame expected");
    for (double g : options.frame_gain)
        if (!(g > 0 && std::isfinite(g))) throw Error(Status::InvalidArgument, "aligned_average: light levels must be positive");
    if (options.vectors) {
        const Shape& v = options.vectors->shape();
        if (v.frames != s.frames || v.height != s.height || v.width != s.width || v.channels < 4)
            throw Error(Status::InvalidArgument, "the motion vectors are " + to_string(v) + ", the input " + to_string(s) +
                                                     ": expected the same frames and size with 4 channels (X, Y, Z, W)");
    }
    if (!pixel_mask.empty() && static_cast<int64_t>(pixel_mask.size()) != s.pixels())
        throw Error(Status::InvalidArgument, "aligned_average: the pixel mask does not match the frame");
    const int64_t F = s.frames, P = s.pixels(), C = s.channels;
    std::vector<int64_t> pixels;
    for (int64_t p = 0; p < P; ++p)
        if (pixel_mask.empty() || pixel_mask[static_cast<size_t>(p)]) pixels.push_back(p);
    AlignedAverageStats stats;
    stats.pixel_fraction = static_cast<double>(pixels.size()) / static_cast<double>(P);
    if (pixels.empty()) return stats;

    // Samples in the averaging domain; the first pass as log(1 + x / m), m its mean, which makes the
    // weights' sigma a relative contrast at any exposure.
    std::vector<float> values(static_cast<size_t>(F * P * C)), guide(values.size());
    double mean = 0;
    for (int64_t f = 0; f < F; ++f)
        for (int64_t p = 0; p < P; ++p)
            for (int64_t c = 0; c < C; ++c) {
                const float v = estimate.at(f, p / s.width, p % s.width, c);
                if (v > 0 && std::isfinite(v)) mean += v;
            }
    mean = mean > 0 ? mean / static_cast<double>(F * P * C) : 1.0;
    cv::parallel_for_(cv::Range(0, static_cast<int>(F)), [&](const cv::Range& frames) {
        std::vector<double> row(static_cast<size_t>(P * C));
        std::vector<float> frame(row.size());
        for (int f = frames.start; f < frames.end; ++f) {
            const double gain = options.frame_gain.empty() ? 1.0 : options.frame_gain[static_cast<size_t>(f)];
            input.get_frame(f, frame.data());
            for (size_t i = 0; i < frame.size(); ++i) row[i] = frame[i] / gain;
            forward_transform(options.transform, row.data(), row.size());
            std::copy(row.begin(), row.end(), values.begin() + f * P * C);
            estimate.get_frame(f, frame.data());
            for (size_t i = 0; i < frame.size(); ++i)
                guide[static_cast<size_t>(f * P * C) + i] = static_cast<float>(std::log1p(std::max(0.0, frame[i] / gain / mean)));
        }
    });
    // The renderer's vectors, when given, replace the flow where they are not zero (X, Y, Z, W of each
    // pixel, contiguous).
    const bool use_vectors = options.vectors != nullptr;
    std::vector<float> vectors;
    if (use_vectors) {
        const Sequence& v = *options.vectors;
        vectors.resize(static_cast<size_t>(F * P * 4));
        for (int64_t f = 0; f < F; ++f)
            for (int64_t p = 0; p < P; ++p)
                for (int64_t c = 0; c < 4; ++c) vectors[static_cast<size_t>((f * P + p) * 4 + c)] = v.at(f, p / s.width, p % s.width, c);
    }
    // The flow's 8-bit images: the passes, or the first pass scaled so its 99.5th percentile is white.
    double scale = 1.0;
    if (!passes) {
        std::vector<float> sample;
        for (size_t i = 0; i < guide.size(); i += 7) sample.push_back(std::isfinite(guide[i]) ? guide[i] : 0.0f);
        auto q = sample.begin() + static_cast<std::ptrdiff_t>(0.995 * static_cast<double>(sample.size() - 1));
        std::nth_element(sample.begin(), q, sample.end());
        scale = *q > 0 ? 1.0 / *q : 1.0;
    }
    std::vector<cv::Mat> images(static_cast<size_t>(F));
    cv::parallel_for_(cv::Range(0, static_cast<int>(F)), [&](const cv::Range& frames) {
        std::vector<float> frame;
        for (int f = frames.start; f < frames.end; ++f) {
            if (passes) {
                frame.resize(static_cast<size_t>(P * passes->shape().channels));
                passes->get_frame(f, frame.data());
                images[static_cast<size_t>(f)] = flow_image(frame.data(), s.width, s.height, passes->shape().channels, 1.0);
            } else {
                images[static_cast<size_t>(f)] = flow_image(guide.data() + f * P * C, s.width, s.height, C, scale);
            }
        }
    });

    const bool estimate_flow = s.width >= kMinFlowSide && s.height >= kMinFlowSide;
    const double inv_two_sigma2 = 1.0 / (2.0 * options.sigma * options.sigma);
    std::vector<double> frame_weight(static_cast<size_t>(F), 0.0);
    std::mutex error_mutex;
    std::exception_ptr error;
    // Frames in batches so a long shot reports progress (and can be cancelled) between them.
    const int batch = std::max(1, cv::getNumThreads());
    for (int64_t start = 0; start < F; start += batch) {
        progress.report(static_cast<double>(start) / static_cast<double>(F));
        const int end = static_cast<int>(std::min<int64_t>(F, start + batch));
        cv::parallel_for_(cv::Range(static_cast<int>(start), end), [&](const cv::Range& frames) {
            try {
                cv::Ptr<cv::DISOpticalFlow> dis = cv::DISOpticalFlow::create(dis_preset(options.flow));
                cv::Mat flow;
                std::vector<double> sum(pixels.size() * static_cast<size_t>(C)), weight(pixels.size());
                std::vector<double> sample(static_cast<size_t>(C));
                std::vector<cv::Vec2f> where(pixels.size());  // each pixel's surface point in frame f
                std::vector<uint8_t> tracked(pixels.size());  // still followed (vectors consistent so far)
                std::vector<uint8_t> by_vector(pixels.size());  // followed along the vectors, else the flow
                for (int t = frames.start; t < frames.end; ++t) {
                    const double gain_t = options.frame_gain.empty() ? 1.0 : options.frame_gain[static_cast<size_t>(t)];
                    std::fill(sum.begin(), sum.end(), 0.0);
                    std::fill(weight.begin(), weight.end(), 0.0);
                    const float* gt = guide.data() + t * P * C;
                    // Frame t itself, then its neighbours outward, one side after the other: each step
                    // starts from the previous one (chained vectors; the flow warm-started from the last
                    // one of this side, never from another frame's), so the result does not depend on
                    // how frames are shared out between threads.
                    const auto accumulate = [&](int64_t f) {
                        const float* vf = values.data() + f * P * C;
                        const float* gf = guide.data() + f * P * C;
                        for (size_t i = 0; i < pixels.size(); ++i) {
                            if (!tracked[i]) continue;  // occluded or uncovered on the way: not the same surface
                            const int64_t p = pixels[i];
                            const float fx = where[i][0], fy = where[i][1];
                            if (!inside(s.width, s.height, where[i])) continue;  // outside frame f (NaN flow lands here too)
                            double mismatch = 0;
                            bool finite = true;
                            for (int64_t c = 0; c < C; ++c) {
                                const double e = bilinear(gf, s.width, s.height, C, fx, fy, c) - gt[p * C + c];
                                mismatch += e * e;
                                sample[static_cast<size_t>(c)] = bilinear(vf, s.width, s.height, C, fx, fy, c);
                                finite = finite && std::isfinite(sample[static_cast<size_t>(c)]);
                            }
                            const double w = std::exp(-mismatch * inv_two_sigma2);
                            if (!(w > 1e-4) || !finite) continue;  // another surface or light, or a non-finite sample
                            for (int64_t c = 0; c < C; ++c)
                                sum[i * static_cast<size_t>(C) + static_cast<size_t>(c)] += w * sample[static_cast<size_t>(c)];
                            weight[i] += w;
                        }
                    };
                    const auto start_at_t = [&] {
                        for (size_t i = 0; i < pixels.size(); ++i)
                            where[i] = cv::Vec2f(static_cast<float>(pixels[i] % s.width), static_cast<float>(pixels[i] / s.width));
                        std::fill(tracked.begin(), tracked.end(), uint8_t{1});
                    };
                    // Which pixels follow the vectors: those with a vector at t (Cycles writes exact zeros
                    // where no geometry is hit, and a static surface has them too); the others follow the flow.
                    int64_t by_flow = 0;
                    for (size_t i = 0; i < pixels.size(); ++i) {
                        const float* v = use_vectors ? vectors.data() + (t * P + pixels[i]) * 4 : nullptr;
                        by_vector[i] = v && (v[0] != 0 || v[1] != 0 || v[2] != 0 || v[3] != 0);
                        by_flow += !by_vector[i];
                    }
                    start_at_t();
                    accumulate(t);
                    for (const int dir : {-1, 1}) {
                        start_at_t();
                        flow.release();  // DIS starts from the flow it is handed: from zero on each side
                        const int64_t last = dir < 0 ? std::max<int64_t>(0, t - options.half_width)
                                                     : std::min<int64_t>(F - 1, t + options.half_width);
                        for (int64_t f = t + dir; dir < 0 ? f >= last : f <= last; f += dir) {
                            for (size_t i = 0; i < pixels.size(); ++i)
                                if (by_vector[i] && tracked[i])
                                    tracked[i] = follow_vectors(vectors.data(), s.width, s.height, f - dir, dir, where[i]);
                            if (by_flow > 0 && estimate_flow) {
                                dis->calc(images[static_cast<size_t>(t)], images[static_cast<size_t>(f)], flow);
                                for (size_t i = 0; i < pixels.size(); ++i) {
                                    if (by_vector[i]) continue;
                                    const int64_t p = pixels[i];
                                    const cv::Vec2f d = flow.at<cv::Vec2f>(static_cast<int>(p / s.width), static_cast<int>(p % s.width));
                                    where[i] = cv::Vec2f(static_cast<float>(p % s.width) + d[0], static_cast<float>(p / s.width) + d[1]);
                                }
                            }
                            accumulate(f);
                        }
                    }
                    double total = 0;
                    for (size_t i = 0; i < pixels.size(); ++i) {
                        if (!(weight[i] > 0)) continue;  // nothing finite to average: the pixel keeps its value
                        total += weight[i];
                        for (int64_t c = 0; c < C; ++c)
                            sample[static_cast<size_t>(c)] = sum[i * static_cast<size_t>(C) + static_cast<size_t>(c)] / weight[i];
                        inverse_transform(options.transform, sample.data(), sample.size());
                        for (int64_t c = 0; c < C; ++c)
                            output.at(t, pixels[i] / s.width, pixels[i] % s.width, c) = static_cast<float>(sample[static_cast<size_t>(c)] * gain_t);
                    }
                    frame_weight[static_cast<size_t>(t)] = total;
                }
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!error) error = std::current_exception();
            }
        });
        if (error) {
            try {
                std::rethrow_exception(error);
            } catch (const cv::Exception& e) {
                throw Error(Status::Internal, std::string("optical flow failed: ") + e.what());
            }
        }
    }
    progress.report(1.0);
    double total = 0;
    for (double w : frame_weight) total += w;
    stats.mean_frames = total / static_cast<double>(F * static_cast<int64_t>(pixels.size()));
    return stats;
}

}  // namespace statfilter
