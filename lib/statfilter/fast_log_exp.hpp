// log1p, expm1 and exp(-x) of non-negative doubles without a library call per sample, so that loops over a
// frame or a tile vectorise: the transforms run on every sample of every pass, and glibc's log1p,
// expm1 and exp (diffusion's conductances) were the largest items of a profile. Within 4 ulp of the
// library on [0, 1e300] (log1p) and [0, 700] (expm1, exp(-x)); outside those ranges, and for NaN,
// the library itself (tested in tests/filters/test_value_transform.cpp against std::log1p,
// std::expm1 and std::exp).
#pragma once
#include <cstddef>

namespace statfilter {
namespace fast_math {

// v[i] = copysign(log1p(|v[i]| * inv), v[i]), and v[i] = scale * copysign(expm1(|v[i]|), v[i]): the
// log transform's two directions (value_transform.hpp).
void signed_log1p(double* v, size_t n, double inv);
void signed_expm1(double* v, size_t n, double scale);
// v[i] = exp(-v[i]) (within 4 ulp for 0 <= v[i] <= 700; the library elsewhere): conductances.
void exp_of_negative(double* v, size_t n);

}  // namespace fast_math
}  // namespace statfilter
