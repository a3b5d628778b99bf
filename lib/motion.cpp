#include "statfilter/motion.hpp"

#include <algorithm>
#include <array>
#include <mutex>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "pipeline/parallel.hpp"
#include "statfilter/box_mean.hpp"

#include "filters/low_rank_reconstruction.hpp"
#include "statfilter/error.hpp"
#include "statfilter/fast_log_exp.hpp"

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

GlobalMotionMap::GlobalMotionMap(const TemporalBasis& basis, double noise_sigma, const GlobalMotionOptions& o,
                                 int64_t height, int64_t width, int64_t channels)
    : basis_(basis), noise_sigma_(noise_sigma), o_(o), height_(height), width_(width), channels_(channels),
      k_(std::min<int64_t>(o.components, max_useful_rank(basis.series, basis.frames))),
      tail_components_(max_useful_rank(basis.series, basis.frames) - k_),
      local_(o.local_noise && tail_components_ > 0),
      s1_(static_cast<size_t>(k_), 0.0), sm_(static_cast<size_t>(k_), 0.0),
      offset_(static_cast<size_t>(k_), 0.0), slope_(static_cast<size_t>(k_), 0.0),
      energy_(static_cast<size_t>(height * width), 0.0), tail_(energy_.size(), 0.0) {}

bool GlobalMotionMap::needs_light_fit() const { return k_ > 0 && o_.ignore_global_light; }

void GlobalMotionMap::fit_light(const PreparedTile& t) {
    // Each component's coefficients fitted by alpha_i + beta_i * mean over all series.
    std::vector<double> a(static_cast<size_t>(k_ * t.n));
    project_onto_basis(basis_, k_, t.tile.data(), t.n, a.data());
    for (int64_t j = 0; j < t.n; ++j) {
        const double mu = t.means[j];
        n_ += 1;
        m1_ += mu;
        mm_ += mu * mu;
        for (int64_t i = 0; i < k_; ++i) {
            s1_[i] += a[i * t.n + j];
            sm_[i] += a[i * t.n + j] * mu;
        }
    }
}

void GlobalMotionMap::finish_light_fit() {
    const double det = n_ * mm_ - m1_ * m1_;
    for (int64_t i = 0; i < k_; ++i) {
        if (std::fabs(det) > 1e-300) {
            slope_[i] = (n_ * sm_[i] - m1_ * s1_[i]) / det;
            offset_[i] = (s1_[i] - slope_[i] * m1_) / n_;
        } else {
            offset_[i] = s1_[i] / std::max(n_, 1.0);
        }
    }
}

void GlobalMotionMap::add_energy(const PreparedTile& t, int64_t first_pixel) {
    // energy: what the k components hold beyond the light change; tail: what is left beyond them
    // (the pixel's own noise, as in the error threshold method).
    if (k_ == 0) return;
    const int64_t F = basis_.frames;
    std::vector<double> a(static_cast<size_t>(k_ * t.n));
    project_onto_basis(basis_, k_, t.tile.data(), t.n, a.data());
    for (int64_t j = 0; j < t.n; ++j) {
        double total = 0;
        if (local_)
            for (int64_t f = 0; f < F; ++f) total += t.tile[f * t.n + j] * t.tile[f * t.n + j];
        const auto p = static_cast<size_t>(first_pixel + t.range.begin + j / channels_);
        for (int64_t i = 0; i < k_; ++i) {
            const double r = a[i * t.n + j] - offset_[i] - slope_[i] * t.means[j];
            energy_[p] += r * r;
            total -= a[i * t.n + j] * a[i * t.n + j];
        }
        tail_[p] += std::max(total, 0.0);
    }
}

