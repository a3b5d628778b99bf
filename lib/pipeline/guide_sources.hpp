// The renderer's passes of a run from files (albedo, normal, vectors) as frame sources beside the
// input: a stage reads their rows as it reads the input's, so a run given passes streams too.
#pragma once
#include <cstdint>
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
// The channels to read of pass `name` from its files `pattern` (ReadOptions::channels), as the first of
// `frames` (else the first on disk) has them: every channel of
// a file without layers; of a file with layers (a renderer's multilayer EXR, the light and every data
// pass in one file) the one layer named for the pass (vectors: Vector; albedo: Albedo, Denoising
// Albedo, DiffCol; normal: Normal, Denoising Normal), the first of those names found in exactly one
// layer. No such layer, or several view layers with it: an error naming the file's layers.
std::string pass_channels(const std::string& name, const std::string& pattern, const std::vector<int64_t>& frames);
// The file pattern pass `name` is given as (a named input's files, else for albedo and normal the
// parameter in `params`), or "" when it is not given as files.
std::string guide_pass_pattern(const Filter& filter, const ParamSet& params, const std::string& name);

}  // namespace statfilter
