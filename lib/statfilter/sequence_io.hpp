// Reading and writing frame sequences through OpenImageIO (EXR and whatever OIIO reads).
#pragma once
#include <memory>
#include <string>

#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"

namespace statfilter {

struct ColorConversion {
    std::string config;  // OCIO config file; empty = $OCIO
    std::string from, to;  // both empty = no conversion
    bool active() const { return !from.empty() || !to.empty(); }
};

struct ReadOptions {
    // Empty = every channel of every part. Otherwise a comma list of channel names and/or layer
    // names; a layer's channels are named by their suffix ("ViewLayer.Diffuse Indirect" -> R, G, B).
    std::string channels;
    std::string frames;  // empty = all frames on disk, which must have no gap
    ColorConversion color;
    Progress progress;
};

struct WriteOptions {
    bool half = true;
    std::string compression = "zip";
    ColorConversion color;
    bool clamp_half = false;  // false: a finite value beyond half's range is an error
    Progress progress;
};

std::unique_ptr<Sequence> read_sequence(const std::string& pattern, const ReadOptions& options);
void write_sequence(const Sequence& sequence, const std::string& pattern, const WriteOptions& options);

}  // namespace statfilter
