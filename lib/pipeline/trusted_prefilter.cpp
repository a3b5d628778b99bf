#include "pipeline/trusted_prefilter.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "pipeline/parallel.hpp"

namespace statfilter {

void prefilter_and_probe(FrameStagePool& prefilter, const Sequence& noisy, Sequence& prefiltered, TimeTrust& trust,
                         int threads, const ProgressSpan& progress) {
    const Shape& s = noisy.shape();
    const auto samples = static_cast<size_t>(s.pixels() * s.channels);
    parallel_for(s.frames, threads, [&](int64_t f) {
        std::vector<float> x(samples), y(samples);
        noisy.get_frame(f, x.data());
        y = x;
        prefilter.apply(f, y.data(), s, noisy);
        trust.probe(f, x.data(), y.data(), [&](float* frame) { prefilter.apply(f, frame, s, noisy); });
        prefiltered.set_frame(f, y.data());
    }, progress);
}

std::vector<float> filter_frames(FrameStagePool& filter, Sequence& frames, const Sequence& attributes, int threads,
                                 const ProgressSpan& progress, bool keep_light) {
    const Shape& s = frames.shape();
    const Shape one{1, s.height, s.width, s.channels};
    std::vector<std::vector<double>> before(static_cast<size_t>(s.frames)), after(before.size());
    parallel_for(s.frames, threads, [&](int64_t f) {
        std::vector<float> x(static_cast<size_t>(s.pixels() * s.channels));
        frames.get_frame(f, x.data());
        if (keep_light) before[static_cast<size_t>(f)] = channel_sums(x.data(), one);
        filter.apply(f, x.data(), s, attributes);
        if (keep_light) after[static_cast<size_t>(f)] = channel_sums(x.data(), one);
        frames.set_frame(f, x.data());
    }, progress);
    if (!keep_light) return {};
    std::vector<float> gain = light_gain(before, after);
    scale_channels(frames, gain, threads);
    return gain;
}

void scale_channels(Sequence& frames, const std::vector<float>& gain, int threads) {
    const Shape& s = frames.shape();
    const Progress none;
    parallel_for(s.frames, threads, [&](int64_t f) {
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) frames.at(f, y, x, c) *= gain[static_cast<size_t>(c)];
    }, ProgressSpan{none, 0, 1, "light"});
}

void scale_channels(float* frame, const Shape& shape, const std::vector<float>& gain) {
    for (int64_t p = 0; p < shape.pixels(); ++p)
        for (int64_t c = 0; c < shape.channels; ++c) frame[p * shape.channels + c] *= gain[static_cast<size_t>(c)];
}

std::vector<double> channel_sums(const float* frame, const Shape& shape) {
    std::vector<double> sums(static_cast<size_t>(shape.channels), 0.0);
    for (int64_t p = 0; p < shape.pixels(); ++p)
        for (int64_t c = 0; c < shape.channels; ++c) {
            const float v = frame[p * shape.channels + c];
            if (std::isfinite(v)) sums[static_cast<size_t>(c)] += v;
        }
    return sums;
}

std::vector<float> light_gain(const std::vector<std::vector<double>>& noisy, const std::vector<std::vector<double>>& prefiltered) {
    if (noisy.empty()) return {};
    std::vector<double> a(noisy.front().size(), 0.0), b(a.size(), 0.0);
    for (size_t f = 0; f < noisy.size(); ++f)
        for (size_t c = 0; c < a.size(); ++c) {
            a[c] += noisy[f][c];
            b[c] += prefiltered[f][c];
        }
    std::vector<float> gain(a.size(), 1.0f);
    for (size_t c = 0; c < a.size(); ++c)
        if (a[c] > 0 && b[c] > 0 && std::isfinite(a[c] / b[c])) gain[c] = static_cast<float>(a[c] / b[c]);
    return gain;
}

