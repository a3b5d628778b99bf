// The median and the median absolute deviation of many short series at once (the firefly search:
// two per sample of the shot). Exactly the order statistics of a sort, so any method gives the same
// values; the one used sorts a few series side by side through a fixed sorting network, which has
// no data-dependent branch to mispredict.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

namespace statfilter {

// The median of v (the mean of the two middle values for an even count); v is reordered.
double median_of(std::vector<double>& v);

// v's median and its median absolute deviation from it, as median_of gives them; v is reordered.
std::pair<double, double> median_and_deviation(std::vector<double>& v);

// For series j < count with samples values[f * stride + j], f < frames: median[j] and
// deviation_scale x its median absolute deviation, both rounded to float. A series with a
// non-finite sample gets what median_and_deviation gives it.
void medians_and_deviations(const double* values, int64_t stride, int64_t frames, int64_t count, double deviation_scale,
                            float* median, float* deviation);

// A sorting network for n values (Knuth's merge exchange, Batcher's method, for any n): comparing
// and exchanging values[first] and values[second] in this order sorts them.
struct Comparator {
    int32_t first, second;
};
std::vector<Comparator> sorting_network(int64_t n);

}  // namespace statfilter
