#include "filters/own_first_pass.hpp"

#include <algorithm>

#include "filters/motion_analysis.hpp"

namespace statfilter {

OwnFirstPass::OwnFirstPass(const Shape& shape, std::vector<float> crossings, const TemporalChange* change,
                           const std::vector<uint8_t>& moving, int64_t half_width, DiffusionOptions diffusion)
    : shape_(shape), crossings_(std::move(crossings)), change_(change), diffusion_(diffusion) {
    crossing_pixels_ = crossing_pixels(crossings_);
    if (!change_ || change_->departures().empty()) return;
    const std::vector<uint32_t>& departures = change_->departures();
    brief_.assign(static_cast<size_t>(shape.pixels()), 0);
    for (size_t p = 0; p < brief_.size(); ++p)
        if (moving[p] && departures[p] > 0 && departures[p] <= half_width) brief_[p] = 1, ++brief_pixels_;
}

double OwnFirstPass::working_bytes(const Shape& s) {
    // The model test's three float images and its mask, this frame's weights and pixel list.
    return static_cast<double>(s.pixels()) * (3 * sizeof(float) + 1 + sizeof(float) + sizeof(int64_t));
}

int64_t OwnFirstPass::apply(int64_t f, float* frame, const float* model, float* first_pass,
                            DiffusionWorkspace& workspace) const {
    const int64_t W = shape_.width, C = shape_.channels, P = shape_.pixels();
    // The crossings alone, or with this frame's brief events that I_T misses.
    const std::vector<float>* weight = &crossings_;
    const std::vector<int64_t>* pixels = &crossing_pixels_;
    std::vector<float> frame_weight;
    std::vector<int64_t> frame_pixels;
    if (brief_pixels_ > 0) {
        std::vector<uint8_t> misses;
        change_->model_misses(f, frame, model, misses);
        frame_weight = crossings_.empty() ? std::vector<float>(static_cast<size_t>(P), 0.0f) : crossings_;
        for (int64_t p = 0; p < P; ++p)
            if (brief_[static_cast<size_t>(p)] && misses[static_cast<size_t>(p)]) frame_weight[static_cast<size_t>(p)] = 1.0f;
        frame_pixels = crossing_pixels(frame_weight);
        weight = &frame_weight, pixels = &frame_pixels;
    }
    if (pixels->empty()) return 0;
    diffuse_region(frame, W, shape_.height, C, crossing_box(*pixels, W), diffusion_, workspace);
    blend_own_first_pass(*pixels, *weight, frame, C, first_pass);
    return static_cast<int64_t>(pixels->size());
}

}  // namespace statfilter
