#include "statfilter/robust_series.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "statfilter/vector_clones.hpp"

namespace statfilter {

double median_of(std::vector<double>& v) {
    const size_t n = v.size(), mid = n / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    double m = v[mid];
    if (n % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
    return m;
}

// The deviations are two sorted runs outward from the median, merged only as far as their middle. A
// series with a non-finite sample has no order to sort by: median_of twice.
std::pair<double, double> median_and_deviation(std::vector<double>& v) {
    const size_t n = v.size(), mid = n / 2;
    if (!std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); })) {
        const double m = median_of(v);
        for (double& x : v) x = std::fabs(x - m);
        return {m, median_of(v)};
    }
    std::sort(v.begin(), v.end());
    const double m = n % 2 ? v[mid] : 0.5 * (v[mid] + v[mid - 1]);
    // Left run: v[i] for i = split - 1 down to 0; right run: v[j] for j = split up; both in rising |v - m|.
    const size_t split = static_cast<size_t>(std::lower_bound(v.begin(), v.end(), m) - v.begin());
    size_t i = split, j = split;
    double previous = 0, current = 0;
    for (size_t k = 0; k <= mid; ++k) {
        const bool take_left = i > 0 && (j >= n || std::fabs(v[i - 1] - m) <= std::fabs(v[j] - m));
        previous = current;
        current = take_left ? std::fabs(v[--i] - m) : std::fabs(v[j++] - m);
    }
    return {m, n % 2 ? current : 0.5 * (current + previous)};
}

// TAOCP 5.2.2, Algorithm M.
std::vector<Comparator> sorting_network(int64_t n) {
    std::vector<Comparator> network;
    if (n < 2) return network;
    int64_t t = 0;
    while ((int64_t{1} << t) < n) ++t;
    for (int64_t p = int64_t{1} << (t - 1); p > 0; p >>= 1) {
        int64_t q = int64_t{1} << (t - 1), r = 0, d = p;
        while (d > 0) {
            for (int64_t i = 0; i < n - d; ++i)
                if ((i & p) == r) network.push_back({static_cast<int32_t>(i), static_cast<int32_t>(i + d)});
            d = q - p;
            q >>= 1;
            r = p;
        }
    }
    return network;
}

namespace {

// Series sorted side by side: x[k * kLanes + l] is value k of series l. Four doubles are one AVX2
// register (two SSE2 ones), so each comparator is a min and a max of whole registers.
constexpr int64_t kLanes = 4;
// Beyond this many frames a block's values outgrow the first-level cache: each series is sorted alone.
constexpr int64_t kMostNetworkFrames = 256;
static_assert(sizeof(Lanes) == kLanes * sizeof(double), "a comparator works on one Lanes vector");

SF_VECTOR_CLONES void sort_lanes(double* x, const Comparator* network, size_t count) {
    for (size_t c = 0; c < count; ++c) {
        double* a = x + network[c].first * kLanes;
        double* b = x + network[c].second * kLanes;
        Lanes u, v;
        std::memcpy(&u, a, sizeof u);
        std::memcpy(&v, b, sizeof v);
        const Lanes low = v < u ? v : u, high = v < u ? u : v;
        std::memcpy(a, &low, sizeof low);
        std::memcpy(b, &high, sizeof high);
    }
}

// The middle of kLanes sorted series of n values, as median_and_deviation takes it.
void middle(const double* x, int64_t n, double* out) {
    const int64_t mid = n / 2;
    for (int64_t l = 0; l < kLanes; ++l)
        out[l] = n % 2 ? x[mid * kLanes + l] : 0.5 * (x[mid * kLanes + l] + x[(mid - 1) * kLanes + l]);
}

}  // namespace

void medians_and_deviations(const double* values, int64_t stride, int64_t frames, int64_t count, double deviation_scale,
                            float* median, float* deviation) {
    if (frames <= 0) return;
    std::vector<double> series(static_cast<size_t>(frames));
    const auto one = [&](int64_t j) {
        for (int64_t f = 0; f < frames; ++f) series[static_cast<size_t>(f)] = values[f * stride + j];
        const auto [m, mad] = median_and_deviation(series);
        median[j] = static_cast<float>(m);
        deviation[j] = static_cast<float>(deviation_scale * mad);
    };
    int64_t j = 0;
    if (frames <= kMostNetworkFrames) {
        const std::vector<Comparator> network = sorting_network(frames);
        std::vector<double> x(static_cast<size_t>(frames * kLanes));
        for (; j + kLanes <= count; j += kLanes) {
            bool finite = true;
            for (int64_t f = 0; f < frames; ++f)
                for (int64_t l = 0; l < kLanes; ++l) {
                    const double v = values[f * stride + j + l];
                    finite = finite & std::isfinite(v);
                    x[static_cast<size_t>(f * kLanes + l)] = v;
                }
            if (!finite) {
                for (int64_t l = 0; l < kLanes; ++l) one(j + l);
                continue;
            }
            double m[kLanes], mad[kLanes];
            sort_lanes(x.data(), network.data(), network.size());
            middle(x.data(), frames, m);
            for (int64_t f = 0; f < frames; ++f)
                for (int64_t l = 0; l < kLanes; ++l) x[static_cast<size_t>(f * kLanes + l)] = std::fabs(x[static_cast<size_t>(f * kLanes + l)] - m[l]);
            sort_lanes(x.data(), network.data(), network.size());
            middle(x.data(), frames, mad);
            for (int64_t l = 0; l < kLanes; ++l) {
                median[j + l] = static_cast<float>(m[l]);
                deviation[j + l] = static_cast<float>(deviation_scale * mad[l]);
            }
        }
    }
    for (; j < count; ++j) one(j);
}

}  // namespace statfilter
