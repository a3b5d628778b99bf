#include "statfilter/time_trust.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "statfilter/error.hpp"

namespace statfilter {
namespace {

// A +-1 pattern fixed by frame and sample: the probe is the same for any thread count or tiling.
float random_sign(int64_t frame, int64_t sample) {
    uint64_t z = static_cast<uint64_t>(frame) * 0x9E3779B97F4A7C15ull + static_cast<uint64_t>(sample) + 0x632BE59BD9B4E019ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (z & 1) ? 1.0f : -1.0f;
}

// Sample i of frame f as the probe sees it: x + eps b, held non-negative where x is (renders are
// non-negative: so is what the prefilter sees).
float probe_sample(float x, double eps, int64_t frame, int64_t sample) {
    const float v = x + static_cast<float>(eps) * random_sign(frame, sample);
    return x >= 0 && v < 0 ? 0.0f : v;
}

// Position of pixel coordinate i among tile centres: index of the tile before it and the weight of
// the next one (clamped at the borders).
void between_centres(int64_t i, int64_t tile, int64_t tiles, int64_t& first, double& t) {
    const double pos = std::clamp((static_cast<double>(i) + 0.5) / static_cast<double>(tile) - 0.5, 0.0,
                                  static_cast<double>(tiles - 1));
    first = std::min(static_cast<int64_t>(pos), tiles - 1);
    t = pos - static_cast<double>(first);
}

// Every sample of a frame in memory order, with the tile it lies in: visit(tile, sample).
template <class Visit>
void each_sample_by_tile(const Shape& shape, int64_t tile, int64_t tiles_x, Visit&& visit) {
    const int64_t W = shape.width, H = shape.height, C = shape.channels;
    for (int64_t py = 0; py < H; ++py)
        for (int64_t px = 0; px < W; ++px) {
            const auto t = static_cast<size_t>((py / tile) * tiles_x + px / tile);
            for (int64_t c = 0; c < C; ++c) visit(t, (py * W + px) * C + c);
        }
}

}  // namespace

TimeTrust::TimeTrust(const Shape& shape, const TimeTrustOptions& options)
    : shape_(shape), options_(options), tiles_x_((shape.width + options.tile - 1) / options.tile),
      tiles_y_((shape.height + options.tile - 1) / options.tile),
      stein_(static_cast<size_t>(shape.frames)), sigma2_(static_cast<size_t>(shape.frames)),
      num_(static_cast<size_t>(shape.frames)), den_(static_cast<size_t>(shape.frames)),
      limit_(static_cast<size_t>(shape.frames)), eps_(static_cast<size_t>(shape.frames)) {}

void TimeTrust::probe(int64_t f, const float* x, const float* y, const std::function<void(float*)>& prefilter) {
    const int64_t samples = shape_.width * shape_.height * shape_.channels;
    const size_t tiles = static_cast<size_t>(tiles_x_ * tiles_y_);
    // Each tile's witnesses: residuals within outlier_z times the tile's RMS residual (a firefly's is
    // not one). The RMS, not a median: renders' noise is heavy-tailed, and its tail is evidence.
    std::vector<double> limit(tiles, std::numeric_limits<double>::infinity());
    if (options_.outlier_z > 0) {
        std::vector<double> squares(tiles, 0.0), n(tiles, 0.0);
        each_sample_by_tile(shape_, options_.tile, tiles_x_, [&](size_t t, int64_t i) {
            const double r = static_cast<double>(x[i]) - y[i];
            if (std::isfinite(r)) {
                squares[t] += r * r;
                n[t] += 1;
            }
        });
        for (size_t t = 0; t < tiles; ++t)
            if (squares[t] > 0) limit[t] = options_.outlier_z * std::sqrt(squares[t] / n[t]);
    }
    // Each tile's noise variance sigma^2, from the prefilter's residual x - y (the truth is near y).
    std::vector<double> sigma2(tiles, 0.0), count(tiles, 0.0);
    each_sample_by_tile(shape_, options_.tile, tiles_x_, [&](size_t t, int64_t i) {
        const double r = static_cast<double>(x[i]) - y[i];
        if (std::isfinite(r) && std::fabs(r) <= limit[t]) {
            sigma2[t] += r * r;
            count[t] += 1;
        }
    });
    for (size_t t = 0; t < sigma2.size(); ++t) sigma2[t] = count[t] > 0 ? sigma2[t] / count[t] : 0.0;
    // The probe: x + eps b, eps a share of the tile's noise (scales with the data), b a sign.
    std::vector<double> eps(sigma2.size());
    for (size_t t = 0; t < sigma2.size(); ++t) eps[t] = options_.probe * std::sqrt(sigma2[t]);
    std::vector<float> perturbed(x, x + samples), step(static_cast<size_t>(samples), 0.0f);
    each_sample_by_tile(shape_, options_.tile, tiles_x_, [&](size_t t, int64_t i) {
        const float v = probe_sample(x[i], eps[t], f, i);
        step[static_cast<size_t>(i)] = v - x[i];
        perturbed[static_cast<size_t>(i)] = v;
    });
    prefilter(perturbed.data());
    std::vector<double> stein(sigma2.size(), 0.0);
    each_sample_by_tile(shape_, options_.tile, tiles_x_, [&](size_t t, int64_t i) {
        const double s = step[static_cast<size_t>(i)];
        if (s == 0 || !(std::fabs(static_cast<double>(x[i]) - y[i]) <= limit[t])) return;  // as the fit's samples
        // sigma^2 dy_i/dx_i, estimated along the sign pattern: sigma^2 b (y' - y) / eps
        const double d = sigma2[t] * (static_cast<double>(perturbed[static_cast<size_t>(i)]) - y[i]) / s;
        if (std::isfinite(d)) stein[t] += d;
    });
    stein_[static_cast<size_t>(f)] = std::move(stein);
    sigma2_[static_cast<size_t>(f)] = std::move(sigma2);
    limit_[static_cast<size_t>(f)] = std::move(limit);
    eps_[static_cast<size_t>(f)] = std::move(eps);
}

void TimeTrust::perturb_rows(int64_t f, int64_t y0, int64_t y1, float* rows) const {
    const std::vector<double>& eps = eps_[static_cast<size_t>(f)];
    if (eps.empty()) throw Error(Status::Internal, "time trust: frame " + std::to_string(f) + " was not probed");
    const int64_t W = shape_.width, C = shape_.channels, tile = options_.tile;
    for (int64_t py = y0; py < y1; ++py)
        for (int64_t px = 0; px < W; ++px) {
            const double e = eps[static_cast<size_t>((py / tile) * tiles_x_ + px / tile)];
            for (int64_t c = 0; c < C; ++c) {
                float& v = rows[((py - y0) * W + px) * C + c];
                v = probe_sample(v, e, f, (py * W + px) * C + c);
            }
        }
}

void TimeTrust::probe_temporal(int64_t f, const float* x, const float* y, const float* z, const float* z_probed) {
    std::vector<double>& stein = stein_[static_cast<size_t>(f)];
    if (stein.empty()) throw Error(Status::Internal, "time trust: frame " + std::to_string(f) + " was not probed");
    const std::vector<double>& eps = eps_[static_cast<size_t>(f)];
    const std::vector<double>& sigma2 = sigma2_[static_cast<size_t>(f)];
    const std::vector<double>& limit = limit_[static_cast<size_t>(f)];
    const bool where_moving = options_.temporal_probe == TimeTrustOptions::TemporalProbe::WhereMoving;
    each_sample_by_tile(shape_, options_.tile, tiles_x_, [&](size_t t, int64_t i) {
        const double reach = where_moving && !path_.empty() ? path_[static_cast<size_t>(i / shape_.channels)] : 1.0;
        if (reach == 0) return;
        const double s = static_cast<double>(probe_sample(x[i], eps[t], f, i)) - x[i];
        if (s == 0 || !(std::fabs(static_cast<double>(x[i]) - y[i]) <= limit[t])) return;  // as probe()'s samples
        const double d = sigma2[t] * (static_cast<double>(z_probed[i]) - z[i]) / s;
        if (std::isfinite(d)) stein[t] -= reach * d;
    });
}

void TimeTrust::set_motion_path(std::vector<float> weight) {
    if (!weight.empty() && static_cast<int64_t>(weight.size()) != shape_.pixels())
        throw Error(Status::Internal, "time trust: the motion path is not one value per pixel of a frame");
    path_ = std::move(weight);
    off_path_.assign(path_.empty() ? 0 : static_cast<size_t>(tiles_x_ * tiles_y_), 1);
    for (size_t p = 0; p < path_.size(); ++p)
        if (path_[p] > 0) {
            const int64_t py = static_cast<int64_t>(p) / shape_.width, px = static_cast<int64_t>(p) % shape_.width;
            off_path_[static_cast<size_t>((py / options_.tile) * tiles_x_ + px / options_.tile)] = 0;
        }
}

void TimeTrust::measure(int64_t f, const float* x, const float* y, const float* z) {
    const std::vector<double>& stein = stein_[static_cast<size_t>(f)];
    if (stein.empty()) throw Error(Status::Internal, "time trust: frame " + std::to_string(f) + " was not probed");
    const std::vector<double>& limit = limit_[static_cast<size_t>(f)];
    std::vector<double> num(stein), den(stein.size(), 0.0);
    each_sample_by_tile(shape_, options_.tile, tiles_x_, [&](size_t t, int64_t i) {
        const double d = static_cast<double>(y[i]) - z[i];
        const double e = static_cast<double>(y[i]) - x[i];
        if (!std::isfinite(d) || !(std::fabs(e) <= limit[t])) return;  // not finite, or a firefly's
        num[t] += e * d;
        den[t] += d * d;
    });
    num_[static_cast<size_t>(f)] = std::move(num);
    den_[static_cast<size_t>(f)] = std::move(den);
}

double TimeTrust::blend(int64_t f, const float* y, float* z) const {
    const int64_t W = shape_.width, H = shape_.height, C = shape_.channels;
    const size_t tiles = static_cast<size_t>(tiles_x_ * tiles_y_);
    // Every frame a tile's pool reaches must have been measured.
    const bool any_off_path = std::find(off_path_.begin(), off_path_.end(), 1) != off_path_.end();
    const int64_t widest = any_off_path ? std::max(options_.pool, options_.still_pool) : options_.pool;
    for (int64_t g = std::max<int64_t>(0, f - widest); g <= std::min(shape_.frames - 1, f + widest); ++g)
        if (num_[static_cast<size_t>(g)].size() != tiles)
            throw Error(Status::Internal, "time trust: frame " + std::to_string(g) + " was not measured");
    std::vector<double> share(tiles);
    double mean = 0;
    for (size_t t = 0; t < tiles; ++t) {
        const int64_t pool = !off_path_.empty() && off_path_[t] ? options_.still_pool : options_.pool;
        double num = 0, den = 0, sigma2 = 0, frames = 0;
        for (int64_t g = std::max<int64_t>(0, f - pool); g <= std::min(shape_.frames - 1, f + pool); ++g) {
            num += num_[static_cast<size_t>(g)][t];
            den += den_[static_cast<size_t>(g)][t];
            sigma2 += sigma2_[static_cast<size_t>(g)][t];
            frames += 1;
        }
        // The fit, num / den, weighed against the prior w = 1 by its evidence den / sigma^2 (sigma^2
        // summed over the pooled frames as den is).
        const double noise = sigma2 / frames;
        const double evidence = noise > 0 ? den / noise : 0.0;
        const double fit = den > 0 ? std::clamp(num / den, 0.0, 1.0) : 1.0;
        const double w = (evidence * fit + 1.0) / (evidence + 1.0);
        share[t] = std::isfinite(w) ? std::clamp(w, 0.0, 1.0) : 1.0;
        mean += share[t];
    }
    for (int64_t py = 0; py < H; ++py) {
        int64_t ty;
        double ay;
        between_centres(py, options_.tile, tiles_y_, ty, ay);
        const int64_t ty1 = std::min(ty + 1, tiles_y_ - 1);
        for (int64_t px = 0; px < W; ++px) {
            int64_t tx;
            double ax;
            between_centres(px, options_.tile, tiles_x_, tx, ax);
            const int64_t tx1 = std::min(tx + 1, tiles_x_ - 1);
            auto at = [&](int64_t a, int64_t b) { return share[static_cast<size_t>(a * tiles_x_ + b)]; };
            const double w = (1 - ay) * ((1 - ax) * at(ty, tx) + ax * at(ty, tx1)) + ay * ((1 - ax) * at(ty1, tx) + ax * at(ty1, tx1));
            for (int64_t c = 0; c < C; ++c) {
                const int64_t i = (py * W + px) * C + c;
                const double d = static_cast<double>(y[i]) - z[i];
                if (std::isfinite(d)) z[i] = static_cast<float>(y[i] - w * d);
            }
        }
    }
    return share.empty() ? 1.0 : mean / static_cast<double>(share.size());
}

}  // namespace statfilter
