#include "statfilter/anisotropic_diffusion.hpp"

#include <algorithm>
#include <cstring>
#include <cmath>
#include <vector>

#include "statfilter/error.hpp"
#include "statfilter/fast_log_exp.hpp"

namespace statfilter {

DiffusionFlux parse_diffusion_flux(const std::string& name) {
    if (name == "study") return DiffusionFlux::Study;
    if (name == "perona-malik") return DiffusionFlux::PeronaMalik;
    throw Error(Status::InvalidArgument, "unknown flux '" + name + "' (study, perona-malik)");
}

namespace {

// The robust spread of neighbour differences: 1.4826 x the median of |u(x+1) - u(x)| over the frame;
// d holds the differences (a workspace buffer).
double gradient_noise(const std::vector<double>& u, int64_t width, int64_t height, int64_t channels,
                      std::vector<double>& d) {
    d.clear();
    d.reserve(static_cast<size_t>(width * height));
    for (int64_t y = 0; y < height; ++y)
        for (int64_t x = 0; x + 1 < width; ++x) {
            double g2 = 0;
            for (int64_t c = 0; c < channels; ++c) {
                const double diff = u[(y * width + x + 1) * channels + c] - u[(y * width + x) * channels + c];
                g2 += diff * diff;
            }
            d.push_back(std::sqrt(g2 / channels));
        }
    if (d.empty()) return 0;
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    return 1.4826 * d[d.size() / 2];
}

}  // namespace

double diffusion_working_bytes(int64_t pixels, int64_t channels) {
    const double P = static_cast<double>(pixels);
    return sizeof(double) * (3.0 * P * static_cast<double>(channels) + 2.0 * P);
}

namespace {

void check_options(const DiffusionOptions& o) {
    if (!(o.dt > 0 && o.dt <= 0.25))
        throw Error(Status::InvalidArgument, "diffusion step dt must be in (0, 0.25] for a stable explicit scheme");
    if (!(o.k > 0)) throw Error(Status::InvalidArgument, "diffusion K must be > 0");
}

// The log domain's eps: a fraction of the mean |x| of the finite samples.
double log_epsilon(const std::vector<double>& u, const DiffusionOptions& o) {
    if (!o.log_domain) return 0;
    double sum = 0;
    int64_t finite = 0;
    for (double v : u)
        if (std::isfinite(v)) sum += std::fabs(v), ++finite;
    return finite && sum > 0 ? o.epsilon * sum / finite : 1.0;
}

// The explicit steps on width x height pixels whose rows start `stride` pixels apart (a window of a
// larger frame), the rows and columns of `keep` (window coordinates) written to `out` (its rows
// `out_stride` pixels apart; `in` itself for a diffusion in place), with the frame's eps and K
// (diffusion_scale: a window of a larger frame diffuses with its frame's).
//
// A step goes down the rows once: row y's log values, edge weights and new values are made from two
// rows of log values and of south weights, not whole images of them. The arithmetic of each sample
// is the same as a whole image at a time, so are the bits; the working set is two images (u and the
// next step) and a few rows.
void diffuse(const float* in, int64_t stride, int64_t width, int64_t height, int64_t channels, const PixelBox& keep,
             float* out, int64_t out_stride, const DiffusionOptions& o, const DiffusionScale& scale,
             DiffusionWorkspace& work) {
    const int64_t n = width * height * channels;
    const int64_t row = width * channels;
    const double eps = scale.eps, k = scale.k;
    if (n == 0 || !(k > 0)) {  // a flat frame: nothing to diffuse, the kept box as it is
        for (int64_t y = keep.y0; y < keep.y1; ++y)
            std::memmove(out + (y - keep.y0) * out_stride * channels, in + (y * stride + keep.x0) * channels,
                         static_cast<size_t>((keep.x1 - keep.x0) * channels) * sizeof(float));
        return;
    }
    std::vector<double>& u = work.u;
    std::vector<double>& next = work.next;
    u.resize(static_cast<size_t>(n));
    next.resize(static_cast<size_t>(n));
    for (int64_t y = 0; y < height; ++y)
        std::copy_n(in + y * stride * channels, row, u.begin() + y * row);
    // The values the conductances are computed on: the log image, or u itself.
    const bool separate = o.log_domain && o.conserve;
    if (o.log_domain && !separate) fast_math::signed_log1p(u.data(), u.size(), 1.0 / eps);
    const double inv_k2 = 1.0 / (k * k);
    // Row y of the values the conductances are measured on: rows y and y + 1 of the log image take
    // turns in two rows of `logs`, or u's own row.
    std::vector<double>& logs = work.edges;
    if (separate) logs.resize(static_cast<size_t>(2 * row));
    const auto edges_row = [&](int64_t y) -> const double* {
        if (!separate) return &u[y * row];
        double* to = &logs[(y & 1) * row];
        std::copy_n(&u[y * row], row, to);
        fast_math::signed_log1p(to, static_cast<size_t>(row), 1.0 / eps);  // within 4 ulp of std::log1p, vectorised
        return to;
    };
    // Each edge's conductance once per step (east and south of every pixel), shared by the two
    // pixels it joins: half the exp/sqrt calls of evaluating it from both sides, same values. East:
    // row y's; south: rows y - 1 and y, taking turns.
    std::vector<double>& east = work.east;
    std::vector<double>& south = work.south;
    east.resize(static_cast<size_t>(width));
    south.resize(static_cast<size_t>(2 * width));
    // r = |grad|^2 / channels / K^2 along each edge, then a row's conductances in one call (a loop
    // that vectorises: the exp was a tenth of a balanced run).
    auto squared = [&](const double* a, const double* b) {
        double g2 = 0;
        for (int64_t ch = 0; ch < channels; ++ch) g2 += (b[ch] - a[ch]) * (b[ch] - a[ch]);
        return g2 / channels * inv_k2;
    };
    auto conductances = [&](double* r, int64_t count) {
        if (o.flux == DiffusionFlux::PeronaMalik) {
            fast_math::exp_of_negative(r, static_cast<size_t>(count));
            for (int64_t i = 0; i < count; ++i) r[i] *= o.dt;
        } else {
            for (int64_t i = 0; i < count; ++i) r[i] = o.dt * (1.0 / std::sqrt(1.0 + r[i]));
        }
    };
    // One pixel's step: its value plus the flux from each neighbour present, west, east, north,
    // south in that order (Neumann borders: a missing neighbour contributes no flux). The interior
    // of a row takes the same sums without the border tests. we, wn, ws: the row's east weights and
    // the south weights of the row above and of this one.
    const auto step = [&](int64_t y, int64_t x, const double* we, const double* wn, const double* ws) {
        const double* c = &u[y * row + x * channels];
        double* out = &next[y * row + x * channels];
        for (int64_t ch = 0; ch < channels; ++ch) out[ch] = c[ch];
        const double* neighbours[4] = {x > 0 ? c - channels : nullptr, x + 1 < width ? c + channels : nullptr,
                                       y > 0 ? c - row : nullptr, y + 1 < height ? c + row : nullptr};
        const double weights[4] = {x > 0 ? we[x - 1] : 0.0, we[x], y > 0 ? wn[x] : 0.0, ws[x]};
        for (int i = 0; i < 4; ++i) {
            if (!neighbours[i]) continue;
            for (int64_t ch = 0; ch < channels; ++ch) out[ch] += weights[i] * (neighbours[i][ch] - c[ch]);
        }
    };
    for (int it = 0; it < o.iterations; ++it) {
        const double* g = edges_row(0);
        for (int64_t y = 0; y < height; ++y) {
            const double* below = y + 1 < height ? edges_row(y + 1) : nullptr;
            double* we = east.data();
            for (int64_t x = 0; x + 1 < width; ++x) we[x] = squared(g + x * channels, g + (x + 1) * channels);
            we[width - 1] = 0.0;
            double* ws = &south[(y & 1) * width];
            if (below)
                for (int64_t x = 0; x < width; ++x) ws[x] = squared(g + x * channels, below + x * channels);
            else
                std::fill(ws, ws + width, 0.0);
            conductances(we, width);
            conductances(ws, width);
            const double* wn = &south[((y + 1) & 1) * width];  // row y - 1's, when there is one
            if (y == 0 || y + 1 == height || width < 3) {
                for (int64_t x = 0; x < width; ++x) step(y, x, we, wn, ws);
            } else {
                step(y, 0, we, wn, ws);
                for (int64_t x = 1; x + 1 < width; ++x) {
                    const double* c = &u[y * row + x * channels];
                    double* out = &next[y * row + x * channels];
                    const double w0 = we[x - 1], w1 = we[x], w2 = wn[x], w3 = ws[x];
                    for (int64_t ch = 0; ch < channels; ++ch) {
                        const double v = c[ch];
                        double r = v;
                        r += w0 * (c[ch - channels] - v);
                        r += w1 * (c[ch + channels] - v);
                        r += w2 * (c[ch - row] - v);
                        r += w3 * (c[ch + row] - v);
                        out[ch] = r;
                    }
                }
                step(y, width - 1, we, wn, ws);
            }
            g = below;
        }
        u.swap(next);
    }
    constexpr double lim = 3.4028234663852886e38;
    if (o.log_domain && !separate) fast_math::signed_expm1(u.data(), u.size(), eps);
    for (int64_t y = keep.y0; y < keep.y1; ++y) {
        float* to = out + (y - keep.y0) * out_stride * channels;
        for (int64_t i = (y * width + keep.x0) * channels, end = (y * width + keep.x1) * channels; i < end; ++i)
            *to++ = static_cast<float>(std::clamp(u[i], -lim, lim));
    }
}

}  // namespace

DiffusionScale diffusion_scale(const float* pixels, int64_t width, int64_t height, int64_t channels,
                               const DiffusionOptions& o, DiffusionWorkspace& ws) {
    check_options(o);
    std::vector<double>& g = ws.u;
    g.assign(pixels, pixels + width * height * channels);
    DiffusionScale scale;
    scale.eps = log_epsilon(g, o);
    if (o.log_domain) fast_math::signed_log1p(g.data(), g.size(), 1.0 / scale.eps);
    scale.k = o.k * gradient_noise(g, width, height, channels, ws.east);
    return scale;
}

DiffusionScale diffusion_scale(const float* pixels, int64_t width, int64_t height, int64_t channels,
                               const DiffusionOptions& o) {
    DiffusionWorkspace ws;
    return diffusion_scale(pixels, width, height, channels, o, ws);
}

void diffuse_frame(float* pixels, int64_t width, int64_t height, int64_t channels, const DiffusionOptions& o,
                   DiffusionWorkspace& ws) {
    check_options(o);
    const DiffusionScale scale = diffusion_scale(pixels, width, height, channels, o, ws);
    diffuse(pixels, width, width, height, channels, PixelBox{0, 0, width, height}, pixels, width, o, scale, ws);
}

void diffuse_frame(float* pixels, int64_t width, int64_t height, int64_t channels, const DiffusionOptions& o) {
    DiffusionWorkspace ws;
    diffuse_frame(pixels, width, height, channels, o, ws);
}

void diffuse_region(float* pixels, int64_t width, int64_t height, int64_t channels, const PixelBox& region,
                    const DiffusionOptions& o) {
    DiffusionWorkspace ws;
    diffuse_region(pixels, width, height, channels, region, o, ws);
}

void diffuse_region(float* pixels, int64_t width, int64_t height, int64_t channels, const PixelBox& region,
                    const DiffusionOptions& o, DiffusionWorkspace& ws) {
    check_options(o);
    if (region.x0 >= region.x1 || region.y0 >= region.y1) return;
    if (region.x0 < 0 || region.y0 < 0 || region.x1 > width || region.y1 > height)
        throw Error(Status::InvalidArgument, "diffuse_region: the region is not inside the frame");
    const DiffusionScale scale = diffusion_scale(pixels, width, height, channels, o, ws);
    diffuse_box(pixels, width, height, channels, region, o, scale, ws, pixels + (region.y0 * width + region.x0) * channels,
                width);
}

void diffuse_box(const float* pixels, int64_t width, int64_t height, int64_t channels, const PixelBox& region,
                 const DiffusionOptions& o, const DiffusionScale& scale, DiffusionWorkspace& ws, float* out,
                 int64_t out_stride) {
    check_options(o);
    if (region.x0 >= region.x1 || region.y0 >= region.y1) return;
    if (region.x0 < 0 || region.y0 < 0 || region.x1 > width || region.y1 > height)
        throw Error(Status::InvalidArgument, "diffuse_box: the box is not inside the frame");
    // Each step reaches one pixel further, so the region grown by the steps sees what the whole frame
    // would; the window's own border (Neumann) stays in that margin.
    const int64_t m = o.iterations;
    const int64_t x0 = std::max<int64_t>(0, region.x0 - m), y0 = std::max<int64_t>(0, region.y0 - m);
    const int64_t x1 = std::min(width, region.x1 + m), y1 = std::min(height, region.y1 + m);
    diffuse(pixels + (y0 * width + x0) * channels, width, x1 - x0, y1 - y0, channels,
            PixelBox{region.x0 - x0, region.y0 - y0, region.x1 - x0, region.y1 - y0}, out, out_stride, o, scale, ws);
}

}  // namespace statfilter
