#include "cli_images.hpp"

#include <algorithm>
#include <cmath>

namespace statfilter_cli {
namespace {

bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && std::equal(tail.rbegin(), tail.rend(), s.rbegin(),
                                                 [](char a, char b) { return std::tolower(a) == b; });
}

// A perceptual-ish ramp: dark blue (0) -> teal -> yellow (1); values are clamped to [0, 1].
void false_colour(float v, float* rgb) {
    const float t = std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f);
    rgb[0] = std::clamp(1.8f * t - 0.5f, 0.0f, 1.0f);
    rgb[1] = std::clamp(0.15f + 0.85f * t, 0.0f, 1.0f);
    rgb[2] = std::clamp(0.55f - 0.5f * t, 0.0f, 1.0f);
}

}  // namespace

void save_image_result(const FilterHandle& filter, const std::string& name, const std::string& pattern,
                       ProgressLine& progress) {
    SequenceHandle image;
    filter.check(sf_filter_result_sequence(filter.get(), name.c_str(), image.out()));
    sf_write_options o;
    sf_write_options_init(&o);
    o.pixel_type = SF_PIXEL_FLOAT;
    o.progress = &ProgressLine::callback;
    o.progress_user = &progress;
    if (!ends_with(pattern, ".png")) {
        check(sf_sequence_write(image.get(), pattern.c_str(), &o));
        return;
    }
    // A preview: the first channel through the false-colour ramp, as 8-bit RGB.
    const sf_shape s = image.shape();
    SequenceHandle rgb;
    check(sf_sequence_create(sf_shape{s.frames, s.height, s.width, 3}, rgb.out()));
    float *src = nullptr, *dst = nullptr;
    sf_strides ss{}, ds{};
    check(sf_sequence_data(image.get(), &src, &ss));
    check(sf_sequence_data(rgb.get(), &dst, &ds));
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x) {
                const char* in = reinterpret_cast<const char*>(src) + f * ss.frame + y * ss.row + x * ss.pixel;
                char* out = reinterpret_cast<char*>(dst) + f * ds.frame + y * ds.row + x * ds.pixel;
                false_colour(*reinterpret_cast<const float*>(in), reinterpret_cast<float*>(out));
            }
    for (int64_t i = 0; i < s.frames; ++i) {
        int64_t number = 0;
        check(sf_sequence_frame_number(image.get(), i, &number));
        check(sf_sequence_set_frame_number(rgb.get(), i, number));
    }
    const char* names[] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) check(sf_sequence_set_channel_name(rgb.get(), c, names[c]));
    check(sf_sequence_write(rgb.get(), pattern.c_str(), &o));
}

std::vector<std::pair<std::string, std::string>> parse_save_list(const std::string& list) {
    std::vector<std::pair<std::string, std::string>> out;
    size_t start = 0;
    while (start < list.size()) {
        size_t comma = list.find(',', start);
        if (comma == std::string::npos) comma = list.size();
        const std::string item = list.substr(start, comma - start);
        const size_t eq = item.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == item.size())
            throw UsageError("--save takes NAME=PATTERN[,NAME=PATTERN...], got '" + item + "'");
        out.emplace_back(item.substr(0, eq), item.substr(eq + 1));
        start = comma + 1;
    }
    return out;
}

void check_save_list(const FilterHandle& filter, const std::string& method,
                     const std::vector<std::pair<std::string, std::string>>& list) {
    int count = 0;
    filter.check(sf_filter_image_result_count(filter.get(), &count));
    std::vector<std::string> names;
    for (int i = 0; i < count; ++i) {
        const char* name = nullptr;
        filter.check(sf_filter_image_result_name(filter.get(), i, &name));
        names.emplace_back(name);
    }
    for (const auto& [name, pattern] : list) {
        if (std::find(names.begin(), names.end(), name) != names.end()) continue;
        std::string known;
        for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
        throw UsageError("--save " + name + "=...: method " + method + " has no image result '" + name + "' (" +
                         (known.empty() ? "it has none" : "it has: " + known) + ")");
    }
}

void save_image_results(const FilterHandle& filter, const std::vector<std::pair<std::string, std::string>>& list,
                        ProgressLine& progress) {
    for (const auto& [name, pattern] : list) save_image_result(filter, name, pattern, progress);
}

}  // namespace statfilter_cli
