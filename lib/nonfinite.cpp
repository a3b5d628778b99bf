#include "statfilter/nonfinite.hpp"

#include <cmath>
#include <vector>

#include "statfilter/error.hpp"

namespace statfilter {

NonFinitePolicy parse_nonfinite_policy(const std::string& name) {
    if (name == "error") return NonFinitePolicy::Error;
    if (name == "repair") return NonFinitePolicy::Repair;
    throw Error(Status::InvalidArgument, "unknown non-finite policy '" + name + "' (error, repair)");
}

int64_t check_nonfinite(const Sequence& seq, NonFinitePolicy policy, int64_t first_row) {
    const Shape& s = seq.shape();
    if (seq.is_contiguous()) {  // the usual case: one branch-free sweep, the detailed walk only if needed
        const float* data = seq.data();
        bool all_finite = true;
        for (int64_t i = 0; i < s.samples(); ++i) all_finite &= std::isfinite(data[i]);
        if (all_finite) return 0;
    }
    int64_t count = 0;
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) {
                    const float v = seq.at(f, y, x, c);
                    if (std::isfinite(v)) continue;
                    if (policy == NonFinitePolicy::Error)
                        throw Error(Status::Numeric,
                                    std::string(std::isnan(v) ? "NaN" : "Inf") + " in frame " +
                                        std::to_string(seq.frame_numbers()[f]) + " at pixel (" + std::to_string(x) +
                                        ", " + std::to_string(first_row + y) + ") channel '" + seq.channel_names()[c] +
                                        "'; set nonfinite=repair to replace such samples and count them");
                    ++count;
                }
    return count;
}

void repair_nonfinite(double* tile, int64_t frames, int64_t n) {
    std::vector<double> sum(static_cast<size_t>(n), 0.0);
    std::vector<int64_t> finite(static_cast<size_t>(n), 0);
    bool any = false;
    for (int64_t f = 0; f < frames; ++f)
        for (int64_t j = 0; j < n; ++j) {
            const double v = tile[f * n + j];
            if (std::isfinite(v)) {
                sum[j] += v;
                ++finite[j];
            } else {
                any = true;
            }
        }
    if (!any) return;
    for (int64_t f = 0; f < frames; ++f)
        for (int64_t j = 0; j < n; ++j) {
            double& v = tile[f * n + j];
            if (!std::isfinite(v)) v = finite[j] ? sum[j] / static_cast<double>(finite[j]) : 0.0;
        }
}

void repair_sequence_nonfinite(Sequence& seq) {
    const Shape& s = seq.shape();
    std::vector<double> series(static_cast<size_t>(s.frames));
    for (int64_t y = 0; y < s.height; ++y)
        for (int64_t x = 0; x < s.width; ++x)
            for (int64_t c = 0; c < s.channels; ++c) {
                bool bad = false;
                for (int64_t f = 0; f < s.frames; ++f) {
                    series[static_cast<size_t>(f)] = seq.at(f, y, x, c);
                    bad = bad || !std::isfinite(series[static_cast<size_t>(f)]);
                }
                if (!bad) continue;
                repair_nonfinite(series.data(), s.frames, 1);
                for (int64_t f = 0; f < s.frames; ++f) seq.at(f, y, x, c) = static_cast<float>(series[static_cast<size_t>(f)]);
            }
}

}  // namespace statfilter
