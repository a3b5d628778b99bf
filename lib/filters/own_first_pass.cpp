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
    // Only these pixels need the frame's diffusion: it runs on the boxes that hold them (a box of
    // the whole frame's bounding box of them cost a fifth of a balanced run for 5% of its pixels).
    // Each pixel's value is the whole frame's diffusion there, bit for bit, whatever the boxes.
    const DiffusionScale scale = diffusion_scale(frame, W, shape_.height, C, diffusion_, workspace);
    std::vector<float> own;
    for (const PixelBox& box : boxes_around(*pixels, W, shape_.height)) {
        const int64_t bw = box.x1 - box.x0;
        own.resize(static_cast<size_t>((box.y1 - box.y0) * bw * C));
        diffuse_box(frame, W, shape_.height, C, box, diffusion_, scale, workspace, own.data(), bw);
        for (int64_t y = box.y0; y < box.y1; ++y) {
            auto p = std::lower_bound(pixels->begin(), pixels->end(), y * W + box.x0);
            for (; p != pixels->end() && *p < y * W + box.x1; ++p) {
                const float w = (*weight)[static_cast<size_t>(*p)];
                const float* v = &own[static_cast<size_t>(((y - box.y0) * bw + (*p - y * W - box.x0)) * C)];
                for (int64_t c = 0; c < C; ++c) {
                    float& e = first_pass[*p * C + c];
                    e += w * (v[c] - e);
                }
            }
        }
    }
    return static_cast<int64_t>(pixels->size());
}

std::vector<PixelBox> OwnFirstPass::boxes_around(const std::vector<int64_t>& pixels, int64_t width, int64_t height) {
    // Bands of kBox rows; in each, the runs of kBox-wide columns that hold a pixel, one box a run
    // (joined, so that neighbours share their margins).
    std::vector<PixelBox> boxes;
    const int64_t columns = (width + kBox - 1) / kBox;
    std::vector<uint8_t> used(static_cast<size_t>(columns));
    size_t i = 0;
    while (i < pixels.size()) {
        const int64_t band = pixels[i] / width / kBox, y0 = band * kBox;
        std::fill(used.begin(), used.end(), 0);
        for (; i < pixels.size() && pixels[i] / width / kBox == band; ++i) used[static_cast<size_t>(pixels[i] % width / kBox)] = 1;
        for (int64_t c = 0; c < columns;) {
            if (!used[static_cast<size_t>(c)]) {
                ++c;
                continue;
            }
            const int64_t c0 = c;
            while (c < columns && used[static_cast<size_t>(c)]) ++c;
            boxes.push_back({c0 * kBox, y0, std::min(width, c * kBox), std::min(height, y0 + kBox)});
        }
    }
    return boxes;
}

}  // namespace statfilter
