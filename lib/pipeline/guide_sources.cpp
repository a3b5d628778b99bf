#include "pipeline/guide_sources.hpp"

#include "statfilter/error.hpp"
#include "statfilter/filter.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/sequence_io.hpp"

namespace statfilter {

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
            const std::string pattern = guide_pass_pattern(filter, filter.params(), name);
            if (pattern.empty()) return;
            what += " '" + pattern + "'";
            ReadOptions read;
            read.frames = format_frame_list(input.attributes().frame_numbers());
            read.channels = "*";  // a data pass: every channel, not the default's light passes
            guides.held.push_back(open_frame_source(pattern, read));
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
