// The renderer's passes of a run from files (albedo, normal, vectors) as frame sources beside the
// input: a stage reads their rows as it reads the input's, so a run given passes streams too.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "pipeline/stage.hpp"

namespace statfilter {

class Filter;
class ParamSet;

struct OpenGuides {
    GuideSources view;
    std::vector<std::unique_ptr<FrameSource>> held;
};

// The passes the filter takes as named inputs and is given, for the frames of `input`: a named input in memory (borrowed), a
// named input given as files, or (albedo, normal) the file pattern its parameter names. Each file
// sequence is opened here, for the input's frame numbers, and every pass is checked against the
// input (frames, width, height; the vectors' four channels) before any work.
OpenGuides open_guide_sources(const Filter& filter, const FrameSource& input);
// The file pattern pass `name` is given as (a named input's files, else for albedo and normal the
// parameter in `params`), or "" when it is not given as files.
std::string guide_pass_pattern(const Filter& filter, const ParamSet& params, const std::string& name);

}  // namespace statfilter
