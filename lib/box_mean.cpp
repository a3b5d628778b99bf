#include "statfilter/box_mean.hpp"

#include <vector>

#include "pipeline/parallel.hpp"
#include "statfilter/progress.hpp"

namespace statfilter {
namespace {

// Index i mirrored into [0, n) as BORDER_REFLECT does (again and again for a box wider than n).
int64_t reflect(int64_t i, int64_t n) {
    while (i < 0 || i >= n) i = i < 0 ? -i - 1 : 2 * n - i - 1;
    return i;
}

// Sums in double whatever the plane's type: the same order, the same result on every run.
template <class T>
void box_mean_of(T* plane, int64_t height, int64_t width, int side, int threads) {
    if (side <= 1 || height <= 0 || width <= 0) return;
    const int64_t before = side / 2;
    const Progress none;
    std::vector<double> rows(static_cast<size_t>(height * width));  // each row's horizontal sums
    parallel_for(height, threads, [&](int64_t y) {
        const T* in = plane + y * width;
        double* out = rows.data() + y * width;
        for (int64_t x = 0; x < width; ++x) {
            double sum = 0;
            for (int64_t k = 0; k < side; ++k) sum += static_cast<double>(in[reflect(x - before + k, width)]);
            out[x] = sum;
        }
    }, {none});
    const double scale = 1.0 / (static_cast<double>(side) * static_cast<double>(side));
    parallel_for(height, threads, [&](int64_t y) {
        T* out = plane + y * width;
        for (int64_t x = 0; x < width; ++x) {
            double sum = 0;
            for (int64_t k = 0; k < side; ++k) sum += rows[static_cast<size_t>(reflect(y - before + k, height) * width + x)];
            out[x] = static_cast<T>(sum * scale);
        }
    }, {none});
}

}  // namespace

void box_mean(double* plane, int64_t height, int64_t width, int side, int threads) {
    box_mean_of(plane, height, width, side, threads);
}
void box_mean(float* plane, int64_t height, int64_t width, int side, int threads) {
    box_mean_of(plane, height, width, side, threads);
}

}  // namespace statfilter
