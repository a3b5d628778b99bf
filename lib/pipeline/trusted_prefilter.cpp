#include "pipeline/trusted_prefilter.hpp"

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

}  // namespace statfilter
