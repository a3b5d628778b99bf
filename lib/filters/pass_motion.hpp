// Where the renderer's passes say things move, for a stage that streams: the albedo and normal
// passes change exactly where geometry moves (local_motion_from_aux: a pixel departing from its
// temporal median in any frame), and the vectors carry a pixel some distance over the shot
// (motion_from_vectors). Read in bands of rows of every frame, as the input is, with the 2 rows of
// halo the aux maps' 3 x 3 opening reaches: the same maps as over the shot in memory.
#pragma once
#include <cstdint>

#include "pipeline/stage.hpp"

namespace statfilter {

struct PassMotionOptions {
    bool surfaces = true;        // the albedo/normal passes count (when given)
    double aux_threshold = 0.05;  // local_motion_from_aux's
    double vector_drift = 0;      // motion_from_vectors' (0: the vectors do not say where things move)
    // The passes the front end named, for the memory a stage asks for before it opens them.
    bool named_vectors = false;
    int named_surfaces = 0;  // albedo, normal
};

// Whether any given pass would raise the weight.
bool passes_show_motion(const GuideSources& passes, const PassMotionOptions& options);
// The bytes a band of `rows` rows takes (the pass' samples and two maps a pixel-frame).
double pass_band_bytes(const Shape& shape, int64_t pass_channels, int64_t rows);
// The least band raise_by_passes reads: one row and its halo, of a pass of up to 4 channels.
double least_pass_band_bytes(const Shape& shape);
// Raises `weight` (H x W, 1 = moving) to 1 where the passes show motion, reading bands that fit in
// `budget_bytes` (at least one row and its halo).
void raise_by_passes(float* weight, const Shape& shape, const GuideSources& passes, const PassMotionOptions& options,
                     double budget_bytes, int threads, const ProgressSpan& progress);

}  // namespace statfilter
