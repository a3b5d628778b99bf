#include "statfilter/motion.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "filters/low_rank_reconstruction.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

double median_of(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

void dilate_plane(cv::Mat& plane, int radius) {
    if (radius > 0) cv::dilate(plane, plane, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * radius + 1, 2 * radius + 1)));
}

}  // namespace

std::shared_ptr<Sequence> global_motion_map(PreparedSeries& series, const TemporalBasis& basis, double noise_sigma,
                                            const GlobalMotionOptions& o, const ProgressSpan& progress) {
    const int64_t F = basis.frames;
    const int64_t k = std::min<int64_t>(o.components, max_useful_rank(basis.series, F));
    const int64_t channels = series.group().count;
    // The first read fits each component's coefficients by alpha_i + beta_i * mean over all series.
    std::vector<double> s1(k, 0), sm(k, 0), a;
    double n = 0, m1 = 0, mm = 0;
    std::vector<double> offset(k, 0), slope(k, 0);
    const ProgressSpan first{progress.progress, progress.start, progress.span / 2, progress.stage};
    const ProgressSpan second{progress.progress, progress.start + progress.span / 2, progress.span / 2, progress.stage};
    if (k > 0 && o.ignore_global_light) {
        series.read(first, [&](const PreparedTile& t) {
            a.resize(static_cast<size_t>(k * t.n));
            project_onto_basis(basis, k, t.tile.data(), t.n, a.data());
            for (int64_t j = 0; j < t.n; ++j) {
                const double mu = t.means[j];
                n += 1;
                m1 += mu;
                mm += mu * mu;
                for (int64_t i = 0; i < k; ++i) {
                    s1[i] += a[i * t.n + j];
                    sm[i] += a[i * t.n + j] * mu;
                }
            }
        });
        const double det = n * mm - m1 * m1;
        for (int64_t i = 0; i < k; ++i) {
            if (std::fabs(det) > 1e-300) {
                slope[i] = (n * sm[i] - m1 * s1[i]) / det;
                offset[i] = (s1[i] - slope[i] * m1) / n;
            } else {
                offset[i] = s1[i] / std::max(n, 1.0);
            }
        }
    }
    const Shape& shape = series.shape();
    // energy: what the k components hold beyond the light change; tail: what is left beyond them
    // (the pixel's own noise, as in the error threshold method).
    std::vector<double> energy(static_cast<size_t>(shape.pixels()), 0.0), tail(energy.size(), 0.0);
    const int64_t tail_components = max_useful_rank(basis.series, F) - k;
    const bool local = o.local_noise && tail_components > 0;
    if (k > 0)
        series.read(second, [&](const PreparedTile& t) {
            a.resize(static_cast<size_t>(k * t.n));
            project_onto_basis(basis, k, t.tile.data(), t.n, a.data());
            for (int64_t j = 0; j < t.n; ++j) {
                double total = 0;
                if (local)
                    for (int64_t f = 0; f < F; ++f) total += t.tile[f * t.n + j] * t.tile[f * t.n + j];
                for (int64_t i = 0; i < k; ++i) {
                    const double r = a[i * t.n + j] - offset[i] - slope[i] * t.means[j];
                    energy[t.range.begin + j / channels] += r * r;
                    total -= a[i * t.n + j] * a[i * t.n + j];
                }
                tail[t.range.begin + j / channels] += std::max(total, 0.0);
            }
        });
    // Pooled over a window, as in the error threshold method: one pixel's component energy at low
    // sample counts is mostly noise, a moving object covers many pixels.
    const auto pool = [&](std::vector<double>& v) {
        cv::Mat m(static_cast<int>(shape.height), static_cast<int>(shape.width), CV_64F, v.data());
        if (o.window > 1) cv::boxFilter(m, m, -1, cv::Size(o.window, o.window), cv::Point(-1, -1), true, cv::BORDER_REFLECT);
    };
    pool(energy);
    if (local) pool(tail);
    // Pure noise puts about sigma^2 into each of the k components of each channel. Render noise is
    // far from uniform (pixels half on a wall, half on the empty background, get a few large samples
    // and zeros): where the pixel's own noise per component is higher, that is the unit.
    const double noise_energy = std::max(noise_sigma * noise_sigma * static_cast<double>(k * channels), 1e-300);
    auto alpha = std::make_shared<Sequence>(Shape{1, shape.height, shape.width, 1});
    alpha->channel_names()[0] = "alpha";
    for (int64_t p = 0; p < shape.pixels(); ++p) {
        const double own = local ? tail[p] / static_cast<double>(tail_components) * static_cast<double>(k) : 0.0;
        const double r = energy[p] / std::max(noise_energy, own);
        const double moving = std::clamp((r - o.low) / (o.high - o.low), 0.0, 1.0);
        alpha->at(0, p / shape.width, p % shape.width, 0) = static_cast<float>(1.0 - moving);
    }
    return alpha;
}

