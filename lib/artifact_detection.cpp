#include "statfilter/artifact_detection.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "statfilter/error.hpp"
#include "statfilter/nonfinite.hpp"
#include "statfilter/polynomial_regression.hpp"

namespace statfilter {

const char* detect_source_name(DetectSource source) {
    switch (source) {
    case DetectSource::Residual: return "residual";
    case DetectSource::Denoised: return "denoised";
    case DetectSource::Noisy: return "noisy";
    }
    return "?";
}

namespace {

// Mirror an index into [0, n) without repeating the edge sample (OpenCV's BORDER_REFLECT_101).
int64_t reflect101(int64_t i, int64_t n) {
    if (n == 1) return 0;
    const int64_t period = 2 * (n - 1);
    i %= period;
    if (i < 0) i += period;
    return i < n ? i : period - i;
}

// The value the regression sees before averaging, per source.
// y is a row of the whole image; the sequences hold its rows from r0 on.
struct SourceView {
    const Sequence& denoised;
    const Sequence* noisy;
    DetectSource source;
    int64_t r0 = 0;
    double operator()(int64_t f, int64_t y, int64_t x, int64_t c) const {
        y -= r0;
        switch (source) {
        case DetectSource::Residual:
            return static_cast<double>(noisy->at(f, y, x, c)) - static_cast<double>(denoised.at(f, y, x, c));
        case DetectSource::Noisy: return noisy->at(f, y, x, c);
        case DetectSource::Denoised: break;
        }
        return denoised.at(f, y, x, c);
    }
};

// Per-pixel quantities of the rows [rows.y0, rows.y1): level (mean |denoised| + offset) and, with a
// noisy input, the relative noise of the window-averaged residual. The noise variance is measured on
// every row held (the band and its halo), so that the window reaches the rows beside the band.
struct PixelStats {
    std::vector<double> level;        // band pixels
    std::vector<double> noise_ratio;  // band pixels (empty without noisy input)
    std::vector<double> sigma;        // C x band pixels: noise sigma of the averaged residual per channel (ditto)
};

PixelStats pixel_stats(const DetectRows& rows, int64_t window, const ProgressSpan& progress) {
    const Sequence& denoised = rows.denoised;
    const Sequence* noisy = rows.noisy;
    const Shape& s = denoised.shape();
    const int64_t F = s.frames, held = s.height, W = s.width, C = s.channels, H = rows.height;
    const int64_t P = (rows.y1 - rows.y0) * W, HP = held * W;  // band pixels, held pixels
    PixelStats st;
    st.level.assign(static_cast<size_t>(P), 0.0);
    std::vector<double> var;  // C x held pixels: per-pixel noise variance of the residual
    if (noisy) var.assign(static_cast<size_t>(C * HP), 0.0);
    std::vector<double> sq(static_cast<size_t>(F));
    for (int64_t y = 0; y < held; ++y) {
        if (y % 64 == 0) progress.report(static_cast<double>(y) / static_cast<double>(held));
        const int64_t gy = rows.r0 + y;
        const bool in_band = gy >= rows.y0 && gy < rows.y1;
        if (!in_band && !noisy) continue;
        for (int64_t x = 0; x < W; ++x) {
            const int64_t p = y * W + x;
            double sum = 0;
            for (int64_t c = 0; c < C; ++c) {
                for (int64_t f = 0; f < F; ++f) {
                    const double d = denoised.at(f, y, x, c);
                    sum += std::fabs(d);
                    if (noisy) {
                        const double e = static_cast<double>(noisy->at(f, y, x, c)) - d;
                        sq[static_cast<size_t>(f)] = e * e;
                    }
                }
                if (noisy) {
                    // The median of e^2 over time ignores the few frames where the denoiser is wrong;
                    // a Gaussian's squared samples have median 0.455 sigma^2.
                    auto mid = sq.begin() + F / 2;
                    std::nth_element(sq.begin(), mid, sq.end());
                    var[static_cast<size_t>(c * HP + p)] = *mid / 0.4549;
                }
            }
            if (in_band) st.level[static_cast<size_t>((gy - rows.y0) * W + x)] = sum / static_cast<double>(F * C) + kLevelOffset;
        }
    }
    if (!noisy) return st;
    // The average of window^2 independent samples has 1/window^2 of their variance; its mean
    // absolute value is sigma sqrt(2/pi).
    st.noise_ratio.assign(static_cast<size_t>(P), 0.0);
    st.sigma.assign(static_cast<size_t>(C * P), 0.0);
    const int64_t lo = (window - 1) / 2, k2 = window * window;
    for (int64_t y = rows.y0; y < rows.y1; ++y)
        for (int64_t x = 0; x < W; ++x) {
            double sigma = 0;
            const int64_t p = (y - rows.y0) * W + x;
            for (int64_t c = 0; c < C; ++c) {
                double v = 0;
                for (int64_t dy = 0; dy < window; ++dy)
                    for (int64_t dx = 0; dx < window; ++dx)
                        v += var[static_cast<size_t>(c * HP + (reflect101(y + dy - lo, H) - rows.r0) * W +
                                                     reflect101(x + dx - lo, W))];
                const double sc = std::sqrt(std::max(0.0, v / static_cast<double>(k2)) / static_cast<double>(k2));
                st.sigma[static_cast<size_t>(c * P + p)] = sc;
                sigma += sc;
            }
            st.noise_ratio[static_cast<size_t>(p)] =
                sigma / static_cast<double>(C) * std::sqrt(2.0 / M_PI) / st.level[static_cast<size_t>(p)];
        }
    return st;
}

// The degree-d fit of one series (F samples) in the basis.
void refit_degree(const PolynomialBasis& basis, int64_t d, const double* series, double* fit) {
    const int64_t F = basis.frames;
    std::fill(fit, fit + F, 0.0);
    for (int64_t k = 0; k <= d; ++k) {
        double c = 0;
        for (int64_t f = 0; f < F; ++f) c += basis.at(f, k) * series[f];
        for (int64_t f = 0; f < F; ++f) fit[f] += basis.at(f, k) * c;
    }
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

// Window-averaged series of the rows [y0, y1): tile[f * n + j], j = (pixel in band) * C + c.
void averaged_band(const SourceView& view, const Shape& s, int64_t H, int64_t y0, int64_t y1, int64_t window,
                   std::vector<double>& tile) {
    const int64_t F = s.frames, W = s.width, C = s.channels;
    const int64_t rows = y1 - y0, n = rows * W * C, lo = (window - 1) / 2;
    const double norm = 1.0 / static_cast<double>(window * window);
    tile.assign(static_cast<size_t>(F * n), 0.0);
    std::vector<double> vertical(static_cast<size_t>(W));
    for (int64_t f = 0; f < F; ++f)
        for (int64_t y = y0; y < y1; ++y)
            for (int64_t c = 0; c < C; ++c) {
                std::fill(vertical.begin(), vertical.end(), 0.0);
                for (int64_t dy = 0; dy < window; ++dy) {
                    const int64_t yy = reflect101(y + dy - lo, H);
                    for (int64_t x = 0; x < W; ++x) vertical[static_cast<size_t>(x)] += view(f, yy, x, c);
                }
                double* out = &tile[static_cast<size_t>(f * n + (y - y0) * W * C + c)];
                for (int64_t x = 0; x < W; ++x) {
                    double sum = 0;
                    for (int64_t dx = 0; dx < window; ++dx) sum += vertical[static_cast<size_t>(reflect101(x + dx - lo, W))];
                    out[x * C] = sum * norm;
                }
            }
}

void check_options(const Sequence& denoised, const Sequence* noisy, const DetectOptions& o) {
    check_detect_options(denoised.shape(), noisy ? &noisy->shape() : nullptr, o);
}

// The regression of the rows [rows.y0, rows.y1), once the tolerance is known: their mask, score and
// degree rows, and the counts. Each pixel's series is its own (the window's average reaches the
// rows held beside the band), so the rows come out the same in any band of any height.
DetectBand regress_rows(const DetectRows& rows, const PixelStats& stats, double delta, const DetectOptions& o,
                        const Progress& progress) {
    const Sequence& denoised = rows.denoised;
    const Shape& s = denoised.shape();
    const int64_t F = s.frames, W = s.width, C = s.channels, H = rows.height, Y0 = rows.y0, Y1 = rows.y1;
    const int64_t BP = (Y1 - Y0) * W;  // band pixels
    DetectBand out;
    out.score = std::make_shared<Sequence>(Shape{F, Y1 - Y0, W, 1});
    out.mask = std::make_shared<Sequence>(Shape{F, Y1 - Y0, W, 1});
    out.degree_map = std::make_shared<Sequence>(Shape{1, Y1 - Y0, W, 1});
    const PolynomialBasis basis = polynomial_basis(F, o.degree);
    const SourceView view{denoised, rows.noisy, o.source, rows.r0};
    // Bands of rows whose F x n buffers (the series, the regression's residual and fit, coefficients)
    // fit the budget.
    const double per_row = static_cast<double>(F + o.degree + 1) * static_cast<double>(W * C) * sizeof(double) * 4.0;
    const int64_t band_rows = std::clamp<int64_t>(static_cast<int64_t>(o.budget_bytes / per_row), 1, Y1 - Y0);
    std::vector<double> tile, tolerance, fit(static_cast<size_t>(C * F)), series(static_cast<size_t>(F));
    std::vector<char> raw(static_cast<size_t>(F));
    for (int64_t y0 = Y0; y0 < Y1; y0 += band_rows) {
        progress.report(0.2 + 0.8 * static_cast<double>(y0 - Y0) / static_cast<double>(Y1 - Y0), "regression");
        const int64_t y1 = std::min(Y1, y0 + band_rows), pixels = (y1 - y0) * W, n = pixels * C;
        averaged_band(view, s, H, y0, y1, o.window, tile);
        tolerance.resize(static_cast<size_t>(pixels));
        for (int64_t j = 0; j < pixels; ++j) tolerance[j] = delta * stats.level[static_cast<size_t>((y0 - Y0) * W + j)];
        const DegreeChoice choice = choose_degrees(basis, tile.data(), n, C, tolerance.data());
        for (int64_t j = 0; j < pixels; ++j) {
            const int64_t y = y0 + j / W, x = j % W, d = choice.degrees[static_cast<size_t>(j)];
            out.degree_map->at(0, y - Y0, x, 0) = static_cast<float>(d);
            const bool unexplained = d > o.degree;
            if (unexplained) {
                ++out.unexplained;
            } else {
                out.degree_sum += d;
                ++out.explained;
            }
            const int64_t p = (y - Y0) * W + x;  // in the band
            // Residual source: a frame the fit misses by far more than the noise is a transient error
            // the fit smoothed away; it keeps its raw average, like unexplained pixels, and the fit is
            // redone without it so that it does not leak into the other frames.
            std::fill(raw.begin(), raw.end(), static_cast<char>(unexplained));
            bool any_outlier = false;
            if (o.source == DetectSource::Residual && !unexplained && o.frame_outlier > 0) {
                for (int64_t f = 0; f < F; ++f) {
                    double z = 0;
                    for (int64_t c = 0; c < C; ++c) {
                        const size_t i = static_cast<size_t>(f * n + j * C + c);
                        const double dev = std::fabs(tile[i] - choice.fit[i]);
                        const double sigma = stats.sigma[static_cast<size_t>(c * BP + p)];
                        z += sigma > 0 ? dev / sigma : (dev > 0 ? HUGE_VAL : 0.0);
                    }
                    raw[static_cast<size_t>(f)] = z / static_cast<double>(C) > o.frame_outlier;
                    any_outlier |= raw[static_cast<size_t>(f)] != 0;
                }
            }
            for (int64_t c = 0; c < C; ++c)
                for (int64_t f = 0; f < F; ++f)
                    fit[static_cast<size_t>(c * F + f)] = choice.fit[static_cast<size_t>(f * n + j * C + c)];
            if (any_outlier) {
                for (int64_t c = 0; c < C; ++c) {
                    for (int64_t f = 0; f < F; ++f) {
                        const size_t i = static_cast<size_t>(f * n + j * C + c);
                        series[static_cast<size_t>(f)] = raw[static_cast<size_t>(f)] ? choice.fit[i] : tile[i];
                    }
                    refit_degree(basis, d, series.data(), &fit[static_cast<size_t>(c * F)]);
                }
            }
            for (int64_t f = 0; f < F; ++f) {
                double score = 0;
                for (int64_t c = 0; c < C; ++c) {
                    const size_t i = static_cast<size_t>(f * n + j * C + c);
                    const double fitted = fit[static_cast<size_t>(c * F + f)];
                    // Residual: the fit is the error estimate. One sequence: what the fit leaves is the artifact.
                    const double est = o.source == DetectSource::Residual ? (raw[static_cast<size_t>(f)] ? tile[i] : fitted)
                                                                          : tile[i] - fitted;
                    const double ref = denoised.at(f, y - rows.r0, x, c);
                    score += est * est / (ref * ref + 0.01);
                }
                score /= static_cast<double>(C);
                out.score->at(f, y - Y0, x, 0) = static_cast<float>(std::min(score, 3.0e38));
                const bool flag = score > o.threshold;
                out.mask->at(f, y - Y0, x, 0) = flag ? 1.0f : 0.0f;
                out.flagged += flag;
            }
        }
    }
    progress.report(1.0, "regression");
    return out;
}

double automatic_delta(const DetectOptions& o, double noise_ratio) {
    if (o.delta > 0) return o.delta;
    if (o.source == DetectSource::Denoised) return kDeltaDenoisedOnly;
    return std::max(kDeltaFloor, kDeltaNoiseFactor * noise_ratio);
}

}  // namespace

void check_detect_options(const Shape& s, const Shape* noisy, const DetectOptions& o) {
    if (o.source != DetectSource::Denoised && !noisy)
        throw Error(Status::InvalidArgument, std::string("source=") + detect_source_name(o.source) +
                                                 " needs the noisy input (the render the denoised sequence was made from)");
    if (noisy && *noisy != s)
        throw Error(Status::InvalidArgument, "the noisy input (" + to_string(*noisy) +
                                                 ") and the denoised sequence (" + to_string(s) + ") differ in shape");
    if (o.degree < 0) throw Error(Status::InvalidArgument, "degree must be >= 0");
    if (o.degree > s.frames - 1)
        throw Error(Status::InvalidArgument, "degree " + std::to_string(o.degree) + " needs at least " +
                                                 std::to_string(o.degree + 1) + " frames; the sequence has " +
                                                 std::to_string(s.frames) + " (use degree <= " +
                                                 std::to_string(s.frames - 1) + ")");
    if (o.window < 1) throw Error(Status::InvalidArgument, "window must be >= 1");
    if (!(o.delta >= 0) || !std::isfinite(o.delta)) throw Error(Status::InvalidArgument, "delta must be >= 0 (0 = automatic)");
    if (!(o.threshold >= 0) || !std::isfinite(o.threshold)) throw Error(Status::InvalidArgument, "threshold must be >= 0");
    if (!(o.frame_outlier >= 0) || !std::isfinite(o.frame_outlier))
        throw Error(Status::InvalidArgument, "frame_outlier must be >= 0 (0 = off)");
}


int64_t detect_halo(const DetectOptions& o) { return o.window / 2; }

std::vector<double> detect_noise_ratios(const DetectRows& rows, const DetectOptions& o) {
    return pixel_stats(rows, o.window, {Progress(), 0.0, 1.0, "noise"}).noise_ratio;
}

double detect_delta(const DetectOptions& o, std::vector<double> noise_ratios, double* noise_ratio) {
    const double ratio = noise_ratios.empty() ? 0.0 : median(std::move(noise_ratios));
    if (noise_ratio) *noise_ratio = ratio;
    return automatic_delta(o, ratio);
}

DetectBand detect_rows(const DetectRows& rows, const DetectOptions& o, double delta, const Progress& progress) {
    check_nonfinite(rows.denoised, NonFinitePolicy::Error);
    if (rows.noisy) check_nonfinite(*rows.noisy, NonFinitePolicy::Error);
    const PixelStats stats = pixel_stats(rows, o.window, {progress, 0.0, 0.2, "noise"});
    return regress_rows(rows, stats, delta, o, progress);
}

Detection detect_artifacts(const Sequence& denoised, const Sequence* noisy, const DetectOptions& o,
                           const Progress& progress) {
    check_options(denoised, noisy, o);
    check_nonfinite(denoised, NonFinitePolicy::Error);
    if (noisy) check_nonfinite(*noisy, NonFinitePolicy::Error);
    const Shape& s = denoised.shape();
    const DetectRows rows{denoised, noisy, 0, 0, s.height, s.height};
    const PixelStats stats = pixel_stats(rows, o.window, {progress, 0.0, 0.2, "noise"});
    Detection out;
    out.source = o.source;
    out.delta = detect_delta(o, stats.noise_ratio, &out.noise_ratio);
    DetectBand band = regress_rows(rows, stats, out.delta, o, progress);
    out.score = std::move(band.score);
    out.mask = std::move(band.mask);
    out.degree_map = std::move(band.degree_map);
    out.score->channel_names()[0] = "score";
    out.mask->channel_names()[0] = "mask";
    out.degree_map->channel_names()[0] = "degree";
    out.score->frame_numbers() = denoised.frame_numbers();
    out.mask->frame_numbers() = denoised.frame_numbers();
    out.degree_map->frame_numbers() = {denoised.frame_numbers().front()};
    out.flagged = band.flagged;
    out.unexplained_pixels = band.unexplained;
    out.mean_degree = band.explained ? static_cast<double>(band.degree_sum) / static_cast<double>(band.explained) : 0.0;
    return out;
}

}  // namespace statfilter
