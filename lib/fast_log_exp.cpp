// The vectorised log1p and expm1 (statfilter/fast_log_exp.hpp). Built with -fno-trapping-math
// (lib/CMakeLists.txt): without it GCC keeps the selects below as branches, since a compare or a
// division might raise a floating-point exception, and the loops stay scalar. The values are the
// same either way; only the exception flags, which nothing here reads, may differ.
#include "statfilter/fast_log_exp.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "statfilter/vector_clones.hpp"

namespace statfilter {
namespace fast_math {

inline uint64_t bits(double x) {
    uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
}
inline double from_bits(uint64_t b) {
    double x;
    std::memcpy(&x, &b, sizeof x);
    return x;
}

// log1p(x) for 0 <= x <= 1e300: log(u) for u = 1 + x (fdlibm's reduction of u to 2^k m, m in
// [sqrt(2)/2, sqrt(2)), and its degree-14 series in s = (m - 1) / (m + 1)), plus the rounding error
// of u over u, which makes small x exact (log1p(x) = x below 2^-53).
inline double log1p_nonneg(double x) {
    constexpr double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
    constexpr double Lg1 = 6.666666666666735130e-01, Lg2 = 3.999999999940941908e-01, Lg3 = 2.857142874366239149e-01,
                     Lg4 = 2.222219843214978396e-01, Lg5 = 1.818357216161805012e-01, Lg6 = 1.531383769920937332e-01,
                     Lg7 = 1.479819860511658591e-01;
    const double u = 1.0 + x;
    // x + 1 - u exactly (Fast2Sum, the larger operand first), divided by u: log1p(x) ~ log(u) + c.
    const double small = x - (u - 1.0), large = 1.0 - (u - x);
    const double c = (x < 1.0 ? small : large) / u;
    uint64_t ix = bits(u);
    uint64_t hx = (ix >> 32) + (0x3ff00000 - 0x3fe6a09e);
    // k = (hx >> 20) - 1023 as a double through the bits (0 <= hx >> 20 < 2^12): no integer conversion,
    // which SSE2 has no vector form of.
    const double k = from_bits(0x4330000000000000ULL | (hx >> 20)) - (0x1p52 + 1023.0);
    hx = (hx & 0x000fffff) + 0x3fe6a09e;
    ix = (hx << 32) | (ix & 0xffffffff);
    const double f = from_bits(ix) - 1.0;
    const double hfsq = 0.5 * f * f, s = f / (2.0 + f), z = s * s, w = z * z;
    const double t1 = w * (Lg2 + w * (Lg4 + w * Lg6)), t2 = z * (Lg1 + w * (Lg3 + w * (Lg5 + w * Lg7)));
    return s * (hfsq + t1 + t2) + (k * ln2_lo + c) - hfsq + f + k * ln2_hi;
}

// The reduction of expm1 and exp: y = k ln2 + r, |r| <= ln2 / 2, for |y| <= 700. Returns expm1(r) by
// its Taylor series to r^13 (truncation below 1e-17 relative); t holds k rounded to nearest in its low
// mantissa bits, for two_to_k.
constexpr double kShifter = 0x1.8p52;
inline double expm1_reduced(double y, double& t) {
    constexpr double inv_ln2 = 1.44269504088896338700e+00, ln2_hi = 6.93147180369123816490e-01,
                     ln2_lo = 1.90821492927058770002e-10;
    t = y * inv_ln2 + kShifter;
    const double kd = t - kShifter;
    const double r = (y - kd * ln2_hi) - kd * ln2_lo;
    double p = 1.0 / 6227020800.0;  // 1/13!
    p = 1.0 / 479001600.0 + r * p;
    p = 1.0 / 39916800.0 + r * p;
    p = 1.0 / 3628800.0 + r * p;
    p = 1.0 / 362880.0 + r * p;
    p = 1.0 / 40320.0 + r * p;
    p = 1.0 / 5040.0 + r * p;
    p = 1.0 / 720.0 + r * p;
    p = 1.0 / 120.0 + r * p;
    p = 1.0 / 24.0 + r * p;
    p = 1.0 / 6.0 + r * p;
    p = 0.5 + r * p;
    return r + r * (r * p);
}
inline double two_to_k(double t) { return from_bits((bits(t) - bits(kShifter) + 1023) << 52); }

// expm1(y) for 0 <= y <= 700: 2^k expm1(r) + (2^k - 1), which cancels at most a bit.
inline double expm1_nonneg(double y) {
    double t;
    const double em = expm1_reduced(y, t);
    const double two_k = two_to_k(t);
    return two_k * em + (two_k - 1.0);
}

// exp(-y) for 0 <= y <= 700, the same reduction with k <= 0: 2^k (1 + expm1(r)).
inline double exp_neg_nonneg(double y) {
    double t;
    const double e = 1.0 + expm1_reduced(-y, t);
    return two_to_k(t) * e;  // k >= -1010: a normal power of two
}

namespace {

// In blocks: a loop the compiler vectorises (fast, which takes any input and is right inside its
// range), then the library for the rare sample outside it (large, infinite, NaN), its input still at
// hand.
template <class Fast, class Outside, class Library>
inline __attribute__((always_inline)) void in_blocks(double* v, size_t n, Fast fast, Outside outside, Library library) {
    constexpr size_t block = 256;
    double out[block];
    for (size_t i0 = 0; i0 < n; i0 += block) {
        const size_t m = n - i0 < block ? n - i0 : block;
        const double* in = v + i0;
        for (size_t i = 0; i < m; ++i) out[i] = fast(in[i]);
        for (size_t i = 0; i < m; ++i)
            if (outside(in[i])) out[i] = library(in[i]);
        std::memcpy(v + i0, out, m * sizeof(double));
    }
}

template <bool Forward>
inline __attribute__((always_inline)) void signed_log_transform(double* v, size_t n, double factor) {
    constexpr double limit = Forward ? 1e300 : 700.0;
    const auto magnitude = [factor](double x) { return Forward ? std::fabs(x) * factor : std::fabs(x); };
    in_blocks(
        v, n,
        [&](double x) {
            const double a = magnitude(x);
            const double inside = a <= limit ? a : 0.0;
            return std::copysign(Forward ? log1p_nonneg(inside) : factor * expm1_nonneg(inside), x);
        },
        [&](double x) { return !(magnitude(x) <= limit); },
        [&](double x) {
            const double a = magnitude(x);
            return std::copysign(Forward ? std::log1p(a) : factor * std::expm1(a), x);
        });
}

}  // namespace

// Four lanes where the CPU has AVX2, two (SSE2) elsewhere (statfilter/vector_clones.hpp).
SF_VECTOR_CLONES void signed_log1p(double* v, size_t n, double inv) { signed_log_transform<true>(v, n, inv); }
SF_VECTOR_CLONES void signed_expm1(double* v, size_t n, double scale) { signed_log_transform<false>(v, n, scale); }
SF_VECTOR_CLONES void exp_of_negative(double* v, size_t n) {
    const auto inside = [](double a) { return a >= 0.0 && a <= 700.0; };
    in_blocks(
        v, n, [&](double a) { return exp_neg_nonneg(inside(a) ? a : 0.0); },
        [&](double a) { return !inside(a); },  // beyond 700, negative or NaN: the library
        [](double a) { return std::exp(-a); });
}

}  // namespace fast_math
}  // namespace statfilter
