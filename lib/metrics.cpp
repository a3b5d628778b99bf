#include "statfilter/metrics.hpp"

#include <algorithm>
#include <limits>
#include <cmath>
#include <vector>

#include "statfilter/error.hpp"

namespace statfilter {
namespace {

double tonemap(double v) { return std::clamp(v / (1.0 + std::max(v, 0.0)), 0.0, 1.0); }

// Luminance of a pixel: Rec.709 weights for RGB(A), the channel mean otherwise.
double luminance(const Sequence& s, int64_t f, int64_t y, int64_t x) {
    const int64_t C = s.shape().channels;
    if (C >= 3) return 0.2126 * s.at(f, y, x, 0) + 0.7152 * s.at(f, y, x, 1) + 0.0722 * s.at(f, y, x, 2);
    double sum = 0;
    for (int64_t c = 0; c < C; ++c) sum += s.at(f, y, x, c);
    return sum / static_cast<double>(C);
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

}  // namespace

Comparison compare_sequences(const Sequence& test, const Sequence& ref) {
    const Shape& s = ref.shape();
    if (test.shape() != s)
        throw Error(Status::InvalidArgument,
                    "cannot compare " + to_string(test.shape()) + " with a reference of " + to_string(s));
    const int64_t P = s.pixels(), F = s.frames, C = s.channels;

    // Per-pixel temporal std of the reference luminance splits moving from still pixels.
    std::vector<double> stdev(static_cast<size_t>(P));
    for (int64_t p = 0; p < P; ++p) {
        double sum = 0, sq = 0;
        for (int64_t f = 0; f < F; ++f) {
            const double l = luminance(ref, f, p / s.width, p % s.width);
            sum += l;
            sq += l * l;
        }
        const double mean = sum / F;
        stdev[p] = std::sqrt(std::max(0.0, sq / F - mean * mean));
    }
    const double med = median(stdev);

    Comparison out;
    double moving_err = 0, static_err = 0, tm_sq = 0, flicker = 0, jitter = 0;
    int64_t moving_n = 0, static_n = 0, moving_pixels = 0, flicker_n = 0, jitter_n = 0;
    for (int64_t p = 0; p < P; ++p) {
        const int64_t y = p / s.width, x = p % s.width;
        const bool moving = stdev[p] > 3 * med;
        const bool still = stdev[p] <= 1.5 * med;
        moving_pixels += moving ? 1 : 0;
        for (int64_t f = 0; f < F; ++f) {
            for (int64_t c = 0; c < C; ++c) {
                const double a = test.at(f, y, x, c), r = ref.at(f, y, x, c);
                const double e = (a - r) * (a - r) / (r * r + 0.01);
                (moving ? moving_err : static_err) += e;
                (moving ? moving_n : static_n) += 1;
                const double d = tonemap(a) - tonemap(r);
                tm_sq += d * d;
                if (f > 0) {
                    const double da = tonemap(a) - tonemap(test.at(f - 1, y, x, c));
                    const double dr = tonemap(r) - tonemap(ref.at(f - 1, y, x, c));
                    flicker += std::fabs(da - dr);
                    ++flicker_n;
                }
            }
            if (still && f > 0 && f + 1 < F) {
                const double l0 = tonemap(luminance(test, f - 1, y, x)), l1 = tonemap(luminance(test, f, y, x)),
                             l2 = tonemap(luminance(test, f + 1, y, x));
                jitter += std::fabs(l2 - 2 * l1 + l0);
                ++jitter_n;
            }
        }
    }
    const double total = static_cast<double>(moving_n + static_n);
    out.rel_mse = (moving_err + static_err) / total;
    out.rel_mse_moving = moving_n ? moving_err / moving_n : 0;
    out.rel_mse_static = static_n ? static_err / static_n : 0;
    out.moving_fraction = static_cast<double>(moving_pixels) / P;
    const double mse = tm_sq / total;
    out.psnr = mse > 0 ? 10 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
    out.flicker = flicker_n ? flicker / flicker_n : 0;
    out.jitter = jitter_n ? jitter / jitter_n : 0;
    return out;
}

}  // namespace statfilter
