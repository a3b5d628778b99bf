// Single-frame anisotropic diffusion on float HDR pixels: an explicit 4-neighbour scheme with the
// study's flux 1/sqrt(1 + |grad u|^2 / K^2) or Perona-Malik's exp(-(|grad u| / K)^2). All channels
// share one conductance (from the gradient across channels), so colour edges stay aligned.
// In the log domain, u = sign(x) log(1 + |x| / eps) with eps a fraction of the frame's mean
// magnitude: K then measures relative contrast, the same on a 1e-6 region as on a 1e6 one (for
// frames spanning many decades, make epsilon smaller than the faintest level of interest).
// By default (conserve) the log domain only measures the edges: the flux moves the linear values,
// with the symmetric conductances of the log image, so each frame keeps its sum exactly (no bias from
// undoing a log) and, the step being a convex combination, a non-negative frame stays non-negative.
// K is in units of the frame's own noise: the robust spread (1.4826 x median) of |grad u|, so one
// setting serves 4 and 1024 samples per pixel alike (Black et al., robust anisotropic diffusion).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace statfilter {

enum class DiffusionFlux { Study, PeronaMalik };

struct DiffusionOptions {
    DiffusionFlux flux = DiffusionFlux::PeronaMalik;
    double k = 2.0;         // edge threshold, in units of the frame's gradient noise
    double epsilon = 0.01;  // log domain: eps as a fraction of the frame's mean |x|
    int iterations = 10;
    double dt = 0.25;       // explicit step; <= 0.25 is stable on the 4-neighbour stencil
    bool log_domain = true;
    bool conserve = true;   // log domain: conductances from the log values, flux on the linear ones
};

DiffusionFlux parse_diffusion_flux(const std::string& name);

// The buffers one diffusion works in (the values and the next step, in which K is measured first;
// two rows of the log image; the gradient spread's sample, then a row of east conductances; two rows
// of south ones; all in double), kept between calls by a caller that diffuses frame after frame: at
// 1080p they are 0.12 GB a frame, which the system would otherwise map and zero afresh for every
// frame. Every element is written before it is read, so a reused workspace gives the same bits as a
// new one.
struct DiffusionWorkspace {
    std::vector<double> u, next, edges, east, south;
};

// Diffuses width x height pixels of `channels` interleaved floats in place.
void diffuse_frame(float* pixels, int64_t width, int64_t height, int64_t channels, const DiffusionOptions& options);
void diffuse_frame(float* pixels, int64_t width, int64_t height, int64_t channels, const DiffusionOptions& options,
                   DiffusionWorkspace& workspace);

// What a frame's diffusion measures on the whole frame: the log domain's eps and the edge threshold K
// (options.k x the gradient noise; 0 for a flat frame, which is left as it is).
struct DiffusionScale {
    double eps = 0;
    double k = 0;
};
DiffusionScale diffusion_scale(const float* pixels, int64_t width, int64_t height, int64_t channels,
                               const DiffusionOptions& options);
DiffusionScale diffusion_scale(const float* pixels, int64_t width, int64_t height, int64_t channels,
                               const DiffusionOptions& options, DiffusionWorkspace& workspace);

// Pixels [x0, x1) x [y0, y1) of a frame.
struct PixelBox {
    int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
// Diffuses only `region` of the frame in place, with the values diffuse_frame gives there (bit for
// bit), working on the region grown by the iterations: for a filter that needs a frame's diffusion
// at a few of its pixels. The pixels outside the region are left as they are.
void diffuse_region(float* pixels, int64_t width, int64_t height, int64_t channels, const PixelBox& region,
                    const DiffusionOptions& options);
void diffuse_region(float* pixels, int64_t width, int64_t height, int64_t channels, const PixelBox& region,
                    const DiffusionOptions& options, DiffusionWorkspace& workspace);
// One box of the frame diffused as diffuse_region diffuses it, with the frame's scale given (measured
// once for many boxes), the frame read only: the box's pixels go to `out`, rows out_stride pixels
// apart. Boxes of one frame may overlap in their margins, since none writes into the frame.
void diffuse_box(const float* pixels, int64_t width, int64_t height, int64_t channels, const PixelBox& region,
                 const DiffusionOptions& options, const DiffusionScale& scale, DiffusionWorkspace& workspace,
                 float* out, int64_t out_stride);
// The bytes diffuse_frame holds besides the frame itself, at most: the frame and the next step in
// double and the gradient spread's sample (a double a pixel). Counted as three images and two doubles
// a pixel, as when the log image and the conductances were whole images: an upper bound kept so that
// budgets, and the bands they choose, stay as they were.
double diffusion_working_bytes(int64_t pixels, int64_t channels);

}  // namespace statfilter
