#include "pipeline/noise_probe.hpp"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace statfilter {

NoiseInTime probe_noise_in_time(const FrameSource& source) {
    const Shape& s = source.shape();
    if (s.frames < 2 || s.width <= 0 || s.height <= 0) return {};
    const int64_t rows = std::min(s.height, kNoiseProbeRows);
    const int64_t y0 = (s.height - rows) / 2;
    std::vector<int64_t> firsts = {0, (s.frames - 2) / 2, s.frames - 2};
    firsts.erase(std::unique(firsts.begin(), firsts.end()), firsts.end());
    const auto samples = static_cast<size_t>(rows * s.width * s.channels);
    std::vector<float> a(samples), b(samples);
    std::vector<NoiseInTime> pairs;
    for (const int64_t f : firsts) {
        source.read_rows(f, y0, y0 + rows, a.data());
        source.read_rows(f + 1, y0, y0 + rows, b.data());
        pairs.push_back(measure_noise_in_time(a.data(), b.data(), rows, s.width, s.channels));
    }
    return combine_noise_in_time(pairs.data(), static_cast<int64_t>(pairs.size()));
}

std::string same_noise_warning(const NoiseInTime& noise) {
    if (!(noise.ratio() < kSameNoiseRatio)) return "";
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "%.2f", noise.ratio());
    return std::string("the noise is the same in every frame (its change from frame to frame is ") + ratio +
           "x its spread across the frame; independent noise gives about 1): a temporal filter cannot remove it. "
           "Render each frame with its own seed (Cycles: the clock icon beside Sampling > Advanced > Seed), or use a "
           "single-frame denoiser (--method oidn)";
}

}  // namespace statfilter
