#include "pipeline/light_levels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pipeline/parallel.hpp"
#include "statfilter/sequence_io.hpp"

namespace statfilter {
namespace {

constexpr int64_t kStripRows = 16, kEveryRowUpTo = 256;
constexpr int kBlocksASide = 8, kBlocks = kBlocksASide * kBlocksASide;

// The mean of the finite samples of the light channels in each of the frame's blocks (NaN where a
// block has none). Every row of a frame up to kEveryRowUpTo rows high; above, a strip of kStripRows
// rows centred in each row of blocks (so every block is read, whatever the height).
std::vector<double> block_means(const FrameSource& source, const std::vector<uint8_t>& light, int64_t f,
                                std::vector<float>& buffer) {
    const Shape& s = source.shape();
    std::vector<double> sum(kBlocks, 0.0), count(kBlocks, 0.0);
    const auto add_rows = [&](int64_t y0, int64_t y1) {
        buffer.resize(static_cast<size_t>((y1 - y0) * s.width * s.channels));
        source.read_rows(f, y0, y1, buffer.data());
        for (int64_t y = y0; y < y1; ++y) {
            const int64_t by = y * kBlocksASide / s.height;
            const float* row = buffer.data() + (y - y0) * s.width * s.channels;
            for (int64_t x = 0; x < s.width; ++x) {
                const auto b = static_cast<size_t>(by * kBlocksASide + x * kBlocksASide / s.width);
                for (int64_t c = 0; c < s.channels; ++c) {
                    const float v = row[x * s.channels + c];
                    if (!light[static_cast<size_t>(c)] || !std::isfinite(v)) continue;
                    sum[b] += v;
                    count[b] += 1;
                }
            }
        }
    };
    if (s.height <= kEveryRowUpTo) {
        add_rows(0, s.height);
    } else {
        for (int64_t by = 0; by < kBlocksASide; ++by) {
            // Rows [first, end) are block row by's (y * 8 / height == by).
            const int64_t first = (by * s.height + kBlocksASide - 1) / kBlocksASide;
            const int64_t end = ((by + 1) * s.height + kBlocksASide - 1) / kBlocksASide;
            const int64_t y0 = std::max(first, (first + end - kStripRows) / 2);
            add_rows(y0, std::min(end, y0 + kStripRows));
        }
    }
    for (size_t b = 0; b < sum.size(); ++b) sum[b] = count[b] > 0 ? sum[b] / count[b] : std::nan("");
    return sum;
}

double median(std::vector<double> v) {
    const size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    if (v.size() % 2) return v[mid];
    return 0.5 * (v[mid] + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
}

// Least squares of c0 + c1 t + c2 t^2 (t = g - f) through raw over frames f - h .. f + h, leaving
// out frame `skip` (-1: none): the value at t = 0 is c0. Fewer than 3 frames: the line, or the mean.
double local_quadratic_at(const std::vector<double>& raw, int64_t f, int half_width, int64_t skip) {
    const auto F = static_cast<int64_t>(raw.size());
    const int64_t a = std::max<int64_t>(0, f - half_width), b = std::min<int64_t>(F - 1, f + half_width);
    double m[3][4] = {};
    int64_t count = 0;
    for (int64_t g = a; g <= b; ++g) {
        if (g == skip) continue;
        const double t = static_cast<double>(g - f), basis[3] = {1, t, t * t};
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) m[i][j] += basis[i] * basis[j];
            m[i][3] += basis[i] * raw[static_cast<size_t>(g)];
        }
        ++count;
    }
    const int n = static_cast<int>(std::min<int64_t>(3, count));
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
    return n > 0 && m[0][0] != 0 ? m[0][3] / m[0][0] : raw[static_cast<size_t>(f)];
}

// Each raw level's distance from the fit over +-half_width frames of the others (leave-one-out).
std::vector<double> left_out_residuals(const std::vector<double>& raw, int half_width) {
    std::vector<double> out(raw.size());
    for (size_t f = 0; f < raw.size(); ++f) {
        const auto t = static_cast<int64_t>(f);
        out[f] = raw[f] - local_quadratic_at(raw, t, half_width, t);
    }
    return out;
}

}  // namespace

std::vector<double> smooth_light_levels(const std::vector<double>& raw, int half_width) {
    std::vector<double> out(raw.size());
    for (size_t f = 0; f < raw.size(); ++f) out[f] = local_quadratic_at(raw, static_cast<int64_t>(f), half_width, -1);
    return out;
}

int choose_light_half_width(const std::vector<double>& raw) {
    int best = kLightLevelHalfWidth;
    double best_error = std::numeric_limits<double>::infinity();
    for (const int h : kLightLevelHalfWidths) {
        double error = 0;
        for (double d : left_out_residuals(raw, h)) error += d * d;
        if (error < best_error) best = h, best_error = error;
    }
    return best;
}

