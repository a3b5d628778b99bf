#include "pipeline/guide_sources.hpp"

#include <algorithm>
#include <cctype>
#include <utility>

#include "statfilter/error.hpp"
#include "statfilter/filter.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/sequence_io.hpp"

namespace statfilter {

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// The file of `frames`' first frame (else the first on disk) that a pattern names.
std::string first_file(const std::string& pattern, const std::vector<int64_t>& frames) {
    const FramePattern files(pattern);
    if (!files.has_frame_token()) return pattern;
    if (!frames.empty()) return files.format(frames.front());
    const std::vector<int64_t> on_disk = files.scan();
    return on_disk.empty() ? pattern : files.format(on_disk.front());
}

}  // namespace

std::string pass_channels(const std::string& name, const std::string& pattern, const std::vector<int64_t>& frames) {
    const std::string path = first_file(pattern, frames);
    // The file's layers, each with the pass it holds (its last part: "Vector" of "ViewLayer.Vector").
    std::vector<std::pair<std::string, std::string>> layers;
    for (const std::string& channel : select_file_channels(path, "*")) {
        const size_t dot = channel.rfind('.');
        if (dot == std::string::npos) continue;
        const std::string layer = channel.substr(0, dot);
        if (std::none_of(layers.begin(), layers.end(), [&](const auto& l) { return l.first == layer; }))
            layers.emplace_back(layer, lower(channel_pass(channel)));
    }
    // No layer: a file of one pass, read whole. With layers, the pass's own, even beside channels of
    // no layer (other renderers keep the beauty as plain R, G, B next to layers of data passes).
    if (layers.empty()) return "*";
    // Cycles names them Vector, Normal, DiffCol, Denoising Albedo and Denoising Normal; Arnold albedo
    // and N. Only Cycles' vectors are taken by name: their convention is the one the window reads.
    const std::vector<std::string> names = name == "vectors" ? std::vector<std::string>{"vector", "vectors"}
                                           : name == "albedo" ? std::vector<std::string>{"albedo", "denoising albedo", "diffcol"}
                                                              : std::vector<std::string>{"normal", "denoising normal", "n"};
    std::string listed;
    for (const auto& layer : layers) listed += (listed.empty() ? "" : ", ") + layer.first;
    for (const std::string& wanted : names) {
        std::vector<std::string> found;
        for (const auto& [layer, pass] : layers)
            if (pass == wanted) found.push_back(layer);
        if (found.size() == 1) return found.front();
        if (found.size() > 1)
            throw Error(Status::InvalidArgument, "the " + name + " pass '" + path + "' has several layers it could be (" +
                                                     found.front() + ", " + found[1] +
                                                     "): give the layer's name instead of the files (layers: " + listed + ")");
    }
    throw Error(Status::NotFound, "the " + name + " pass '" + path + "' has layers but none named for it (layers: " +
                                      listed + "): give the layer's name instead of the files");
}

// The text alone decides (never what is on disk), so a plan's tasks decide as its writer did, from
// any working directory.
bool pass_names_files(const std::string& value) {
    if (FramePattern(value).has_frame_token() || value.find_first_of("/\\") != std::string::npos) return true;
    const size_t dot = value.rfind('.');
    const std::string extension = dot == std::string::npos ? "" : lower(value.substr(dot + 1));
    for (const char* image : {"exr", "sxr", "tif", "tiff", "hdr", "png", "dpx", "jpg", "jpeg", "tga", "bmp", "jxl", "webp"})
        if (extension == image) return true;
    return false;
}

PassFiles pass_files(const std::string& name, const std::string& value, const Sequence& input) {
    if (pass_names_files(value)) return {value, pass_channels(name, value, input.frame_numbers())};
    const std::string taken = "the " + name + " pass '" + value +
                              "', taken as a layer of the input's files (it has no frame token, directory or image "
                              "extension: give a file as ./" + value + ")";
    const std::string& own = input.source().pattern;
    if (own.empty()) throw Error(Status::InvalidArgument, taken + ", but the input was not read from files");
    // The layer checked on the input's first file now, so that a typo says how the value was read.
    try {
        select_file_channels(first_file(own, input.frame_numbers()), value);
    } catch (const Error& e) {
        throw Error(e.status(), taken + ": " + e.what());
    }
    return {own, value};
}

std::string guide_pass_pattern(const Filter& filter, const ParamSet& params, const std::string& name) {
    if (filter.input(name)) return "";
    const std::string& files = filter.input_files(name);
    if (!files.empty() || name == "vectors" || !params.has(name)) return files;
    return params.get_string(name);
}

OpenGuides open_guide_sources(const Filter& filter, const FrameSource& input) {
    OpenGuides guides;
    const Shape& s = input.shape();
    const auto open = [&](const std::string& name, const FrameSource*& into) {
        if (!filter.takes_input(name)) return;  // e.g. a plugin's own "albedo" parameter (a layer, or its files)
        std::string what = "the " + name + " pass";
        if (const Sequence* pass = filter.input(name)) {
            guides.held.push_back(memory_source(*pass));
        } else {
            const std::string value = guide_pass_pattern(filter, filter.params(), name);
            if (value.empty()) return;
            const PassFiles files = pass_files(name, value, input.attributes());
            what += files.pattern == value ? " '" + value + "'" : " (layer '" + value + "' of '" + files.pattern + "')";
            ReadOptions read;
            read.frames = format_frame_list(input.attributes().frame_numbers());
            read.channels = files.channels;
            guides.held.push_back(open_frame_source(files.pattern, read));
        }
        const Shape& p = guides.held.back()->shape();
        if (p.frames != s.frames || p.width != s.width || p.height != s.height)
            throw Error(Status::InvalidArgument, what + " is " + to_string(p) + ", the input " + to_string(s));
        if (name == "vectors" && p.channels < 4)
            throw Error(Status::InvalidArgument, what + " is " + to_string(p) + ": expected 4 channels (X, Y, Z, W)");
        into = guides.held.back().get();
    };
    open("albedo", guides.view.albedo);
    open("normal", guides.view.normal);
    open("vectors", guides.view.vectors);
    return guides;
}

}  // namespace statfilter
