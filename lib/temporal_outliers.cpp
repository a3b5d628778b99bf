#include "statfilter/temporal_outliers.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "pipeline/parallel.hpp"
#include "statfilter/nonfinite.hpp"
#include "statfilter/robust_series.hpp"
#include "statfilter/vector_clones.hpp"

namespace statfilter {

namespace {

constexpr double kTileBytes = 64.0 * 1024 * 1024;  // a worker's firefly-search tile, at most

// Visits a pixel's neighbours among the 8 around p inside the frame (3 at a corner).
template <class Visit>
void for_each_neighbour(int64_t p, int64_t width, int64_t height, Visit&& visit) {
    const int64_t y = p / width, x = p % width;
    const bool up = y > 0, down = y + 1 < height, left = x > 0, right = x + 1 < width;
    if (up) {
        if (left) visit(p - width - 1);
        visit(p - width);
        if (right) visit(p - width + 1);
    }
    if (left) visit(p - 1);
    if (right) visit(p + 1);
    if (down) {
        if (left) visit(p + width - 1);
        visit(p + width);
        if (right) visit(p + width + 1);
    }
}

// The second largest of a sample's finite neighbours: `at(q)` is pixel q's value of that sample's
// channel; the only one when there is one, the sample's own value with none (a one-pixel frame).
template <class At>
double second_brightest_neighbour(int64_t p, int64_t width, int64_t height, At&& at) {
    double first = -HUGE_VAL, second = -HUGE_VAL;
    int n = 0;
    for_each_neighbour(p, width, height, [&](int64_t q) {
        const double a = at(q);
        if (!std::isfinite(a)) return;
        ++n;
        if (a > first) second = first, first = a;
        else if (a > second) second = a;
    });
    return n == 0 ? at(p) : n == 1 ? first : second;
}

// Samples [i0, i1) of u (pixel * C + channel) inside the frame, less the second largest of their 8
// neighbours at u[i + offsets[k]], as std::max and std::min take it; NaN where a neighbour is not
// finite (redone one at a time by the caller). Four samples at a time, without a branch.
SF_VECTOR_CLONES void interior_residuals(const double* u, int64_t i0, int64_t i1, const int64_t* offsets, double* out) {
    const Lanes lowest = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    const Lanes nan = lowest - lowest + std::numeric_limits<double>::quiet_NaN();
    int64_t i = i0;
    for (; i + 4 <= i1; i += 4) {
        Lanes first_v = lowest, second_v = lowest;
        LaneMask finite = {-1, -1, -1, -1};
        for (int k = 0; k < 8; ++k) {
            Lanes a;
            std::memcpy(&a, u + i + offsets[k], sizeof a);
            finite &= (a - a) == 0;  // false for Inf and NaN
            const Lanes lower = a < first_v ? a : first_v;     // std::min(first_v, a)
            second_v = second_v < lower ? lower : second_v;    // std::max(second_v, lower)
            first_v = first_v < a ? a : first_v;               // std::max(first_v, a)
        }
        Lanes r;
        std::memcpy(&r, u + i, sizeof r);
        r = finite ? r - second_v : nan;
        std::memcpy(out + (i - i0), &r, sizeof r);
    }
    for (; i < i1; ++i) {
        double first_v = -HUGE_VAL, second_v = -HUGE_VAL;
        bool finite = true;
        for (int k = 0; k < 8; ++k) {
            const double a = u[i + offsets[k]];
            finite = finite && std::isfinite(a);
            second_v = std::max(second_v, std::min(first_v, a));
            first_v = std::max(first_v, a);
        }
        out[i - i0] = finite ? u[i] - second_v : std::numeric_limits<double>::quiet_NaN();
    }
}

// out[(p - first) * C + c] = u's sample c of pixel p less the second brightest of its neighbours, for
// pixels [first, first + count) of a frame; u holds pixels [u_first, ...) of that frame, C samples a
// pixel, including the rows around the range. A row's interior pixels go through
// interior_residuals; the frame's border and the samples next to a non-finite one, one at a time.
void residuals_above_neighbours(const double* u, int64_t u_first, int64_t first, int64_t count, int64_t width,
                                int64_t height, int64_t C, double* out) {
    const int64_t offsets[8] = {(-width - 1) * C, -width * C, (-width + 1) * C, -C, C, (width - 1) * C, width * C,
                                (width + 1) * C};
    const auto one = [&](int64_t p, int64_t c) {
        const auto sample_of = [&](int64_t q) { return u[(q - u_first) * C + c]; };
        out[(p - first) * C + c] = sample_of(p) - second_brightest_neighbour(p, width, height, sample_of);
    };
    const int64_t end = first + count;
    for (int64_t p = first; p < end;) {
        const int64_t y = p / width, row = y * width, row_end = std::min(end, row + width);
        const bool inside = y > 0 && y + 1 < height;
        // The row's pixels [p, row_end): interior ones [lo, hi), x in [1, width - 1).
        const int64_t lo = inside ? std::min(row_end, std::max(p, row + 1)) : row_end;
        const int64_t hi = inside ? std::max(lo, std::min(row_end, row + width - 1)) : row_end;
        for (int64_t q = p; q < lo; ++q)
            for (int64_t c = 0; c < C; ++c) one(q, c);
        if (hi > lo) {
            double* at = out + (lo - first) * C;
            interior_residuals(u, (lo - u_first) * C, (hi - u_first) * C, offsets, at);
            for (int64_t i = 0; i < (hi - lo) * C; ++i)
                if (!std::isfinite(at[i])) one(lo + i / C, i % C);
        }
        for (int64_t q = hi; q < row_end; ++q)
            for (int64_t c = 0; c < C; ++c) one(q, c);
        p = row_end;
    }
}

// The median of a sample's finite neighbours (as above, the sample's own value with none).
template <class At>
double neighbour_median(int64_t p, int64_t width, int64_t height, At&& at) {
    double v[8];
    int n = 0;
    for_each_neighbour(p, width, height, [&](int64_t q) {
        const double a = at(q);
        if (std::isfinite(a)) v[n++] = a;
    });
    if (n == 0) return at(p);
    std::nth_element(v, v + n / 2, v + n);
    double m = v[n / 2];
    if (n % 2 == 0) m = 0.5 * (m + *std::max_element(v, v + n / 2));
    return m;
}

// The floor of a set of robust deviations: their median over the series that vary.
double deviation_floor(const std::vector<float>& deviation) {
    std::vector<double> positive;
    positive.reserve(deviation.size());
    for (float d : deviation)
        if (d > 0 && std::isfinite(d)) positive.push_back(d);
    return positive.empty() ? 0.0 : median_of(positive);
}

}  // namespace

std::vector<TemporalOutlier> find_temporal_outliers(const Sequence& seq, ChannelSelection group,
                                                    const OutlierOptions& o) {
    std::vector<TemporalOutlier> found;
    const Shape& s = seq.shape();
    const int64_t F = s.frames, C = group.count, P = s.pixels(), N = P * C;
    if (!(o.z > 0) || F < 3 || N == 0) return found;
    // Each series' temporal median and robust deviation, transformed, tile by tile (tiles in parallel);
    // the same of its residual above its neighbours (the sample less the second brightest of its 8
    // neighbours: a lone spike stands out of it, the corner of a small bright object does not), so
    // the tile is read with a row and a pixel on each side.
    std::vector<float> median(static_cast<size_t>(N)), deviation(median.size());
    std::vector<float> residual_median(median.size()), residual_deviation(median.size());
    // A tile's buffers: its samples with the rows around it, and its residuals; the rows around it
    // come out of the budget first, so a tile of a wide frame stays within it.
    // A worker's share is capped (kTileBytes): every series is judged on its own, so the tile size
    // changes no result, and tiles of hundreds of MiB each cost more in first-touch page faults and
    // cache misses than the two halo rows that smaller tiles read again.
    const double halo_bytes = static_cast<double>(2 * s.width + 2) * static_cast<double>(F * C) * sizeof(double);
    // (Never below 8 halos: a long, wide shot's halo rows alone can near the cap.)
    const double share = std::min(o.budget_bytes / resolve_threads(0), std::max(kTileBytes, 8 * halo_bytes));
    const std::vector<PixelRange> tiles = make_pixel_tiles(s, C, std::max(0.0, share - halo_bytes), 2);
    // A worker's tile buffers are made once: the tiles are the same size but the last.
    struct TileBuffers {
        std::vector<double> tile, residuals;
    };
    const auto tile_count = static_cast<int64_t>(tiles.size());
    std::vector<TileBuffers> buffers(static_cast<size_t>(worker_count(tile_count, resolve_threads(0))));
    parallel_for_workers(tile_count, resolve_threads(0), [&](int64_t t, int worker) {
        const PixelRange range = tiles[static_cast<size_t>(t)];
        const PixelRange wide{std::max<int64_t>(0, range.begin - s.width - 1), std::min(P, range.end + s.width + 1)};
        const int64_t n = range.size() * C, wn = wide.size() * C, skip = (range.begin - wide.begin) * C;
        std::vector<double>& tile = buffers[static_cast<size_t>(worker)].tile;
        std::vector<double>& residuals = buffers[static_cast<size_t>(worker)].residuals;
        tile.resize(static_cast<size_t>(F * wn));
        residuals.resize(static_cast<size_t>(F * n));
        gather_tile(seq, wide, group, tile.data());
        if (o.repair_nonfinite) repair_nonfinite(tile.data(), F, wn);
        forward_transform(o.transform, o.scale, tile.data(), tile.size());
        for (int64_t f = 0; f < F; ++f)
            residuals_above_neighbours(tile.data() + f * wn, wide.begin, range.begin, range.size(), s.width, s.height, C,
                                       residuals.data() + f * n);
        const int64_t g = range.begin * C;
        medians_and_deviations(tile.data() + skip, wn, F, n, 1.4826, median.data() + g, deviation.data() + g);
        medians_and_deviations(residuals.data(), n, F, n, 1.4826, residual_median.data() + g, residual_deviation.data() + g);
    }, {Progress(), 0, 1, "fireflies"});
    const double floor = deviation_floor(deviation), residual_floor = deviation_floor(residual_deviation);
    if (!(floor > 0)) return found;  // (nearly) every series constant: nothing to measure against
    // Frame by frame (frames in parallel): each pixel's largest deviation over the group's channels,
    // then isolation.
    std::vector<std::vector<TemporalOutlier>> per_frame(static_cast<size_t>(F));
    const double half = 0.5 * o.z;
    // Each worker takes every workers-th frame with buffers of its own, made once (frame-sized buffers
    // made fresh for every frame cost more in page faults than the judging).
    const int64_t workers = std::min<int64_t>(resolve_threads(0), F);
    parallel_for(workers, static_cast<int>(workers), [&](int64_t worker) {
        std::vector<float> frame(static_cast<size_t>(P * s.channels));
        std::vector<float> score(static_cast<size_t>(P)), residual_score(score.size());
        std::vector<double> transformed(static_cast<size_t>(N)), residual_z(transformed.size());
        for (int64_t f = worker; f < F; f += workers) {
            std::vector<TemporalOutlier>& out = per_frame[static_cast<size_t>(f)];
            seq.get_frame(f, frame.data());
            // The group's samples transformed in one call (a loop that vectorises), then judged.
            for (int64_t p = 0; p < P; ++p)
                for (int64_t c = 0; c < C; ++c)
                    transformed[static_cast<size_t>(p * C + c)] = frame[static_cast<size_t>(p * s.channels + group.first + c)];
            forward_transform(o.transform, o.scale, transformed.data(), transformed.size());
            // Each sample's score: how far above its series it is, as a value or as a residual above its neighbours.
            // The residuals stay put where the image moves under the pixels (a camera pan makes a spike's
            // neighbours outliers in time too, and its series' median another surface's level); still-scene
            // fireflies score on both.
            // residual_z holds the residuals, then (in place) their scores, rounded to float.
            residuals_above_neighbours(transformed.data(), 0, 0, P, s.width, s.height, C, residual_z.data());
            for (int64_t g = 0; g < N; ++g)
                residual_z[g] = residual_floor > 0 ? static_cast<float>((residual_z[g] - residual_median[g]) /
                                                                        std::max<double>(residual_deviation[g], residual_floor))
                                                   : 0.0f;
            const auto value_z = [&](int64_t g) {
                return (std::fabs(transformed[static_cast<size_t>(g)]) - std::fabs(median[g])) /
                       std::max<double>(deviation[g], floor);
            };
            // Each rule on its own: a pixel's largest score over the group's channels, then isolation among
            // the scores of the same rule (under a pan every value scores high, the residuals do not).
            const auto isolated_above = [&](const std::vector<float>& score, int64_t p) {
                if (!(score[p] > o.z)) return false;
                int neighbours = 0;
                for_each_neighbour(p, s.width, s.height, [&](int64_t q) { neighbours += score[q] > half; });
                return neighbours <= 1;  // else part of something that moves or changes: real
            };
            const auto finite = [&](int64_t p, int64_t c) {
                return std::isfinite(frame[static_cast<size_t>(p * s.channels + group.first + c)]);
            };
            for (int64_t p = 0; p < P; ++p) {
                float worst = 0, worst_residual = 0;
                for (int64_t c = 0; c < C; ++c) {
                    if (!finite(p, c)) continue;
                    worst = std::max(worst, static_cast<float>(value_z(p * C + c)));
                    worst_residual = std::max(worst_residual, static_cast<float>(residual_z[static_cast<size_t>(p * C + c)]));
                }
                score[p] = worst;
                residual_score[p] = worst_residual;
            }
            for (int64_t p = 0; p < P; ++p) {
                const bool by_value = isolated_above(score, p), by_residual = isolated_above(residual_score, p);
                if (!by_value && !by_residual) continue;
                for (int64_t c = 0; c < C; ++c) {
                    const int64_t g = p * C + c;
                    if (!finite(p, c)) continue;
                    // Above its own series: its series' median. Only above its neighbours (the image moves
                    // under it): its neighbours' median in this frame.
                    double back = median[g];
                    if (by_value && value_z(g) > o.z) {
                        inverse_transform(o.transform, o.scale, &back, 1);
                    } else if (by_residual && residual_z[static_cast<size_t>(g)] > o.z) {
                        const float* px = frame.data() + group.first + c;
                        back = neighbour_median(p, s.width, s.height,
                                                [&](int64_t q) { return static_cast<double>(px[q * s.channels]); });
                    } else {
                        continue;
                    }
                    out.push_back({f, g, back});
                }
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
