#include "statfilter/value_transform.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "statfilter/error.hpp"
#include "statfilter/fast_log_exp.hpp"

namespace statfilter {

ValueTransform parse_value_transform(const std::string& name) {
    if (name == "none") return ValueTransform::None;
    if (name == "sqrt") return ValueTransform::Sqrt;
    if (name == "log") return ValueTransform::Log;
    throw Error(Status::InvalidArgument, "unknown transform '" + name + "' (none, sqrt, log)");
}

void forward_transform(ValueTransform t, double scale, double* v, size_t n) {
    const double inv = 1.0 / scale;
    switch (t) {
    case ValueTransform::None: return;
    case ValueTransform::Sqrt:
        for (size_t i = 0; i < n; ++i) v[i] = std::copysign(std::sqrt(std::fabs(v[i]) * inv), v[i]);
        return;
    case ValueTransform::Log:
        fast_math::signed_log1p(v, n, inv);  // within 4 ulp of std::log1p, vectorised
        return;
    }
}

void inverse_transform(ValueTransform t, double scale, double* v, size_t n) {
    switch (t) {
    case ValueTransform::None: return;
    case ValueTransform::Sqrt:
        for (size_t i = 0; i < n; ++i) v[i] = scale * std::copysign(v[i] * v[i], v[i]);
        return;
    case ValueTransform::Log:
        fast_math::signed_expm1(v, n, scale);  // within 4 ulp of std::expm1, vectorised
        return;
    }
}

void forward_transform(ValueTransform t, double* v, size_t n) { forward_transform(t, 1.0, v, n); }
void inverse_transform(ValueTransform t, double* v, size_t n) { inverse_transform(t, 1.0, v, n); }

std::vector<int64_t> transform_level_frames(int64_t frames) {
    // Up to four frames spread over the shot: enough samples for a robust level, and few enough that
    // a streamed run reads them before its passes at little cost.
    const int64_t k = std::min<int64_t>(frames, 4);
    std::vector<int64_t> picked;
    for (int64_t i = 0; i < k; ++i) picked.push_back(k == 1 ? 0 : i * (frames - 1) / (k - 1));
    return picked;
}

double transform_level(const Sequence& seq, ChannelSelection group) {
    const Shape& s = seq.shape();
    const std::vector<int64_t> picked = transform_level_frames(s.frames);
    // Every stride-th sample of the group in those frames, in storage order (a fixed subset, so any
    // tiling of the later passes sees the same level), at most ~2^20 of them.
    const int64_t count = static_cast<int64_t>(picked.size()) * s.pixels() * group.count;
    const int64_t stride = std::max<int64_t>(1, (count + (1 << 20) - 1) >> 20);
    std::vector<float> magnitudes, frame(static_cast<size_t>(s.pixels() * s.channels));
    magnitudes.reserve(static_cast<size_t>(count / stride + 1));
    int64_t i = 0;
    for (int64_t f : picked) {
        seq.get_frame(f, frame.data());
        for (int64_t p = 0; p < s.pixels(); ++p)
            for (int64_t c = group.first; c < group.first + group.count; ++c, ++i) {
                if (i % stride) continue;
                const float v = std::fabs(frame[static_cast<size_t>(p * s.channels + c)]);
                if (v > 0 && std::isfinite(v)) magnitudes.push_back(v);
            }
    }
    if (magnitudes.empty()) return 1.0;
    const auto mid = magnitudes.begin() + static_cast<std::ptrdiff_t>(magnitudes.size() / 2);
    std::nth_element(magnitudes.begin(), mid, magnitudes.end());
    return static_cast<double>(*mid);
}

namespace {

// The correction p when output samples are clamped at 0: with the samples sorted descending, the
// first k kept and the rest at 0, the p matching the mean from the k largest; the right k is the
// one whose p keeps exactly those k positive (out is increasing in the sample and in p). The sums
// over the k largest are running sums, added in the same order as summing each prefix afresh
// (the same numbers), so the search is linear after the sort instead of quadratic.
template <class Out, class Solve>
double solve_with_clamp(std::vector<double> x, double b, const Out& out, const Solve& solve) {
    std::sort(x.begin(), x.end(), std::greater<double>());
    const auto n = static_cast<int64_t>(x.size());
    double sx = 0, su = 0;
    for (int64_t i = 0; i < n; ++i) sx += x[i], su += x[i] + b;
    double p = solve(sx, su, n);
    sx = su = 0;
    for (int64_t k = 1; k <= n; ++k) {
        sx += x[k - 1], su += x[k - 1] + b;
        p = solve(sx, su, k);
        if (out(x[k - 1], p) > 0 && (k == n || !(out(x[k], p) > 0))) return p;
    }
    return p;
}

}  // namespace

MeanCorrection solve_mean_correction(ValueTransform t, double scale, const double* x, int64_t F, double target_mean,
                                     bool non_negative) {
    MeanCorrection c;
    c.clamp = non_negative;
    if (F <= 0) return c;
    if (non_negative && !(target_mean > 0)) {
        c.kind = MeanCorrection::Constant;
        c.p = 0.0;
        return c;
    }
    const double total = target_mean * static_cast<double>(F);
    // Multiplicative for the compressing transforms on non-negative data: x + b (b = s for log, 0 for
    // sqrt) scaled by 1 + p, the inverse's own form, so the correction never flips a sign; written
    // x + p (x + b) so that a scale far above the samples loses no precision. Additive otherwise
    // (none keeps the mean already; signed data may cross zero).
    const bool multiplicative = non_negative && t != ValueTransform::None;
    c.kind = multiplicative ? MeanCorrection::Scale : MeanCorrection::Shift;
    c.b = t == ValueTransform::Log ? scale : 0.0;
    const double b = c.b;
    auto out = [&](double xv, double q) { return multiplicative ? xv + q * (xv + b) : xv + q; };
    // The correction when the k largest samples are the ones kept (all of them without clamping),
    // from their sum sx and the sum su of x + b.
    auto solve = [&](double sx, double su, int64_t k) {
        if (!multiplicative) return (total - sx) / static_cast<double>(k);
        return su > 0 ? (total - sx) / su : 0.0;
    };
    double sx = 0, su = 0;
    for (int64_t i = 0; i < F; ++i) sx += x[i], su += x[i] + b;
    c.p = solve(sx, su, F);
    if (multiplicative && !(su > 0)) {  // nothing left to scale: the mean itself
        c.kind = MeanCorrection::Constant;
        c.p = target_mean;
        return c;
    }
    if (non_negative && std::any_of(x, x + F, [&](double xv) { return out(xv, c.p) < 0; }))
        c.p = solve_with_clamp(std::vector<double>(x, x + F), b, out, solve);
    return c;
}

void inverse_transform_keeping_mean(ValueTransform t, double scale, double* v, int64_t F, int64_t stride,
                                    double target_mean, bool non_negative) {
    if (F <= 0) return;
    std::vector<double> x(static_cast<size_t>(F));
    for (int64_t f = 0; f < F; ++f) x[f] = v[f * stride];
    inverse_transform(t, scale, x.data(), x.size());
    const MeanCorrection c = solve_mean_correction(t, scale, x.data(), F, target_mean, non_negative);
    for (int64_t f = 0; f < F; ++f) v[f * stride] = c.apply(x[f]);
}

}  // namespace statfilter
