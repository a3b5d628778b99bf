// Where temporal filtering can be trusted.
//  alpha(x), one value per pixel, 1 = stationary: from the energy of the leading temporal
//    components at each pixel (the study sums |B_1..B_k|, the leading spatial basis vectors),
//    measured in units of the noise those components would carry anyway (the larger of the global
//    noise level and the pixel's own, from its energy beyond those components). A global light change
//    also lands in the leading components; it is explained across all series by a constant plus a
//    multiple of the mean image, so that part is removed first (global_light=ignore).
//  beta(x, t), per pixel and frame, 1 = moving now: robust temporal z-scores of the pixel's
//    luminance, averaged over a small window and thresholded, then dilated; or, when the renderer's
//    albedo/normal passes are given, their departure from the pixel's temporal median, which noise
//    cannot fake.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "statfilter/prepared_series.hpp"
#include "statfilter/temporal_basis.hpp"

namespace statfilter {

struct GlobalMotionOptions {
    int components = 5;            // the caller passes only components that carry signal (see motion_params)
    bool local_noise = true;       // noise unit: max(global, this pixel's pooled energy beyond the components)
    bool ignore_global_light = true;
    double low = 2.0, high = 8.0;  // ramp from alpha 1 to 0, in multiples of the noise energy
    int window = 5;                // side of the box the energy is averaged over
};

// alpha from passes over the prepared tiles, in any tiling: a fit of the light change (when
// ignore_global_light, needs_light_fit), then the energies; tiles may come from bands of the shot
// (first_pixel: the band's first pixel in the frame).
class GlobalMotionMap {
public:
    GlobalMotionMap(const TemporalBasis& basis, double noise_sigma, const GlobalMotionOptions& options, int64_t height,
                    int64_t width, int64_t channels);
    bool needs_light_fit() const;
    void fit_light(const PreparedTile& tile);
    void finish_light_fit();
    void add_energy(const PreparedTile& tile, int64_t first_pixel);
    std::shared_ptr<Sequence> alpha();  // once every tile's energy is in

private:
    const TemporalBasis& basis_;
    double noise_sigma_;
    GlobalMotionOptions o_;
    int64_t height_, width_, channels_, k_, tail_components_;
    bool local_;
    double n_ = 0, m1_ = 0, mm_ = 0;
    std::vector<double> s1_, sm_, offset_, slope_, energy_, tail_;
};

// alpha as a 1-frame, 1-channel sequence.
std::shared_ptr<Sequence> global_motion_map(PreparedSeries& series, const TemporalBasis& basis, double noise_sigma,
                                            const GlobalMotionOptions& options, const ProgressSpan& progress);

struct LocalMotionOptions {
    double z_threshold = 2.5;
    int window = 5;    // side of the box the squared z-scores are averaged over
    int dilate = 2;    // pixels
    // The scores are on log1p(|l| / scale), l the luminance: scale in the input's units, so that the
    // map does not depend on them (the filters pass transform_scale x transform_level; 1 = the units).
    double scale = 1.0;
};

// beta from z-scores: a F-frame, 1-channel sequence of 0/1.
std::shared_ptr<Sequence> local_motion_from_zscores(const Sequence& input, const LocalMotionOptions& options);

// beta from auxiliary passes (albedo, normal...): moving where any channel departs from the pixel's
// temporal median by more than threshold plus three robust standard deviations of that pixel (edges
// that flicker in every frame are not motion), opened to drop thin edge lines; the maps of several
// passes are combined with max.
std::shared_ptr<Sequence> local_motion_from_aux(const Sequence& aux, double threshold, int dilate);

void combine_max(Sequence& into, const Sequence& other);

// Motion that alpha misses: an object that crosses a pixel in a frame or two (a fast ball) puts a short
// spike into each series, spread over many components each below the noise threshold. This test looks
// at every frame instead: each frame's luminance is divided by the frame's mean (a global light change
// is not motion), median-filtered over 5 x 5 pixels (noise and fireflies go, an object stays), taken as
// log(1 + l / mean), and compared with the pixel's temporal median in units of its own noise, measured
// from frame-to-frame differences (robust to slow trends and to the short spike itself). A pixel moves
// where the median over a 5x5 neighbourhood of the squared score (a firefly or a lone noisy pixel does
// not count, an object does) exceeds z_threshold^2 in some frame, or exceeds grow_z^2 and is joined to
// such a pixel through others that do (hysteresis: the rest of an object's path, not the lone still
// pixels a lower threshold alone would take). 1-frame, 1-channel map of 0/1.
struct TemporalChangeOptions {
    double z_threshold = 5.0;
    double grow_z = 3.0;  // 0 (or >= z_threshold): no growing
};
std::shared_ptr<Sequence> motion_from_temporal_change(const Sequence& input, const TemporalChangeOptions& options);

// The same test in passes over bands of rows of every frame (each band read with kHalo rows above
// and below where the frame has them: the two 5 x 5 median filters reach 4 rows): the frames' light
// levels, then each pixel's centre and noise, then the scores. Any banding gives the same map.
// What the finished test keeps for model_misses and departures (its noise, centres, per-frame gain
// and departures), so another process (a plan's task) can ask them without running the test again.
struct TemporalChangeModel {
    std::vector<double> gain, sigma, centre;
    double unit = 0, floor = 0;
    std::vector<uint32_t> departures;
};

class TemporalChange {
public:
    static constexpr int64_t kHalo = 4;
    TemporalChange(const Shape& shape, const TemporalChangeOptions& options);
    // band: rows [y0, y0 + band height) of every frame, no halo.
    void add_levels(const Sequence& band, int64_t y0);
    void finish_levels();
    // band: rows [y0 - top, ...) of every frame, holding [y0, y1) and up to kHalo rows either side.
    void add_noise(const Sequence& band, int64_t y0, int64_t y1, int64_t top);
    void finish_noise();
    void add_scores(const Sequence& band, int64_t y0, int64_t y1, int64_t top);
    // Once every band's scores are in: the map (its connected regions need the whole frame).
    void finish_scores();
    std::shared_ptr<Sequence> map() const { return map_; }
    // Per pixel (row-major), the number of frames in which the test fires.
    const std::vector<uint32_t>& departures() const { return departures_; }
    // Once the noise is in: 1 where frame f (whole, contiguous pixel x channel) departs from the pixel's
    // temporal median (an event in this frame, by the test's own score and threshold) and by as much
    // from a model of the frame (the temporal reconstruction, its value taking the median's place):
    // where the model misses what the frame shows.
    void model_misses(int64_t f, const float* frame, const float* model, std::vector<uint8_t>& misses) const;
    // Once the scores are in: what model_misses and departures read; a test made from it answers them
    // alike (its map is not kept).
    TemporalChangeModel model() const { return {gain_, sigma_, centre_, unit_, floor_, departures_}; }
    static std::unique_ptr<TemporalChange> from_model(const Shape& shape, const TemporalChangeOptions& options,
                                                      TemporalChangeModel model);

private:
    bool active() const;
    Shape shape_;
    TemporalChangeOptions o_;
    std::vector<double> row_levels_, gain_, sigma_, centre_;
    double unit_ = 0, floor_ = 0;
    std::shared_ptr<Sequence> map_;
    std::vector<uint32_t> departures_;
};

// The test over a sequence held in memory, its map and departures in.
std::unique_ptr<TemporalChange> temporal_change_test(const Sequence& input, const TemporalChangeOptions& options);

// Where the renderer's motion vectors (Cycles' Vector pass, X, Y, Z, W in pixels) carry a pixel `drift`
// pixels or more over the shot (its steps to the next frame summed): 1-frame, 1-channel map of 0/1.
std::shared_ptr<Sequence> motion_from_vectors(const Sequence& vectors, double drift);

}  // namespace statfilter
