// Variance-stabilising transforms applied to each time series before temporal PCA and undone after.
// Render noise grows with brightness; sqrt (Anscombe-like) and log1p compress bright pixels so the
// shared basis is not led by them. Signed versions keep negative inputs valid and invertible.
#pragma once
#include <cstddef>
#include <string>

namespace statfilter {

enum class ValueTransform { None, Sqrt, Log };

ValueTransform parse_value_transform(const std::string& name);
void forward_transform(ValueTransform t, double* values, size_t count);
void inverse_transform(ValueTransform t, double* values, size_t count);

}  // namespace statfilter
