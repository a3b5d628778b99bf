// How far to trust time after a single-frame prefilter (OIDN): a temporal filter run on prefiltered
// frames y removes their flicker, but where it aligns or models frames badly (fast motion,
// disocclusion) its result z is further from the truth than y was. Per tile of every frame, the share
// w of the temporal change d = y - z kept is the least-squares fit of y's own error on d, measured
// against the noisy frame x (an unbiased render of the truth): w = (sum (y - x) d + S) / sum d^2,
// held in [0, 1], where S, Stein's correction for y having been made from x (sum of sigma^2 dy/dx), is
// measured by running the prefilter once more on x perturbed by a small random sign pattern. That fit
// is noisy where d is small against the noise (still regions, where d is the prefilter's flicker and
// a share that jumps from frame to frame would bring the flicker back), so the sums are pooled over
// the frames t-2..t+2 (t-8..t+8 where the temporal stage followed no motion: set_motion_path) and w
// is the posterior mean under a unit prior around 1 (trust time):
// w = (F w_fit + 1) / (F + 1), F = sum d^2 / sigma^2 the evidence in noise units. The output is
// y - w d, with w interpolated between tile centres. A firefly of the noisy frame is no witness: a
// sample whose residual x - y lies beyond `outlier_z` times its tile's RMS residual is left out of the
// tile's fit and noise (one such sample outweighed every other of the pooled frames, and moved their
// output by several per cent). docs/methods.md, "Trusting time after a prefilter".
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "statfilter/sequence.hpp"

namespace statfilter {

struct TimeTrustOptions {
    // 16 x 16 pixels: with three channels, 768 samples per fit, enough for the share to be steady at
    // 4 samples per pixel; small enough to follow a moving object.
    int64_t tile = 16;
    // Frames t - pool .. t + pool share a tile's fit.
    int64_t pool = 2;
    // Where the temporal stage said it followed no motion in a tile (set_motion_path: it modelled the
    // tile's pixels with its model of the whole shot), frames t - still_pool .. t + still_pool share
    // the tile's fit: there z's relation to y is the same at every frame, and a share fitted on five
    // frames jumps from frame to frame (the still-scene jitter: cornell_moving 0.108 -> 0.075 of
    // OIDN's at 4 spp). Chosen leave-one-scene-out (docs/preset_loso.md).
    int64_t still_pool = 8;
    // The probe's step, in units of the tile's noise.
    double probe = 0.05;
    // A residual x - y beyond this many times the RMS residual of its tile and frame is a firefly's,
    // left out of the fit; 0 = none left out. The filters pass their firefly_z. The RMS, not a robust
    // deviation: a render's noise is heavy-tailed, and cut at 8 median deviations its tail went too
    // (relMSE of --quality high 7% higher at 4 spp).
    double outlier_z = 8;
    // With the prefilter run last, where the temporal result's own dependence on the noisy frame is
    // probed too (perturb_rows, probe_temporal: the pipeline runs them): nowhere, only where the
    // temporal stage followed the motion (set_motion_path; not probed when it did not), everywhere.
    enum class TemporalProbe { None, WhereMoving, Everywhere };
    TemporalProbe temporal_probe = TemporalProbe::None;
};

class TimeTrust {
public:
    explicit TimeTrust(const Shape& shape, const TimeTrustOptions& options = {});

    // Frame f's Stein correction per tile, from its noisy pixels x, the prefilter's output y = P(x)
    // and one more run of P (filters a frame in place) on a perturbed copy of x. Frames may be
    // probed from several threads at once.
    void probe(int64_t f, const float* x, const float* y, const std::function<void(float*)>& prefilter);
    // With a temporal result that is itself made from x (the prefilter run last: z = P(T(x))), S must
    // count z's dependence on x too, S = sum sigma^2 (dy/dx - dz/dx): without it the fit leans towards
    // time (on a scene it was not tuned on, --quality high at 4 spp: 1.44x OIDN's relMSE, 1.10x with
    // it; docs/methods.md). dz/dx comes from a second run of T and P on the probe's frames:
    // rows y0..y1 of frame f of the probe, x + eps b as probe() made it, written over x's rows.
    void perturb_rows(int64_t f, int64_t y0, int64_t y1, float* rows) const;
    // Frame f's z and z_probed = P(T(probe)) (the same light gain): sigma^2 dz/dx taken from its Stein
    // correction, over the samples probe() counted. Before measure(f).
    void probe_temporal(int64_t f, const float* x, const float* y, const float* z, const float* z_probed);
    // Where the temporal stage followed the motion (H x W, 0..1; before probe_temporal and blend; never
    // set: the stage did not say). With TemporalProbe::WhereMoving, z's dependence on x counts times
    // this weight: a temporal model over the whole shot gives each frame a weight of about its rank
    // over the frame count, too little to measure, so there the probe's estimate of it is only noise,
    // which reaches the fit and brings back the prefilter's flicker (the still-scene jitter doubled);
    // an average along the flow over a few frames gives it a tenth or more. A tile with no pixel on
    // the path pools its fit over still_pool frames. The stage says where it ran which
    // (lib/filters/hybrid_stage.cpp: the grown moving weight, all zero for a still scene).
    void set_motion_path(std::vector<float> weight);
    // The fit's sums for frame f from its noisy, prefiltered and temporal pixels (any frame order,
    // from several threads at once), once every frame is probed.
    void measure(int64_t f, const float* x, const float* y, const float* z);
    // Once every frame is measured: z (frame f of the temporal result) becomes y - w (y - z); returns
    // the mean share w of the frame.
    double blend(int64_t f, const float* y, float* z) const;
    int64_t tiles_x() const { return tiles_x_; }
    int64_t tiles_y() const { return tiles_y_; }

private:
    Shape shape_;
    TimeTrustOptions options_;
    int64_t tiles_x_, tiles_y_;
    // [frame][tile]: Stein's correction, noise variance, the fit's numerator and denominator, the
    // largest |x - y| a witness may have, the probe's step eps
    std::vector<std::vector<double>> stein_, sigma2_, num_, den_, limit_, eps_;
    std::vector<float> path_;     // set_motion_path's (empty: not said)
    std::vector<char> off_path_;  // per tile: no pixel on the path (empty: not said)
};

}  // namespace statfilter
