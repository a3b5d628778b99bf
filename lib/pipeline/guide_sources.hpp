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
// named input given as files or a layer of the input's files, or (albedo, normal) the same given by
// its parameter (pass_files). Each file
// sequence is opened here, for the input's frame numbers, and every pass is checked against the
// input (frames, width, height; the vectors' four channels) before any work.
OpenGuides open_guide_sources(const Filter& filter, const FrameSource& input);
// The channels to read of pass `name` from its files `pattern` (ReadOptions::channels), as the first of
// `frames` (else the first on disk) has them: every channel of
// a file without layers; of a file with layers (a renderer's multilayer EXR, the light and every data
// pass in one file) the one layer named for the pass (vectors: Vector; albedo: Albedo, Denoising
// Albedo, DiffCol; normal: Normal, Denoising Normal, N), the first of those names found in exactly one
// layer. No such layer, or several view layers with it: an error naming the file's layers (the pass
// can then be given as the layer's name).
std::string pass_channels(const std::string& name, const std::string& pattern, const std::vector<int64_t>& frames);
// Whether a pass given as `value` names files (a frame token #, @ or %, a directory, or an image
// file's extension) rather than a layer of the input's own files ("ViewLayer.Vector").
bool pass_names_files(const std::string& value);
// Where pass `name` given as `value` is read from: its files, or for a layer name the files the
// input was read from (`input`'s source; an error when it was not read from files), and the channels
// to read (pass_channels, or the layer).
struct PassFiles {
    std::string pattern, channels;
};
PassFiles pass_files(const std::string& name, const std::string& value, const Sequence& input);
// The file pattern or layer name pass `name` is given as (a named input's files, else for albedo and
// normal the parameter in `params`), or "" when it is not given as files.
std::string guide_pass_pattern(const Filter& filter, const ParamSet& params, const std::string& name);

}  // namespace statfilter
