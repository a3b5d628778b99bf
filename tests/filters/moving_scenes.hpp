// Synthetic moving scenes with known answers for the motion tests.
#pragma once
#include <cmath>
#include <memory>
#include <random>

#include "statfilter/sequence.hpp"

namespace statfilter::test {

// A world of 4x4 blocks of random levels in [0.2, 1] (the albedo) lit by smooth indirect light (a
// product of sines, as indirect light is smooth); frame f sees it from column `pan * f` on (the camera
// pans right, the content moves left by `pan` pixels a frame).
inline float world(int64_t u, int64_t v) {
    const uint32_t h = static_cast<uint32_t>((u / 4) * 73856093u) ^ static_cast<uint32_t>((v / 4) * 19349663u);
    return 0.2f + 0.8f * static_cast<float>((h * 2654435761u) >> 8) / static_cast<float>(1u << 24);
}

struct Pan {
    std::unique_ptr<Sequence> clean, noisy, albedo;
};

inline Pan pan_scene(int64_t frames, int64_t height, int64_t width, int64_t pan, double noise) {
    Pan s;
    const Shape shape{frames, height, width, 3};
    s.clean = std::make_unique<Sequence>(shape);
    s.noisy = std::make_unique<Sequence>(shape);
    s.albedo = std::make_unique<Sequence>(shape);
    std::mt19937 rng(5);
    std::normal_distribution<double> n(0, noise);
    for (int64_t f = 0; f < frames; ++f)
        for (int64_t y = 0; y < height; ++y)
            for (int64_t x = 0; x < width; ++x)
                for (int64_t c = 0; c < 3; ++c) {
                    const int64_t u = x + pan * f;
                    s.albedo->at(f, y, x, c) = world(u, y);
                    s.clean->at(f, y, x, c) = static_cast<float>(
                        0.2 + (1 + std::sin(2 * M_PI * u / 24.0)) * (1 + 0.5 * std::cos(2 * M_PI * y / 20.0 + c)));
                    s.noisy->at(f, y, x, c) = static_cast<float>(s.clean->at(f, y, x, c) * (1 + n(rng)));
                }
    return s;
}

}  // namespace statfilter::test