std::shared_ptr<Sequence> GlobalMotionMap::alpha() {
    // Pooled over a window, as in the error threshold method: one pixel's component energy at low
    // sample counts is mostly noise, a moving object covers many pixels.
    const auto pool = [&](std::vector<double>& v) {
        box_mean(v.data(), height_, width_, o_.window, resolve_threads(0));
    };
    pool(energy_);
    if (local_) pool(tail_);
    // Pure noise puts about sigma^2 into each of the k components of each channel. Render noise is
    // far from uniform (pixels half on a wall, half on the empty background, get a few large samples
    // and zeros): where the pixel's own noise per component is higher, that is the unit.
    const double noise_energy = std::max(noise_sigma_ * noise_sigma_ * static_cast<double>(k_ * channels_), 1e-300);
    auto alpha = std::make_shared<Sequence>(Shape{1, height_, width_, 1});
    alpha->channel_names()[0] = "alpha";
    for (int64_t p = 0; p < height_ * width_; ++p) {
        const double own = local_ ? tail_[p] / static_cast<double>(tail_components_) * static_cast<double>(k_) : 0.0;
        const double r = energy_[p] / std::max(noise_energy, own);
        const double moving = std::clamp((r - o_.low) / (o_.high - o_.low), 0.0, 1.0);
        alpha->at(0, p / width_, p % width_, 0) = static_cast<float>(1.0 - moving);
    }
    return alpha;
}

std::shared_ptr<Sequence> global_motion_map(PreparedSeries& series, const TemporalBasis& basis, double noise_sigma,
                                            const GlobalMotionOptions& o, const ProgressSpan& progress) {
    const Shape& shape = series.shape();
    GlobalMotionMap map(basis, noise_sigma, o, shape.height, shape.width, series.group().count);
    const ProgressSpan first{progress.progress, progress.start, progress.span / 2, progress.stage};
    const ProgressSpan second{progress.progress, progress.start + progress.span / 2, progress.span / 2, progress.stage};
    if (map.needs_light_fit()) series.read(first, [&](const PreparedTile& t) { map.fit_light(t); });
    map.finish_light_fit();
    series.read(second, [&](const PreparedTile& t) { map.add_energy(t, 0); });
    return map.alpha();
}