std::shared_ptr<Sequence> local_motion_from_zscores(const Sequence& input, const LocalMotionOptions& o) {
    const Shape& s = input.shape();
    auto beta = std::make_shared<Sequence>(Shape{s.frames, s.height, s.width, 1});
    beta->channel_names()[0] = "beta";
    beta->frame_numbers() = input.frame_numbers();
    if (s.frames < 3) return beta;  // too few frames to tell motion from noise: nothing is flagged
    // Robust per-pixel centre and spread of the log luminance: median and 1.4826 x MAD over time.
    const int64_t P = s.pixels();
    std::vector<float> lum(static_cast<size_t>(s.frames * P));
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t p = 0; p < P; ++p) {
            double sum = 0;
            for (int64_t c = 0; c < s.channels; ++c) sum += input.at(f, p / s.width, p % s.width, c);
            const double l = sum / s.channels;
            lum[f * P + p] = static_cast<float>(std::copysign(std::log1p(std::fabs(l)), l));
        }
    std::vector<cv::Mat> z2(static_cast<size_t>(s.frames));
    for (auto& m : z2) m = cv::Mat(static_cast<int>(s.height), static_cast<int>(s.width), CV_32F);
    std::vector<double> series(static_cast<size_t>(s.frames)), dev(series.size());
    for (int64_t p = 0; p < P; ++p) {
        for (int64_t f = 0; f < s.frames; ++f) series[f] = lum[f * P + p];
        const double med = median_of(series);
        for (int64_t f = 0; f < s.frames; ++f) dev[f] = std::fabs(series[f] - med);
        const double sigma = 1.4826 * median_of(dev);
        for (int64_t f = 0; f < s.frames; ++f) {
            const double z = sigma > 0 ? (series[f] - med) / sigma : 0.0;  // a constant pixel never moves
            z2[f].at<float>(static_cast<int>(p)) = static_cast<float>(z * z);
        }
    }
    const double threshold2 = o.z_threshold * o.z_threshold;
    for (int64_t f = 0; f < s.frames; ++f) {
        cv::Mat& m = z2[f];
        if (o.window > 1) cv::boxFilter(m, m, -1, cv::Size(o.window, o.window), cv::Point(-1, -1), true, cv::BORDER_REFLECT);
        cv::Mat mask = m > threshold2;  // 255 where moving
        mask.convertTo(m, CV_32F, 1.0 / 255.0);
        dilate_plane(m, o.dilate);
        for (int64_t p = 0; p < P; ++p) beta->at(f, p / s.width, p % s.width, 0) = m.at<float>(static_cast<int>(p));
    }
    return beta;
}

std::shared_ptr<Sequence> local_motion_from_aux(const Sequence& aux, double threshold, int dilate) {
    const Shape& s = aux.shape();
    auto beta = std::make_shared<Sequence>(Shape{s.frames, s.height, s.width, 1});
    beta->channel_names()[0] = "beta";
    beta->frame_numbers() = aux.frame_numbers();
    std::vector<double> series(static_cast<size_t>(s.frames)), dev(series.size());
    std::vector<cv::Mat> planes(static_cast<size_t>(s.frames));
    for (auto& m : planes) m = cv::Mat::zeros(static_cast<int>(s.height), static_cast<int>(s.width), CV_32F);
    for (int64_t y = 0; y < s.height; ++y)
        for (int64_t x = 0; x < s.width; ++x)
            for (int64_t c = 0; c < s.channels; ++c) {
                for (int64_t f = 0; f < s.frames; ++f) series[f] = aux.at(f, y, x, c);
                const double med = median_of(series);
                for (int64_t f = 0; f < s.frames; ++f) dev[f] = std::fabs(series[f] - med);
                // Antialiased edges flicker between two surfaces in every frame: their own spread
                // (MAD) raises the bar, so only a departure that is rare for this pixel counts.
                const double bar = threshold + 3.0 * 1.4826 * median_of(dev);
                for (int64_t f = 0; f < s.frames; ++f)
                    if (dev[f] > bar) planes[f].at<float>(static_cast<int>(y), static_cast<int>(x)) = 1.0f;
            }
    const cv::Mat cross = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
    for (int64_t f = 0; f < s.frames; ++f) {
        // Opening removes one- and two-pixel-wide lines (edges) and keeps solid regions (objects).
        cv::morphologyEx(planes[f], planes[f], cv::MORPH_OPEN, cross);
        dilate_plane(planes[f], dilate);
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                beta->at(f, y, x, 0) = planes[f].at<float>(static_cast<int>(y), static_cast<int>(x));
    }
    return beta;
}

void combine_max(Sequence& into, const Sequence& other) {
    if (into.shape() != other.shape())
        throw Error(Status::InvalidArgument, "motion maps of different shapes: " + to_string(into.shape()) + " and " +
                                                 to_string(other.shape()));
    const Shape& s = into.shape();
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c)
                    into.at(f, y, x, c) = std::max(into.at(f, y, x, c), other.at(f, y, x, c));
}

