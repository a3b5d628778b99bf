#include "statfilter/time_series_tiles.hpp"

#include <algorithm>
#include <limits>

namespace statfilter {

std::vector<PixelRange> make_pixel_tiles(const Shape& s, int64_t channels_per_pixel, double budget_bytes,
                                         int buffers_per_tile) {
    const double bytes_per_pixel = static_cast<double>(s.frames) * channels_per_pixel * sizeof(double) * buffers_per_tile;
    // At least one image row's worth of pixels or 1024, so tiny budgets still make progress efficiently.
    const auto fit = static_cast<int64_t>(budget_bytes / bytes_per_pixel);
    const int64_t tile = std::max<int64_t>(std::min<int64_t>(fit, s.pixels()), std::min<int64_t>(1024, s.pixels()));
    std::vector<PixelRange> tiles;
    for (int64_t p = 0; p < s.pixels(); p += tile) tiles.push_back({p, std::min(p + tile, s.pixels())});
    return tiles;
}

namespace {

// Visits every sample of the tile with its index j in the F x n buffer, one image row segment at a
// time; where the selected channels of a row segment are contiguous floats it is one tight loop.
template <class Visit>
void walk_tile(const Sequence& seq, PixelRange range, ChannelSelection ch, Visit&& visit) {
    const Shape& s = seq.shape();
    const Strides& st = seq.strides();
    const int64_t n = range.size() * ch.count;
    const bool packed = st.channel == static_cast<int64_t>(sizeof(float)) &&
                        st.pixel == static_cast<int64_t>(sizeof(float)) * ch.count;
    char* base = reinterpret_cast<char*>(const_cast<float*>(seq.data()));
    for (int64_t f = 0; f < s.frames; ++f) {
        int64_t j = f * n;
        for (int64_t p = range.begin; p < range.end;) {
            const int64_t y = p / s.width, x0 = p % s.width, count = std::min(s.width - x0, range.end - p);
            char* row = base + f * st.frame + y * st.row + x0 * st.pixel + ch.first * st.channel;
            if (packed) {
                float* run = reinterpret_cast<float*>(row);
                for (int64_t k = 0; k < count * ch.count; ++k) visit(run + k, j + k);
                j += count * ch.count;
            } else {
                for (int64_t x = 0; x < count; ++x)
                    for (int64_t c = 0; c < ch.count; ++c, ++j)
                        visit(reinterpret_cast<float*>(row + x * st.pixel + c * st.channel), j);
            }
            p += count;
        }
    }
}

}  // namespace

void gather_tile(const Sequence& seq, PixelRange range, ChannelSelection ch, double* tile) {
    walk_tile(seq, range, ch, [tile](float* v, int64_t j) { tile[j] = *v; });
}

void scatter_tile(const double* tile, PixelRange range, ChannelSelection ch, Sequence& seq) {
    // A reconstruction may overshoot an input at the float limit: saturate rather than become Inf.
    constexpr double lim = std::numeric_limits<float>::max();
    walk_tile(seq, range, ch, [tile, lim](float* v, int64_t j) {
        const double x = tile[j];
        *v = static_cast<float>(x > lim ? lim : (x < -lim ? -lim : x));  // NaN passes through
    });
}

}  // namespace statfilter