void keep_prefilter_light(const Sequence& noisy, Sequence& prefiltered, int threads) {
    const Shape& s = noisy.shape();
    const Shape frame{1, s.height, s.width, s.channels};
    const auto samples = static_cast<size_t>(s.pixels() * s.channels);
    std::vector<std::vector<double>> a(static_cast<size_t>(s.frames)), b(a.size());
    const Progress none;
    parallel_for(s.frames, threads, [&](int64_t f) {
        std::vector<float> x(samples);
        noisy.get_frame(f, x.data());
        a[static_cast<size_t>(f)] = channel_sums(x.data(), frame);
        prefiltered.get_frame(f, x.data());
        b[static_cast<size_t>(f)] = channel_sums(x.data(), frame);
    }, ProgressSpan{none, 0, 1, "light"});
    scale_channels(prefiltered, light_gain(a, b), threads);
}

double blend_toward_prefilter(TimeTrust& trust, const Sequence& noisy, const Sequence& prefiltered, Sequence& result,
                              int threads) {
    const Shape& s = noisy.shape();
    const auto samples = static_cast<size_t>(s.pixels() * s.channels);
    const Progress none;
    parallel_for(s.frames, threads, [&](int64_t f) {
        std::vector<float> x(samples), y(samples), z(samples);
        noisy.get_frame(f, x.data());
        prefiltered.get_frame(f, y.data());
        result.get_frame(f, z.data());
        trust.measure(f, x.data(), y.data(), z.data());
    }, ProgressSpan{none, 0, 1, "blend"});
    std::vector<double> share(static_cast<size_t>(s.frames), 1.0);
    parallel_for(s.frames, threads, [&](int64_t f) {
        std::vector<float> y(samples), z(samples);
        prefiltered.get_frame(f, y.data());
        result.get_frame(f, z.data());
        share[static_cast<size_t>(f)] = trust.blend(f, y.data(), z.data());
        result.set_frame(f, z.data());
    }, ProgressSpan{none, 0, 1, "blend"});
    double mean = 0;
    for (double v : share) mean += v;
    return s.frames > 0 ? mean / static_cast<double>(s.frames) : 1.0;
}

namespace {

class ProbedSource final : public FrameSource {
public:
    ProbedSource(const FrameSource& source, const TimeTrust& trust) : source_(source), trust_(trust) {}
    const Shape& shape() const override { return source_.shape(); }
    const Sequence& attributes() const override { return source_.attributes(); }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override {
        source_.read_rows(f, y0, y1, dst);
        trust_.perturb_rows(f, y0, y1, dst);
    }

private:
    const FrameSource& source_;
    const TimeTrust& trust_;
};

}  // namespace

std::unique_ptr<FrameSource> probed_source(const FrameSource& source, const TimeTrust& trust) {
    return std::make_unique<ProbedSource>(source, trust);
}

void probe_temporal_result(TimeTrust& trust, const Sequence& noisy, const Sequence& prefiltered, const Sequence& result,
                           const Sequence& probed_result, int threads) {
    const Shape& s = noisy.shape();
    const auto samples = static_cast<size_t>(s.pixels() * s.channels);
    const Progress none;
    parallel_for(s.frames, threads, [&](int64_t f) {
        std::vector<float> x(samples), y(samples), z(samples), zp(samples);
        noisy.get_frame(f, x.data());
        prefiltered.get_frame(f, y.data());
        result.get_frame(f, z.data());
        probed_result.get_frame(f, zp.data());
        trust.probe_temporal(f, x.data(), y.data(), z.data(), zp.data());
    }, ProgressSpan{none, 0, 1, "blend"});
}

bool prepare_temporal_probe(TimeTrust& trust, const TimeTrustOptions& options, const Results& results) {
    bool any = false;
    if (results.has(kMotionPathResult)) {
        const auto path = results.image(kMotionPathResult);
        const Shape& s = path->shape();
        std::vector<float> weight(static_cast<size_t>(s.pixels()));
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x) {
                const float w = std::clamp(path->at(0, y, x, 0), 0.0f, 1.0f);
                weight[static_cast<size_t>(y * s.width + x)] = w;
                any = any || w > 0;
            }
        trust.set_motion_path(std::move(weight));
    }
    switch (options.temporal_probe) {
    case TimeTrustOptions::TemporalProbe::None: return false;
    case TimeTrustOptions::TemporalProbe::Everywhere: return true;
    case TimeTrustOptions::TemporalProbe::WhereMoving: return any;
    }
    return false;
}

}  // namespace statfilter
