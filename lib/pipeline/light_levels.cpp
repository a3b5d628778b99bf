#include "pipeline/light_levels.hpp"

#include <algorithm>
#include <cmath>

#include "pipeline/parallel.hpp"

namespace statfilter {
namespace {

constexpr int64_t kStripRows = 16, kStripEvery = 128;

// Sum and count of the finite samples of frame f over the strips.
void frame_sum(const FrameSource& source, int64_t f, std::vector<float>& buffer, double& sum, double& count) {
    const Shape& s = source.shape();
    const int64_t step = s.height <= 2 * kStripEvery ? s.height : kStripEvery;
    const int64_t rows = s.height <= 2 * kStripEvery ? s.height : kStripRows;
    buffer.resize(static_cast<size_t>(rows * s.width * s.channels));
    for (int64_t y0 = 0; y0 < s.height; y0 += step) {
        const int64_t y1 = std::min(s.height, y0 + rows);
        source.read_rows(f, y0, y1, buffer.data());
        const int64_t n = (y1 - y0) * s.width * s.channels;
        for (int64_t i = 0; i < n; ++i)
            if (std::isfinite(buffer[static_cast<size_t>(i)])) {
                sum += buffer[static_cast<size_t>(i)];
                count += 1;
            }
    }
}

}  // namespace

std::vector<double> smooth_light_levels(const std::vector<double>& raw, int half_width) {
    const auto F = static_cast<int64_t>(raw.size());
    std::vector<double> out(raw.size());
    for (int64_t f = 0; f < F; ++f) {
        const int64_t a = std::max<int64_t>(0, f - half_width), b = std::min<int64_t>(F - 1, f + half_width);
        // Least squares of c0 + c1 t + c2 t^2 (t = g - f) through the window: the value at t = 0 is c0.
        double m[3][4] = {};
        for (int64_t g = a; g <= b; ++g) {
            const double t = static_cast<double>(g - f), basis[3] = {1, t, t * t};
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) m[i][j] += basis[i] * basis[j];
                m[i][3] += basis[i] * raw[static_cast<size_t>(g)];
            }
        }
        // A window of fewer than 3 frames: a lower degree (the mean, or the line).
        const int n = static_cast<int>(std::min<int64_t>(3, b - a + 1));
        for (int col = 0; col < n; ++col) {  // Gauss-Jordan with partial pivoting on the n x n system
            int pivot = col;
            for (int r = col + 1; r < n; ++r)
                if (std::fabs(m[r][col]) > std::fabs(m[pivot][col])) pivot = r;
            std::swap(m[col], m[pivot]);
            for (int r = 0; r < n; ++r) {
                if (r == col || m[col][col] == 0) continue;
                const double k = m[r][col] / m[col][col];
                for (int c = col; c < n; ++c) m[r][c] -= k * m[col][c];
                m[r][3] -= k * m[col][3];
            }
        }
        out[static_cast<size_t>(f)] = m[0][0] != 0 ? m[0][3] / m[0][0] : raw[static_cast<size_t>(f)];
    }
    return out;
}

std::vector<double> measure_light_levels(const FrameSource& source, int threads) {
    const Shape& s = source.shape();
    std::vector<double> ones(static_cast<size_t>(s.frames), 1.0);
    if (s.frames < 2 || s.pixels() <= 0 || s.channels <= 0) return ones;
    std::vector<double> mean(static_cast<size_t>(s.frames), 0.0);
    const Progress none;
    parallel_for(s.frames, threads, [&](int64_t f) {
        std::vector<float> buffer;
        double sum = 0, count = 0;
        frame_sum(source, f, buffer, sum, count);
        mean[static_cast<size_t>(f)] = count > 0 ? sum / count : 0.0;
    }, {none, 0, 1, "light"});
    double total = 0;
    for (double m : mean) {
        if (!(m > 0) || !std::isfinite(m)) return ones;  // a black or broken frame: nothing to divide by
        total += m;
    }
    std::vector<double> raw(mean.size());
    for (size_t f = 0; f < mean.size(); ++f) raw[f] = mean[f] * static_cast<double>(mean.size()) / total;
    std::vector<double> levels = smooth_light_levels(raw, kLightLevelHalfWidth);
    for (double l : levels)
        if (!(l > 0) || !std::isfinite(l)) return ones;
    return levels;
}

void LevelledSource::read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const {
    inner_.read_rows(f, y0, y1, dst);
    const double level = levels_[static_cast<size_t>(f)];
    if (level == 1.0) return;
    const int64_t n = (y1 - y0) * inner_.shape().width * inner_.shape().channels;
    for (int64_t i = 0; i < n; ++i) dst[i] = static_cast<float>(dst[i] / level);
}

void LevelledSource::restore(int64_t f, float* pixels) const {
    const double level = levels_[static_cast<size_t>(f)];
    if (level == 1.0) return;
    const int64_t n = inner_.shape().pixels() * inner_.shape().channels;
    for (int64_t i = 0; i < n; ++i) pixels[i] = static_cast<float>(pixels[i] * level);
}

}  // namespace statfilter