std::shared_ptr<Sequence> motion_from_temporal_change(const Sequence& input, const TemporalChangeOptions& o) {
    const Shape& s = input.shape();
    const int64_t F = s.frames, P = s.pixels();
    auto map = std::make_shared<Sequence>(Shape{1, s.height, s.width, 1});
    map->channel_names()[0] = "moving";
    if (F < 3) return map;  // too few frames to tell motion from noise
    // Luminance over each frame's mean level, median-filtered (5 x 5), in log(1 + l / m).
    std::vector<cv::Mat> lum(static_cast<size_t>(F));
    std::vector<double> level(static_cast<size_t>(F), 0.0);
    for (int64_t f = 0; f < F; ++f) {
        lum[f] = cv::Mat(static_cast<int>(s.height), static_cast<int>(s.width), CV_32F);
        for (int64_t p = 0; p < P; ++p) {
            double sum = 0;
            for (int64_t c = 0; c < s.channels; ++c) sum += input.at(f, p / s.width, p % s.width, c);
            const double l = std::isfinite(sum) ? std::max(0.0, sum / static_cast<double>(s.channels)) : 0.0;
            lum[f].at<float>(static_cast<int>(p)) = static_cast<float>(l);
            level[f] += l;
        }
    }
    double mean_level = 0;
    for (double l : level) mean_level += l / static_cast<double>(F);
    if (!(mean_level > 0)) return map;  // all zero: nothing moves
    const double m = mean_level / static_cast<double>(P);
    for (int64_t f = 0; f < F; ++f) {
        const double gain = level[f] > 0 ? mean_level / level[f] : 1.0;
        if (s.width >= 5 && s.height >= 5) cv::medianBlur(lum[f], lum[f], 5);
        for (int64_t p = 0; p < P; ++p) {
            float& v = lum[f].at<float>(static_cast<int>(p));
            v = static_cast<float>(std::log1p(gain * v / m));
        }
    }
    // Each pixel's centre (temporal median) and noise (1.4826 MAD of its frame differences / sqrt 2).
    std::vector<cv::Mat> z2(static_cast<size_t>(F));
    for (auto& z : z2) z = cv::Mat(static_cast<int>(s.height), static_cast<int>(s.width), CV_32F);
    std::vector<double> series(static_cast<size_t>(F)), diff(static_cast<size_t>(F - 1)), sigma(static_cast<size_t>(P));
    std::vector<double> centre(static_cast<size_t>(P));
    for (int64_t p = 0; p < P; ++p) {
        for (int64_t f = 0; f < F; ++f) series[f] = lum[f].at<float>(static_cast<int>(p));
        for (int64_t f = 1; f < F; ++f) diff[f - 1] = series[f] - series[f - 1];
        const double dmed = median_of(diff);
        for (double& d : diff) d = std::fabs(d - dmed);
        sigma[p] = 1.4826 * median_of(diff) / std::sqrt(2.0);
        centre[p] = median_of(series);
    }
    // A noise-free series has sigma 0: a floor far below any render noise keeps its score finite.
    const double floor = 1e-6 + 1e-3 * median_of(sigma);
    for (int64_t p = 0; p < P; ++p) {
        const double sd = std::max(sigma[p], floor);
        for (int64_t f = 0; f < F; ++f) {
            const double z = (lum[f].at<float>(static_cast<int>(p)) - centre[p]) / sd;
            z2[f].at<float>(static_cast<int>(p)) = static_cast<float>(std::min(z * z, 1e30));
        }
    }
    cv::Mat peak = cv::Mat::zeros(static_cast<int>(s.height), static_cast<int>(s.width), CV_32F);
    for (int64_t f = 0; f < F; ++f) {
        if (s.width >= 5 && s.height >= 5) cv::medianBlur(z2[f], z2[f], 5);
        peak = cv::max(peak, z2[f]);
    }
    const double threshold2 = o.z_threshold * o.z_threshold;
    for (int64_t p = 0; p < P; ++p)
        map->at(0, p / s.width, p % s.width, 0) = peak.at<float>(static_cast<int>(p)) > threshold2 ? 1.0f : 0.0f;
    return map;
}

std::shared_ptr<Sequence> motion_from_vectors(const Sequence& vectors, double min_drift) {
    const Shape& s = vectors.shape();
    if (s.channels < 4)
        throw Error(Status::InvalidArgument, "motion vectors need 4 channels (X, Y, Z, W), got " + to_string(s));
    auto map = std::make_shared<Sequence>(Shape{1, s.height, s.width, 1});
    map->channel_names()[0] = "moving";
    for (int64_t y = 0; y < s.height; ++y)
        for (int64_t x = 0; x < s.width; ++x) {
            double drift = 0;
            for (int64_t f = 0; f + 1 < s.frames; ++f) {
                const double z = vectors.at(f, y, x, 2), w = vectors.at(f, y, x, 3);
                const double d = std::hypot(z, w);
                if (std::isfinite(d)) drift += d;
            }
            map->at(0, y, x, 0) = drift >= min_drift ? 1.0f : 0.0f;
        }
    return map;
}

}  // namespace statfilter
