#include "statfilter/noise_in_time.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace statfilter {
namespace {

// 1.4826 x the median of |v|: the standard deviation of a Gaussian with that median deviation.
double robust_deviation(std::vector<double>& v) {
    if (v.empty()) return 0;
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return 1.4826 * *mid;
}

// The frame's median positive finite sample (1 when it has none): the unit of log(1 + x / m).
double median_positive(const float* x, int64_t n) {
    std::vector<float> positive;
    positive.reserve(static_cast<size_t>(n));
    for (int64_t i = 0; i < n; ++i)
        if (std::isfinite(x[i]) && x[i] > 0) positive.push_back(x[i]);
    if (positive.empty()) return 1.0;
    const auto mid = positive.begin() + static_cast<std::ptrdiff_t>(positive.size() / 2);
    std::nth_element(positive.begin(), mid, positive.end());
    return *mid;
}

std::vector<double> log_units(const float* x, int64_t n) {
    const double m = median_positive(x, n);
    std::vector<double> v(static_cast<size_t>(n));
    for (int64_t i = 0; i < n; ++i)
        v[static_cast<size_t>(i)] = std::isfinite(x[i]) && x[i] >= 0 ? std::log1p(x[i] / m) : NAN;
    return v;
}

// |v - mean of its 4 neighbours| over the interior samples, / sqrt(1.25): one sample's noise.
void spatial_residuals(const std::vector<double>& v, int64_t rows, int64_t width, int64_t channels,
                       std::vector<double>& out) {
    const auto at = [&](int64_t y, int64_t x, int64_t c) { return v[static_cast<size_t>((y * width + x) * channels + c)]; };
    for (int64_t y = 1; y + 1 < rows; ++y)
        for (int64_t x = 1; x + 1 < width; ++x)
            for (int64_t c = 0; c < channels; ++c) {
                const double e = at(y, x, c) - 0.25 * (at(y - 1, x, c) + at(y + 1, x, c) + at(y, x - 1, c) + at(y, x + 1, c));
                if (std::isfinite(e)) out.push_back(std::fabs(e) / std::sqrt(1.25));
            }
}

}  // namespace

NoiseInTime measure_noise_in_time(const float* a, const float* b, int64_t rows, int64_t width, int64_t channels) {
    NoiseInTime r;
    const int64_t n = rows * width * channels;
    if (n <= 0) return r;
    const std::vector<double> va = log_units(a, n), vb = log_units(b, n);
    std::vector<double> change;
    change.reserve(static_cast<size_t>(n));
    for (int64_t i = 0; i < n; ++i) {
        const double d = vb[static_cast<size_t>(i)] - va[static_cast<size_t>(i)];
        if (std::isfinite(d)) change.push_back(std::fabs(d) / std::sqrt(2.0));  // two samples' noise
    }
    std::vector<double> across;
    across.reserve(2 * static_cast<size_t>(n));
    spatial_residuals(va, rows, width, channels, across);
    spatial_residuals(vb, rows, width, channels, across);
    if (change.empty() || across.empty()) return r;
    r.temporal = robust_deviation(change);
    r.spatial = robust_deviation(across);
    r.pairs = 1;
    return r;
}

NoiseInTime combine_noise_in_time(const NoiseInTime* pairs, int64_t count) {
    std::vector<double> t, s;
    for (int64_t i = 0; i < count; ++i)
        if (pairs[i].pairs > 0) {
            t.push_back(pairs[i].temporal);
            s.push_back(pairs[i].spatial);
        }
    NoiseInTime r;
    if (t.empty()) return r;
    const auto median = [](std::vector<double>& v) {
        std::sort(v.begin(), v.end());
        const size_t n = v.size();
        return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    };
    r.temporal = median(t);
    r.spatial = median(s);
    r.pairs = static_cast<int64_t>(t.size());
    return r;
}

}  // namespace statfilter
