#include "filters/pass_motion.hpp"

#include <algorithm>
#include <vector>

#include "pipeline/band_view.hpp"
#include "statfilter/motion.hpp"

namespace statfilter {
namespace {

constexpr int64_t kAuxHalo = 2;  // the 3 x 3 opening: an erosion, then a dilation

}  // namespace

bool passes_show_motion(const GuideSources& passes, const PassMotionOptions& o) {
    return (o.surfaces && (passes.albedo || passes.normal)) || (passes.vectors && o.vector_drift > 0);
}

double pass_band_bytes(const Shape& s, int64_t pass_channels, int64_t rows) {
    return static_cast<double>(s.frames) * static_cast<double>(rows) * static_cast<double>(s.width) *
           static_cast<double>(pass_channels + 2) * sizeof(float);
}

double least_pass_band_bytes(const Shape& s) { return pass_band_bytes(s, 4, 1 + 2 * kAuxHalo); }

void raise_by_passes(float* weight, const Shape& s, const GuideSources& passes, const PassMotionOptions& o,
                     double budget_bytes, int threads, const ProgressSpan& progress) {
    const int64_t H = s.height, W = s.width;
    std::vector<float> buffer;
    const auto each_band = [&](const FrameSource& pass, int64_t halo, const auto& body) {
        const int64_t per_row = static_cast<int64_t>(pass_band_bytes(s, pass.shape().channels, 1));
        const int64_t rows = std::clamp<int64_t>(static_cast<int64_t>(budget_bytes) / std::max<int64_t>(1, per_row) - 2 * halo,
                                                 1, H);
        for (int64_t y0 = 0; y0 < H; y0 += rows) {
            progress.report(static_cast<double>(y0) / static_cast<double>(H));
            const int64_t y1 = std::min(H, y0 + rows);
            const int64_t a = std::max<int64_t>(0, y0 - halo), e = std::min(H, y1 + halo);
            const auto band = band_view(pass, a, e, buffer, threads,
                                        {progress.progress, progress.start + progress.span * y0 / H, 0, progress.stage});
            body(*band, y0, y1, y0 - a);
        }
    };
    if (o.surfaces)
        for (const FrameSource* pass : {passes.albedo, passes.normal}) {
            if (!pass) continue;
            each_band(*pass, kAuxHalo, [&](const Sequence& band, int64_t y0, int64_t y1, int64_t top) {
                const auto beta = local_motion_from_aux(band, o.aux_threshold, 0);
                for (int64_t f = 0; f < s.frames; ++f)
                    for (int64_t y = y0; y < y1; ++y)
                        for (int64_t x = 0; x < W; ++x)
                            weight[y * W + x] = std::max(weight[y * W + x], beta->at(f, top + y - y0, x, 0));
            });
        }
    if (passes.vectors && o.vector_drift > 0)
        each_band(*passes.vectors, 0, [&](const Sequence& band, int64_t y0, int64_t y1, int64_t) {
            const auto moving = motion_from_vectors(band, o.vector_drift);
            for (int64_t y = y0; y < y1; ++y)
                for (int64_t x = 0; x < W; ++x)
                    weight[y * W + x] = std::max(weight[y * W + x], moving->at(0, y - y0, x, 0));
        });
    buffer = std::vector<float>();
    progress.report(1.0);
}

}  // namespace statfilter
