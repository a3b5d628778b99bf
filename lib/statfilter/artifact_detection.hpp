// Artifact detection by temporal regression: which pixel-frames of a denoised sequence are still
// wrong, so that a renderer can re-render just those.
//
// The default source (residual) uses both sequences: the residual noisy - denoised is the render
// noise (zero mean, no structure) plus the denoiser's error (structured in space and time). It is
// averaged over a small window (noise drops, the error stays), and each pixel's residual time series
// is fitted by polynomials of degree 0..D in scaled time; the pixel's degree n(x) is the smallest one
// whose mean absolute residual is below delta x the pixel's level (the study's rule). That fit is the
// estimate of the denoiser's error; a pixel no degree explains keeps its raw averaged residual, and so
// does a single frame the fit misses by more than frame_outlier noise sigmas (a transient error, e.g.
// where something passes for a few frames, that a mean over all frames would hide). A
// pixel-frame is flagged when its estimated relative squared error, mean over channels of
// est^2 / (denoised^2 + 0.01) (the relMSE the project measures), exceeds the threshold.
//
// The other sources apply the same regression to one sequence only (the study's form): the part of
// the denoised (or noisy) series the chosen degree does not explain is the artifact estimate.
// docs/methods.md and docs/detect.md give the measurements behind the defaults.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"

namespace statfilter {

enum class DetectSource { Residual, Denoised, Noisy };

const char* detect_source_name(DetectSource source);

struct DetectOptions {
    DetectSource source = DetectSource::Residual;
    int64_t degree = 8;         // highest polynomial degree D (<= frames - 1)
    double delta = 0;           // tolerance relative to the pixel's level; 0 = automatic
    int64_t window = 3;         // side of the square window the series are averaged over
    double threshold = 0.01;    // flag where the estimated relMSE of the pixel-frame exceeds this
    double frame_outlier = 4;   // residual source: a frame whose averaged residual departs from the pixel's
                                // fit by more than this many noise sigmas keeps its raw residual (0 = off)
    double budget_bytes = 512.0 * 1024 * 1024;
};

struct Detection {
    std::shared_ptr<Sequence> score;       // F x H x W x 1: estimated relMSE of each pixel-frame
    std::shared_ptr<Sequence> mask;        // F x H x W x 1: 1 where score > threshold, else 0
    std::shared_ptr<Sequence> degree_map;  // 1 x H x W x 1: n(x); D + 1 where no degree explains the series
    DetectSource source = DetectSource::Residual;
    double delta = 0;                      // the tolerance used
    double noise_ratio = 0;                // median relative noise of the averaged residual (0 without noisy input)
    int64_t flagged = 0;                   // pixel-frames in the mask
    int64_t unexplained_pixels = 0;        // pixels whose degree is D + 1
    double mean_degree = 0;                // over the pixels some degree explains
};

// The automatic tolerance: max(0.1, 2 x the median relative noise) when the noisy input is known
// (noise alone must never pass for structure), 0.02 for the denoised source alone.
constexpr double kDeltaFloor = 0.1;
constexpr double kDeltaNoiseFactor = 2.0;
constexpr double kDeltaDenoisedOnly = 0.02;
// Added to a pixel's mean absolute level before delta scales it, so that dark pixels are not asked
// for an exact fit.
constexpr double kLevelOffset = 0.03;

// noisy may be null only for DetectSource::Denoised. Throws Error(InvalidArgument) for mismatched
// shapes or parameters out of range (degree above frames - 1), Error(Numeric) for NaN/Inf.
Detection detect_artifacts(const Sequence& denoised, const Sequence* noisy, const DetectOptions& options,
                           const Progress& progress);

// The same detection cut into bands of rows (the detect plan's tasks, docs/distributed.md). It is
// per pixel over time except for two window averages (the residual's noise variance and the series),
// which reach detect_halo() rows beside a pixel; and the automatic tolerance, which is the median of
// every pixel's relative noise. So: detect_noise_ratios per band, detect_delta over all of them in
// row order, detect_rows per band. Each gives the rows detect_artifacts gives, bit for bit.
//
// Rows [y0, y1) of an image `height` rows high; the sequences hold its rows [r0, r0 + held) of every
// frame, which must include the band's halo rows (clipped to the image).
struct DetectRows {
    const Sequence& denoised;
    const Sequence* noisy;  // null only for DetectSource::Denoised
    int64_t r0 = 0, y0 = 0, y1 = 0, height = 0;
};

struct DetectBand {
    std::shared_ptr<Sequence> score, mask;  // F x (y1 - y0) x W x 1
    std::shared_ptr<Sequence> degree_map;   // 1 x (y1 - y0) x W x 1
    int64_t flagged = 0, unexplained = 0;
    int64_t degree_sum = 0, explained = 0;  // mean degree = degree_sum / explained, over every band
};

// What detect_artifacts checks, on shapes alone (noisy null without the noisy input).
void check_detect_options(const Shape& denoised, const Shape* noisy, const DetectOptions& options);
int64_t detect_halo(const DetectOptions& options);
// The relative noise of each pixel of the band's rows, row-major (empty without the noisy input).
std::vector<double> detect_noise_ratios(const DetectRows& rows, const DetectOptions& options);
// The tolerance from every pixel's relative noise (any order: the median does not depend on it);
// noise_ratio receives the median.
double detect_delta(const DetectOptions& options, std::vector<double> noise_ratios, double* noise_ratio);
DetectBand detect_rows(const DetectRows& rows, const DetectOptions& options, double delta, const Progress& progress);

}  // namespace statfilter
