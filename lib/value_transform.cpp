#include "statfilter/value_transform.hpp"

#include <cmath>

#include "statfilter/error.hpp"

namespace statfilter {

ValueTransform parse_value_transform(const std::string& name) {
    if (name == "none") return ValueTransform::None;
    if (name == "sqrt") return ValueTransform::Sqrt;
    if (name == "log") return ValueTransform::Log;
    throw Error(Status::InvalidArgument, "unknown transform '" + name + "' (none, sqrt, log)");
}

void forward_transform(ValueTransform t, double* v, size_t n) {
    switch (t) {
    case ValueTransform::None: return;
    case ValueTransform::Sqrt:
        for (size_t i = 0; i < n; ++i) v[i] = std::copysign(std::sqrt(std::fabs(v[i])), v[i]);
        return;
    case ValueTransform::Log:
        for (size_t i = 0; i < n; ++i) v[i] = std::copysign(std::log1p(std::fabs(v[i])), v[i]);
        return;
    }
}

void inverse_transform(ValueTransform t, double* v, size_t n) {
    switch (t) {
    case ValueTransform::None: return;
    case ValueTransform::Sqrt:
        for (size_t i = 0; i < n; ++i) v[i] = std::copysign(v[i] * v[i], v[i]);
        return;
    case ValueTransform::Log:
        for (size_t i = 0; i < n; ++i) v[i] = std::copysign(std::expm1(std::fabs(v[i])), v[i]);
        return;
    }
}

}  // namespace statfilter
