#include "cli_images.hpp"

#include <algorithm>
#include <cctype>

namespace statfilter_cli {
namespace {

bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && std::equal(tail.rbegin(), tail.rend(), s.rbegin(),
                                                 [](char a, char b) { return std::tolower(a) == b; });
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
    // A preview: the first channel through the library's false-colour ramp, as 8-bit RGB.
    SequenceHandle rgb;
    check(sf_sequence_false_colour(image.get(), rgb.out()));
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

void check_save_outputs(const FilterHandle& filter, const std::vector<std::pair<std::string, std::string>>& list,
                        const std::string& input_pattern, const std::string& frames, const std::string& output_pattern) {
    for (const auto& [name, pattern] : list)
        filter.check(sf_filter_check_image_output(filter.get(), name.c_str(), pattern.c_str(), input_pattern.c_str(),
                                                  frames.c_str(), output_pattern.empty() ? nullptr : output_pattern.c_str()));
}

void save_image_results(const FilterHandle& filter, const std::vector<std::pair<std::string, std::string>>& list,
                        ProgressLine& progress) {
    for (const auto& [name, pattern] : list) save_image_result(filter, name, pattern, progress);
}

}  // namespace statfilter_cli