std::shared_ptr<Sequence> local_motion_from_zscores(const Sequence& input, const LocalMotionOptions& o) {
    const Shape& s = input.shape();
    auto beta = std::make_shared<Sequence>(Shape{s.frames, s.height, s.width, 1});
    beta->channel_names()[0] = "beta";
    beta->frame_numbers() = input.frame_numbers();
    if (s.frames < 3) return beta;  // too few frames to tell motion from noise: nothing is flagged
    if (!(o.scale > 0) || !std::isfinite(o.scale)) throw Error(Status::InvalidArgument, "local motion: scale must be > 0");
    // Robust per-pixel centre and spread of the log luminance: median and 1.4826 x MAD over time.
    const int64_t P = s.pixels();
    std::vector<float> lum(static_cast<size_t>(s.frames * P));
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t p = 0; p < P; ++p) {
            double sum = 0;
            for (int64_t c = 0; c < s.channels; ++c) sum += input.at(f, p / s.width, p % s.width, c);
            const double l = sum / s.channels / o.scale;
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
        box_mean(m.ptr<float>(), m.rows, m.cols, o.window, resolve_threads(0));
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

TemporalChange::TemporalChange(const Shape& shape, const TemporalChangeOptions& o)
    : shape_(shape), o_(o), row_levels_(static_cast<size_t>(shape.frames * shape.height), 0.0),
      sigma_(static_cast<size_t>(shape.pixels()), 0.0), centre_(sigma_.size(), 0.0),
      map_(std::make_shared<Sequence>(Shape{1, shape.height, shape.width, 1})),
      departures_(static_cast<size_t>(shape.pixels()), 0) {
    map_->channel_names()[0] = "moving";
}

std::unique_ptr<TemporalChange> TemporalChange::from_model(const Shape& shape, const TemporalChangeOptions& options,
                                                           TemporalChangeModel model) {
    if (model.sigma.size() != static_cast<size_t>(shape.pixels()) || model.centre.size() != model.sigma.size() ||
        model.departures.size() != model.sigma.size() || (!model.gain.empty() && model.gain.size() != static_cast<size_t>(shape.frames)))
        throw Error(Status::InvalidArgument, "the temporal-change test's saved model does not fit the shot's shape");
    auto change = std::make_unique<TemporalChange>(shape, options);
    change->gain_ = std::move(model.gain);
    change->sigma_ = std::move(model.sigma);
    change->centre_ = std::move(model.centre);
    change->unit_ = model.unit;
    change->floor_ = model.floor;
    change->departures_ = std::move(model.departures);
    return change;
}

bool TemporalChange::active() const { return shape_.frames >= 3; }  // fewer: noise and motion look alike

namespace {

const Progress kNoProgress;

// One frame's luminance (channel mean, non-negative, 0 where not finite) as a float image; `at` gives
// sample c of pixel p.
template <typename At>
cv::Mat luminance_image(int64_t width, int64_t height, int64_t channels, const At& at) {
    cv::Mat lum(static_cast<int>(height), static_cast<int>(width), CV_32F);
    for (int64_t p = 0; p < width * height; ++p) {
        double sum = 0;
        for (int64_t c = 0; c < channels; ++c) sum += at(p, c);
        const double l = std::isfinite(sum) ? std::max(0.0, sum / static_cast<double>(channels)) : 0.0;
        lum.at<float>(static_cast<int>(p)) = static_cast<float>(l);
    }
    return lum;
}

// Each frame's luminance as float images.
std::vector<cv::Mat> luminance(const Sequence& band) {
    const Shape& b = band.shape();
    std::vector<cv::Mat> lum(static_cast<size_t>(b.frames));
    parallel_for(b.frames, resolve_threads(0), [&](int64_t f) {
        lum[f] = luminance_image(b.width, b.height, b.channels,
                                 [&](int64_t p, int64_t c) { return band.at(f, p / b.width, p % b.width, c); });
    }, {kNoProgress});
    return lum;
}

// A luminance image over its frame's mean level (gain / unit), median-filtered (5 x 5), in
// log(1 + l / m), in place.
void to_scores_domain(cv::Mat& lum, double gain, double unit, bool blur) {
    if (blur) cv::medianBlur(lum, lum, 5);
    // In blocks through fast_math's vectorised log1p (the luminance is >= 0 here).
    float* v = lum.ptr<float>();
    const auto total = static_cast<int64_t>(lum.total());
    constexpr int64_t block = 1024;
    double x[block];
    for (int64_t p0 = 0; p0 < total; p0 += block) {
        const int64_t m = std::min(block, total - p0);
        for (int64_t i = 0; i < m; ++i) x[i] = gain * v[p0 + i] / unit;
        fast_math::signed_log1p(x, static_cast<size_t>(m), 1.0);
        for (int64_t i = 0; i < m; ++i) v[p0 + i] = static_cast<float>(x[i]);
    }
}

std::vector<cv::Mat> scores_domain(const Sequence& band, const std::vector<double>& gain, double unit, bool blur) {
    std::vector<cv::Mat> lum = luminance(band);
    parallel_for(static_cast<int64_t>(lum.size()), resolve_threads(0),
                 [&](int64_t f) { to_scores_domain(lum[f], gain[f], unit, blur); }, {kNoProgress});
    return lum;
}

}  // namespace

void TemporalChange::add_levels(const Sequence& band, int64_t y0) {
    if (!active()) return;
    const Shape& b = band.shape();
    const std::vector<cv::Mat> lum = luminance(band);
    // Per row, summed over the rows in order once all are in: the same sums whatever the bands. Each
    // sample counts as the median of it and its two neighbours either side in the row (no rows beyond
    // the band needed): one firefly (500 where the frame is 0.4) would otherwise move its frame's level
    // by several per cent and with it every score of that frame.
    const int64_t W = b.width, reach = W >= 5 ? 2 : 0;
    for (int64_t f = 0; f < b.frames; ++f)
        for (int64_t y = 0; y < b.height; ++y) {
            const float* row = lum[f].ptr<float>(static_cast<int>(y));
            double sum = 0;
            for (int64_t x = 0; x < W; ++x) {
                // The five (or one) samples around x, the row's ends repeated, sorted by insertion.
                std::array<float, 5> near{};
                int64_t n = 0;
                for (int64_t k = -reach; k <= reach; ++k, ++n) {
                    const float v = row[std::clamp<int64_t>(x + k, 0, W - 1)];
                    int64_t i = n;
                    for (; i > 0 && near[static_cast<size_t>(i - 1)] > v; --i) near[static_cast<size_t>(i)] = near[static_cast<size_t>(i - 1)];
                    near[static_cast<size_t>(i)] = v;
                }
                sum += near[static_cast<size_t>(reach)];
            }
            row_levels_[static_cast<size_t>(f * shape_.height + y0 + y)] = sum;
        }
}

void TemporalChange::finish_levels() {
    if (!active()) return;
    const int64_t F = shape_.frames;
    gain_.assign(static_cast<size_t>(F), 1.0);
    std::vector<double> level(static_cast<size_t>(F), 0.0);
    for (int64_t f = 0; f < F; ++f)
        for (int64_t y = 0; y < shape_.height; ++y) level[f] += row_levels_[static_cast<size_t>(f * shape_.height + y)];
    double mean_level = 0;
    for (double l : level) mean_level += l / static_cast<double>(F);
    row_levels_.clear();
    if (!(mean_level > 0)) return;  // all zero: nothing moves
    unit_ = mean_level / static_cast<double>(shape_.pixels());
    for (int64_t f = 0; f < F; ++f) gain_[f] = level[f] > 0 ? mean_level / level[f] : 1.0;
}

void TemporalChange::add_noise(const Sequence& band, int64_t y0, int64_t y1, int64_t top) {
    if (!active() || !(unit_ > 0)) return;
    const int64_t F = shape_.frames, W = shape_.width;
    const std::vector<cv::Mat> lum = scores_domain(band, gain_, unit_, shape_.width >= 5 && shape_.height >= 5);
    // Each pixel's centre (temporal median) and noise (1.4826 MAD of its frame differences / sqrt 2).
    parallel_for(y1 - y0, resolve_threads(0), [&](int64_t row) {
        const int64_t y = y0 + row;
        std::vector<double> series(static_cast<size_t>(F)), diff(static_cast<size_t>(F - 1));
        for (int64_t x = 0; x < W; ++x) {
            const int at = static_cast<int>((y - y0 + top) * W + x);
            for (int64_t f = 0; f < F; ++f) series[f] = lum[f].at<float>(at);
            for (int64_t f = 1; f < F; ++f) diff[f - 1] = series[f] - series[f - 1];
            const double dmed = median_of(diff);
            for (double& d : diff) d = std::fabs(d - dmed);
            sigma_[static_cast<size_t>(y * W + x)] = 1.4826 * median_of(diff) / std::sqrt(2.0);
            centre_[static_cast<size_t>(y * W + x)] = median_of(series);
        }
    }, {kNoProgress});
}

void TemporalChange::finish_noise() {
    // A noise-free series has sigma 0: a floor far below any render noise keeps its score finite.
    if (active() && unit_ > 0) floor_ = 1e-6 + 1e-3 * median_of(sigma_);
}

void TemporalChange::add_scores(const Sequence& band, int64_t y0, int64_t y1, int64_t top) {
    if (!active() || !(unit_ > 0)) return;
    const int64_t F = shape_.frames, W = shape_.width, rows = band.shape().height;
    const std::vector<cv::Mat> lum = scores_domain(band, gain_, unit_, shape_.width >= 5 && shape_.height >= 5);
    // Squared scores on every row of the band the pixel's noise is known for (the band's own rows and
    // its halo), median-filtered over 5 x 5 like the luminance.
    const int64_t first = y0 - top;  // the band's first row in the frame
    // Frames in parallel, each thread its own peak; the maximum does not depend on the order.
    cv::Mat peak = cv::Mat::zeros(static_cast<int>(rows), static_cast<int>(W), CV_32F);
    std::mutex peak_mutex;
    const double threshold2 = o_.z_threshold * o_.z_threshold;
    parallel_for(F, resolve_threads(0), [&](int64_t f) {
        cv::Mat z2(static_cast<int>(rows), static_cast<int>(W), CV_32F);
        for (int64_t r = 0; r < rows; ++r)
            for (int64_t x = 0; x < W; ++x) {
                const auto p = static_cast<size_t>((first + r) * W + x);
                const double sd = std::max(sigma_[p], floor_);
                const double z = (lum[f].at<float>(static_cast<int>(r * W + x)) - centre_[p]) / sd;
                z2.at<float>(static_cast<int>(r), static_cast<int>(x)) = static_cast<float>(std::min(z * z, 1e30));
            }
        if (shape_.width >= 5 && shape_.height >= 5) cv::medianBlur(z2, z2, 5);
        std::lock_guard<std::mutex> lock(peak_mutex);
        peak = cv::max(peak, z2);
        for (int64_t y = y0; y < y1; ++y)
            for (int64_t x = 0; x < W; ++x)
                departures_[static_cast<size_t>(y * W + x)] += z2.at<float>(static_cast<int>(y - first), static_cast<int>(x)) > threshold2;
    }, {kNoProgress});
    for (int64_t y = y0; y < y1; ++y)
        for (int64_t x = 0; x < W; ++x)
            map_->at(0, y, x, 0) = peak.at<float>(static_cast<int>(y - first), static_cast<int>(x));
}

void TemporalChange::finish_scores() {
    // The map holds each pixel's peak squared score until here. A pixel moves where its peak exceeds
    // z_threshold^2, or exceeds grow_z^2 and is joined (8-connected, through such pixels) to one that
    // does: the rim of an object's path, whose scores a lower threshold finds, without the lone
    // pixels of a still region that cross it by chance.
    if (!active() || !(unit_ > 0)) return;
    const int H = static_cast<int>(shape_.height), W = static_cast<int>(shape_.width);
    const double high = o_.z_threshold * o_.z_threshold;
    const double low = o_.grow_z > 0 && o_.grow_z < o_.z_threshold ? o_.grow_z * o_.grow_z : high;
    cv::Mat peak(H, W, CV_32F, &map_->at(0, 0, 0, 0));
    cv::Mat candidate = peak > low, labels;
    const int count = cv::connectedComponents(candidate, labels, 8, CV_32S);
    std::vector<uint8_t> seeded(static_cast<size_t>(count), 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            if (peak.at<float>(y, x) > high) seeded[static_cast<size_t>(labels.at<int>(y, x))] = 1;
    seeded[0] = 0;  // label 0: below the low threshold
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) peak.at<float>(y, x) = seeded[static_cast<size_t>(labels.at<int>(y, x))] ? 1.0f : 0.0f;
}

void TemporalChange::model_misses(int64_t f, const float* frame, const float* model, std::vector<uint8_t>& misses) const {
    const int64_t W = shape_.width, H = shape_.height, C = shape_.channels, P = shape_.pixels();
    misses.assign(static_cast<size_t>(P), 0);
    if (!active() || !(unit_ > 0)) return;
    const bool blur = W >= 5 && H >= 5;
    const auto domain = [&](const float* pixels) {
        cv::Mat lum = luminance_image(W, H, C, [&](int64_t p, int64_t c) { return pixels[p * C + c]; });
        to_scores_domain(lum, gain_[static_cast<size_t>(f)], unit_, blur);
        return lum;
    };
    const cv::Mat a = domain(frame), b = domain(model);
    // The squared scores of the frame against the pixel's temporal median (the test's own: an event
    // in this frame) and against the model, each median-filtered like the test's.
    cv::Mat event(static_cast<int>(H), static_cast<int>(W), CV_32F), miss(event.size(), CV_32F);
    for (int64_t p = 0; p < P; ++p) {
        const double sd = std::max(sigma_[static_cast<size_t>(p)], floor_);
        const double v = a.at<float>(static_cast<int>(p));
        const double ze = (v - centre_[static_cast<size_t>(p)]) / sd, zm = (v - b.at<float>(static_cast<int>(p))) / sd;
        event.at<float>(static_cast<int>(p)) = static_cast<float>(std::min(ze * ze, 1e30));
        miss.at<float>(static_cast<int>(p)) = static_cast<float>(std::min(zm * zm, 1e30));
    }
    if (blur) cv::medianBlur(event, event, 5), cv::medianBlur(miss, miss, 5);
    const double threshold2 = o_.z_threshold * o_.z_threshold;
    for (int64_t p = 0; p < P; ++p)
        misses[static_cast<size_t>(p)] = event.at<float>(static_cast<int>(p)) > threshold2 && miss.at<float>(static_cast<int>(p)) > threshold2;
}

std::unique_ptr<TemporalChange> temporal_change_test(const Sequence& input, const TemporalChangeOptions& o) {
    const Shape& s = input.shape();
    auto change = std::make_unique<TemporalChange>(s, o);
    change->add_levels(input, 0);
    change->finish_levels();
    change->add_noise(input, 0, s.height, 0);
    change->finish_noise();
    change->add_scores(input, 0, s.height, 0);
    change->finish_scores();
    return change;
}

std::shared_ptr<Sequence> motion_from_temporal_change(const Sequence& input, const TemporalChangeOptions& o) {
    return temporal_change_test(input, o)->map();
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