std::vector<uint8_t> light_channels(const std::vector<std::string>& names, int64_t channels) {
    std::vector<uint8_t> light(static_cast<size_t>(std::max<int64_t>(0, channels)), 1);
    if (static_cast<int64_t>(names.size()) != channels) return light;
    bool any = false;
    for (size_t c = 0; c < light.size(); ++c) any = (light[c] = is_light_channel(names[c]) ? 1 : 0) || any;
    if (!any) std::fill(light.begin(), light.end(), uint8_t{1});  // no light pass named: every channel
    return light;
}

LightLevels measure_light_levels(const FrameSource& source, int threads) {
    const Shape& s = source.shape();
    LightLevels still;
    still.levels.assign(static_cast<size_t>(std::max<int64_t>(0, s.frames)), 1.0);
    still.channels = light_channels(source.attributes().channel_names(), s.channels);
    if (s.frames < kLeastLightFrames || s.pixels() <= 0 || s.channels <= 0) return still;
    std::vector<std::vector<double>> means(static_cast<size_t>(s.frames));
    const Progress none;
    parallel_for(s.frames, threads, [&](int64_t f) {
        std::vector<float> buffer;
        means[static_cast<size_t>(f)] = block_means(source, still.channels, f, buffer);
    }, {none, 0, 1, "light"});
    // Each block's typical level over the shot: the median of its frames' means, not their mean. A
    // firefly of 500 in a 20 x 15 block of 32 frames raised that block's mean over the shot by 13%, so
    // its ratio fell in every frame, the median block of every frame changed, and five fireflies on
    // cornell_light changed the light's smoothing from +-6 to +-4 frames: every pixel of the shot
    // moved by up to 0.9% of the reference. A block black or broken in any frame says nothing of the
    // light.
    std::vector<double> shot(kBlocks, 0.0), column(means.size());
    std::vector<size_t> usable;
    for (size_t b = 0; b < shot.size(); ++b) {
        bool finite = true;
        for (size_t f = 0; f < means.size(); ++f) {
            finite = finite && std::isfinite(means[f][b]);
            column[f] = means[f][b];
        }
        if (!finite) continue;
        shot[b] = median(column);
        if (shot[b] > 0) usable.push_back(b);
    }
    if (usable.empty()) return still;
    std::vector<double> raw(static_cast<size_t>(s.frames)), ratios(usable.size());
    double total = 0;
    for (size_t f = 0; f < raw.size(); ++f) {
        for (size_t i = 0; i < usable.size(); ++i) ratios[i] = means[f][usable[i]] / shot[usable[i]];
        raw[f] = median(ratios);
        if (!(raw[f] > 0)) return still;  // a black frame: nothing to divide by
        total += raw[f];
    }
    if (!(total > 0) || !std::isfinite(total)) return still;
    for (double& r : raw) r *= static_cast<double>(raw.size()) / total;
    // Whether the light changes: the swing of the levels smoothed over kLightLevelHalfWidth frames
    // (wide: noise must not pass for a light), against the raw levels' spread about them.
    // The spread is each raw level's distance from the fit of the frames around it without it
    // (leave-one-out): a fit through the frame itself passes through every level of a short shot,
    // and its spread of 0 let noise pass for a light.
    LightLevels out = still;
    out.levels = smooth_light_levels(raw, kLightLevelHalfWidth);
    for (double l : out.levels) {
        if (!(l > 0) || !std::isfinite(l)) return still;
        out.swing = std::max(out.swing, std::fabs(l - 1));
    }
    std::vector<double> off = left_out_residuals(raw, kLightLevelHalfWidth);
    for (double& d : off) d = std::fabs(d);
    out.noise = 1.4826 * median(off);
    out.modelled = out.swing > std::max(kLeastLightSwing, 3 * out.noise);
    if (!out.modelled) {
        out.levels = still.levels;
        return out;
    }
    // How the changing light is followed: the half-width that predicts each frame's raw level best
    // from the frames around it (leave-one-out). A light that swings fast needs a narrow window (a
    // quadratic over +-8 frames misses cornell_light's period of 32 frames by 0.5%); a noisy level, a
    // wide one.
    out.half_width = choose_light_half_width(raw);
    out.levels = smooth_light_levels(raw, out.half_width);
    for (double l : out.levels)
        if (!(l > 0) || !std::isfinite(l)) return still;
    return out;
}

void LevelledSource::read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const {
    inner_.read_rows(f, y0, y1, dst);
    const double level = levels_[static_cast<size_t>(f)];
    if (level == 1.0) return;
    const int64_t C = inner_.shape().channels, n = (y1 - y0) * inner_.shape().width * C;
    for (int64_t i = 0; i < n; ++i)
        if (light_[static_cast<size_t>(i % C)]) dst[i] = static_cast<float>(dst[i] / level);
}

void LevelledSource::restore(int64_t f, float* pixels) const {
    const double level = levels_[static_cast<size_t>(f)];
    if (level == 1.0) return;
    const int64_t C = inner_.shape().channels, n = inner_.shape().pixels() * C;
    for (int64_t i = 0; i < n; ++i)
        if (light_[static_cast<size_t>(i % C)]) pixels[i] = static_cast<float>(pixels[i] * level);
}

}  // namespace statfilter
