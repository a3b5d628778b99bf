#include "statfilter/temporal_outliers.hpp"

#include <algorithm>
#include <cmath>

#include "pipeline/parallel.hpp"
#include "statfilter/nonfinite.hpp"

namespace statfilter {

namespace {

double median_of(std::vector<double>& v) {
    const size_t n = v.size(), mid = n / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    double m = v[mid];
    if (n % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
    return m;
}

}  // namespace

std::vector<TemporalOutlier> find_temporal_outliers(const Sequence& seq, ChannelSelection group,
                                                    const OutlierOptions& o) {
    std::vector<TemporalOutlier> found;
    const Shape& s = seq.shape();
    const int64_t F = s.frames, C = group.count, P = s.pixels(), N = P * C;
    if (!(o.z > 0) || F < 3 || N == 0) return found;
    // Each series' temporal median and robust deviation, transformed, tile by tile (tiles in parallel).
    std::vector<float> median(static_cast<size_t>(N)), deviation(static_cast<size_t>(N));
    const std::vector<PixelRange> tiles = make_pixel_tiles(s, C, o.budget_bytes / resolve_threads(0), 1);
    parallel_for(static_cast<int64_t>(tiles.size()), resolve_threads(0), [&](int64_t t) {
        const PixelRange range = tiles[static_cast<size_t>(t)];
        const int64_t n = range.size() * C;
        std::vector<double> tile(static_cast<size_t>(F * n)), series(static_cast<size_t>(F));
        gather_tile(seq, range, group, tile.data());
        if (o.repair_nonfinite) repair_nonfinite(tile.data(), F, n);
        forward_transform(o.transform, o.scale, tile.data(), tile.size());
        for (int64_t j = 0; j < n; ++j) {
            for (int64_t f = 0; f < F; ++f) series[f] = tile[f * n + j];
            const double m = median_of(series);
            for (double& v : series) v = std::fabs(v - m);
            const int64_t g = range.begin * C + j;
            median[g] = static_cast<float>(m);
            deviation[g] = static_cast<float>(1.4826 * median_of(series));
        }
    }, {Progress(), 0, 1, "fireflies"});
    std::vector<double> positive;
    for (float d : deviation)
        if (d > 0 && std::isfinite(d)) positive.push_back(d);
    const double floor = positive.empty() ? 0.0 : median_of(positive);
    if (!(floor > 0)) return found;  // (nearly) every series constant: nothing to measure against
    // Frame by frame (frames in parallel): each pixel's largest deviation over the group's channels,
    // then isolation.
    std::vector<std::vector<TemporalOutlier>> per_frame(static_cast<size_t>(F));
    const double half = 0.5 * o.z;
    parallel_for(F, resolve_threads(0), [&](int64_t f) {
        std::vector<float> frame(static_cast<size_t>(P * s.channels)), score(static_cast<size_t>(P));
        std::vector<double> transformed(static_cast<size_t>(N));
        std::vector<TemporalOutlier>& out = per_frame[static_cast<size_t>(f)];
        seq.get_frame(f, frame.data());
        // The group's samples transformed in one call (a loop that vectorises), then judged.
        for (int64_t p = 0; p < P; ++p)
            for (int64_t c = 0; c < C; ++c)
                transformed[static_cast<size_t>(p * C + c)] = frame[static_cast<size_t>(p * s.channels + group.first + c)];
        forward_transform(o.transform, o.scale, transformed.data(), transformed.size());
        const auto z_of = [&](int64_t g) {
            return (std::fabs(transformed[static_cast<size_t>(g)]) - std::fabs(median[g])) / std::max<double>(deviation[g], floor);
        };
        for (int64_t p = 0; p < P; ++p) {
            float worst = 0;
            for (int64_t c = 0; c < C; ++c) {
                if (!std::isfinite(frame[static_cast<size_t>(p * s.channels + group.first + c)])) continue;
                worst = std::max(worst, static_cast<float>(z_of(p * C + c)));
            }
            score[p] = worst;
        }
        for (int64_t p = 0; p < P; ++p) {
            if (!(score[p] > o.z)) continue;
            const int64_t y = p / s.width, x = p % s.width;
            int neighbours = 0;
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dx = -1; dx <= 1; ++dx) {
                    const int64_t yy = y + dy, xx = x + dx;
                    if ((dy || dx) && yy >= 0 && yy < s.height && xx >= 0 && xx < s.width && score[yy * s.width + xx] > half)
                        ++neighbours;
                }
            if (neighbours > 1) continue;  // part of something that moves or changes: real
            for (int64_t c = 0; c < C; ++c) {
                const int64_t g = p * C + c;
                if (!std::isfinite(frame[static_cast<size_t>(p * s.channels + group.first + c)])) continue;
                if (!(z_of(g) > o.z)) continue;
                double back = median[g];
                inverse_transform(o.transform, o.scale, &back, 1);
                out.push_back({f, g, back});
            }
        }
    }, {Progress(), 0, 1, "fireflies"});
    for (const auto& frame_found : per_frame) found.insert(found.end(), frame_found.begin(), frame_found.end());
    std::sort(found.begin(), found.end(), [](const TemporalOutlier& a, const TemporalOutlier& b) {
        return a.series != b.series ? a.series < b.series : a.frame < b.frame;
    });
    return found;
}

void replace_temporal_outliers(Sequence& seq, ChannelSelection group, const std::vector<TemporalOutlier>& outliers) {
    const Shape& s = seq.shape();
    for (const TemporalOutlier& o : outliers) {
        const int64_t p = o.series / group.count, c = group.first + o.series % group.count;
        seq.at(o.frame, p / s.width, p % s.width, c) = static_cast<float>(o.value);
    }
}

}  // namespace statfilter
