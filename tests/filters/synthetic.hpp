// Synthetic sequences with known answers: a low-rank temporal signal plus seeded noise.
#pragma once
#include <cmath>
#include <memory>
#include <random>

#include "statfilter/sequence.hpp"

namespace statfilter::test {

struct LowRank {
    int64_t frames = 24, height = 30, width = 40, channels = 3, rank = 3;
    double offset = 1.0, amplitude = 0.5;
    double noise = 0.0;            // Gaussian sigma
    bool poisson_like = false;     // noise sigma grows with sqrt(signal)
    unsigned seed = 7;
};

// clean gets the noise-free signal, the return value the noisy one.
inline std::unique_ptr<Sequence> make_low_rank(const LowRank& g, std::unique_ptr<Sequence>* clean = nullptr) {
    const Shape shape{g.frames, g.height, g.width, g.channels};
    auto noisy = std::make_unique<Sequence>(shape);
    if (clean) *clean = std::make_unique<Sequence>(shape);
    std::mt19937 rng(g.seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::vector<double> spatial(static_cast<size_t>(g.rank * shape.pixels() * g.channels));
    for (double& v : spatial) v = uniform(rng);
    for (int64_t f = 0; f < g.frames; ++f) {
        const double t = g.frames > 1 ? static_cast<double>(f) / (g.frames - 1) : 0.0;
        for (int64_t p = 0; p < shape.pixels(); ++p)
            for (int64_t c = 0; c < g.channels; ++c) {
                double v = g.offset;
                for (int64_t r = 0; r < g.rank; ++r)
                    v += g.amplitude * spatial[(r * shape.pixels() + p) * g.channels + c] * std::cos(M_PI * (r + 1) * t + r);
                const double sigma = g.poisson_like ? g.noise * std::sqrt(std::max(v, 0.0)) : g.noise;
                const int64_t y = p / g.width, x = p % g.width;
                if (clean) (*clean)->at(f, y, x, c) = static_cast<float>(v);
                noisy->at(f, y, x, c) = static_cast<float>(v + sigma * normal(rng));
            }
    }
    return noisy;
}

inline double mse(const Sequence& a, const Sequence& b) {
    const Shape& s = a.shape();
    double sum = 0;
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) {
                    const double d = static_cast<double>(a.at(f, y, x, c)) - b.at(f, y, x, c);
                    sum += d * d;
                }
    return sum / static_cast<double>(s.samples());
}

// visit(|a - b|) for every sample of two sequences of one shape.
template <class Visit>
void each_abs_diff(const Sequence& a, const Sequence& b, Visit&& visit) {
    const Shape& s = a.shape();
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) visit(std::fabs(static_cast<double>(a.at(f, y, x, c)) - b.at(f, y, x, c)));
}

inline double max_abs_diff(const Sequence& a, const Sequence& b) {
    double m = 0;
    each_abs_diff(a, b, [&](double d) { m = std::max(m, d); });
    return m;
}

// The share of samples of a and b further apart than tolerance.
inline double share_apart(const Sequence& a, const Sequence& b, double tolerance) {
    int64_t apart = 0;
    each_abs_diff(a, b, [&](double d) { apart += d > tolerance; });
    return static_cast<double>(apart) / static_cast<double>(a.shape().samples());
}

inline bool all_finite(const Sequence& a) {
    const Shape& s = a.shape();
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c)
                    if (!std::isfinite(a.at(f, y, x, c))) return false;
    return true;
}

}  // namespace statfilter::test
