#include "statfilter/motion_compensation.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>

#include <opencv2/core.hpp>

#include "statfilter/aligned_frame.hpp"
#include "statfilter/error.hpp"

namespace statfilter {

FlowPreset parse_flow_preset(const std::string& name) {
    if (name == "ultrafast") return FlowPreset::UltraFast;
    if (name == "fast") return FlowPreset::Fast;
    if (name == "medium") return FlowPreset::Medium;
    throw Error(Status::InvalidArgument, "flow preset '" + name + "': expected ultrafast, fast or medium");
}

void pass_guide_pixels(const float* pass, int64_t channels, bool normal, int64_t pixels, float* out, int64_t stride) {
    for (int64_t p = 0; p < pixels; ++p)
        for (int64_t c = 0; c < 3; ++c) {
            // A pass with fewer than three channels repeats its last one.
            const float v = pass[p * channels + std::min(c, channels - 1)];
            out[p * stride + c] = normal ? 0.5f * v + 0.5f : v;
        }
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
    const int64_t passes = (albedo ? 1 : 0) + (normal ? 1 : 0), P = a.pixels();
    auto guide = std::make_unique<Sequence>(Shape{a.frames, a.height, a.width, 3 * passes});
    std::vector<float> frame;
    int64_t group = 0;
    for (const Sequence* pass : {albedo, normal}) {
        if (!pass) continue;
        const int64_t C = pass->shape().channels;
        frame.resize(static_cast<size_t>(P * C));
        for (int64_t f = 0; f < a.frames; ++f) {
            pass->get_frame(f, frame.data());
            pass_guide_pixels(frame.data(), C, pass == normal, P, &guide->at(f, 0, 0, 3 * group), 3 * passes);
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

    // Every frame's samples, guide and flow image, made as a stream would make them (aligned_frame.hpp).
    const auto gain = [&](int64_t f) { return options.frame_gain.empty() ? 1.0 : options.frame_gain[static_cast<size_t>(f)]; };
    const int64_t frame_samples = P * C;
    std::vector<float> values(static_cast<size_t>(F * frame_samples)), guide(values.size());
    std::vector<double> sums(static_cast<size_t>(F));
    cv::parallel_for_(cv::Range(0, static_cast<int>(F)), [&](const cv::Range& frames) {
        std::vector<float> frame(static_cast<size_t>(frame_samples));
        for (int f = frames.start; f < frames.end; ++f) {
            estimate.get_frame(f, frame.data());
            sums[static_cast<size_t>(f)] = positive_sum(frame.data(), frame_samples);
        }
    });
    double sum = 0;
    for (double v : sums) sum += v;
    const double mean = estimate_mean(sum, F * frame_samples);
    cv::parallel_for_(cv::Range(0, static_cast<int>(F)), [&](const cv::Range& frames) {
        std::vector<float> frame(static_cast<size_t>(frame_samples));
        for (int f = frames.start; f < frames.end; ++f) {
            input.get_frame(f, frame.data());
            aligned_values(frame.data(), frame_samples, gain(f), options.transform, values.data() + f * frame_samples);
            estimate.get_frame(f, frame.data());
            aligned_guide(frame.data(), frame_samples, gain(f), mean, guide.data() + f * frame_samples);
        }
    });
    // The flow's 8-bit images: the passes, or the first pass scaled so its 99.5th percentile is white.
    double scale = 1.0;
    if (!passes) {
        GuideScale quantile(frame_samples);
        for (int64_t f = 0; f < F; ++f) quantile.count(f, guide.data() + f * frame_samples);
        quantile.finish_counting();
        for (int64_t f = 0; f < F; ++f) quantile.collect(f, guide.data() + f * frame_samples);
        scale = quantile.scale();
    }
    std::vector<uint8_t> images(static_cast<size_t>(F * P));
    cv::parallel_for_(cv::Range(0, static_cast<int>(F)), [&](const cv::Range& frames) {
        std::vector<float> frame;
        for (int f = frames.start; f < frames.end; ++f) {
            if (passes) {
                frame.resize(static_cast<size_t>(P * passes->shape().channels));
                passes->get_frame(f, frame.data());
                flow_image(frame.data(), s.width, s.height, passes->shape().channels, 1.0, images.data() + f * P);
            } else {
                flow_image(guide.data() + f * frame_samples, s.width, s.height, C, scale, images.data() + f * P);
            }
        }
    });
    // The renderer's vectors, when given, replace the flow where they are not zero (X, Y, Z, W of each
    // pixel, contiguous).
    std::vector<float> vectors;
    if (options.vectors) {
        const Sequence& v = *options.vectors;
        vectors.resize(static_cast<size_t>(F * P * 4));
        for (int64_t f = 0; f < F; ++f)
            for (int64_t p = 0; p < P; ++p)
                for (int64_t c = 0; c < 4; ++c) vectors[static_cast<size_t>((f * P + p) * 4 + c)] = v.at(f, p / s.width, p % s.width, c);
    }
    const AlignedAverager averager(s, pixels, options);
    AlignedWindow window;
    window.values = [&](int64_t f) { return values.data() + f * frame_samples; };
    window.guide = [&](int64_t f) { return guide.data() + f * frame_samples; };
    window.image = [&](int64_t f) { return images.data() + f * P; };
    if (!vectors.empty()) window.vectors = [&](int64_t f) { return vectors.data() + f * P * 4; };

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
                std::vector<float> frame(static_cast<size_t>(frame_samples));
                for (int t = frames.start; t < frames.end; ++t) {
                    output.get_frame(t, frame.data());
                    frame_weight[static_cast<size_t>(t)] = averager.average(t, window, frame.data());
                    output.set_frame(t, frame.data());
                }
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!error) error = std::current_exception();
            }
        });
        if (error) std::rethrow_exception(error);
    }
    progress.report(1.0);
    double total = 0;
    for (double w : frame_weight) total += w;
    stats.mean_frames = total / static_cast<double>(F * static_cast<int64_t>(pixels.size()));
    return stats;
}

}  // namespace statfilter
