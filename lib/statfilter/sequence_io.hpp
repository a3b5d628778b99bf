// Reading and writing frame sequences through OpenImageIO (EXR and whatever OIIO reads).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"

namespace statfilter {

class FrameSource;
class FrameSink;

struct ColorConversion {
    std::string config;  // OCIO config file; empty = $OCIO
    std::string from, to;  // both empty = no conversion
    bool active() const { return !from.empty() || !to.empty(); }
};

struct ReadOptions {
    // Empty = the default: every channel of a file without layers, the light passes of a file
    // with layers (is_light_channel). "*" = every channel of every part. Otherwise a comma list of
    // channel names and/or layer names; one layer alone is named by its channels' suffixes
    // ("ViewLayer.Diffuse Indirect" -> R, G, B), several names keep the file's full names.
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
    int tile_size = 0;        // 0 = scanlines; N = N x N tiles
    // Each frame a copy of the file it was read from with the channels put back in place, every other
    // part and channel and every header kept (statfilter/exr_into.hpp); pixel types, compression and
    // tiling are then the file's own.
    bool into = false;
    Progress progress;
};

// What an output is checked against before any work, besides its own options.
struct OutputChecks {
    int64_t width = 0, height = 0;  // the frames' size
    std::string input_pattern;      // refuse to write any frame of this sequence ("" = no check) ...
    bool overwrite = false;         // ... unless told to
};

// The pass a channel belongs to: the last part of its layer ("Diffuse Color" of
// "ViewLayer.Diffuse Color.R"), or the channel's own name when it has no layer ("Z").
std::string channel_pass(const std::string& channel);
// False for the data and auxiliary passes a default selection leaves out of a layered file.
bool is_light_channel(const std::string& channel);
// The channels of one file (as named there) that ReadOptions::channels takes, in order.
std::vector<std::string> select_file_channels(const std::string& path, const std::string& channels);
// Where one channel of a sequence lives in its file: the part (OpenImageIO subimage) and its name there.
struct FileChannelRef {
    int part = 0;
    std::string name;
};
// The same channels with their parts.
std::vector<FileChannelRef> locate_file_channels(const std::string& path, const std::string& channels);

std::unique_ptr<Sequence> read_sequence(const std::string& pattern, const ReadOptions& options);
// The same sequence opened for reading in pieces (pipeline/frame_source.hpp): every frame's header is
// read and checked now; pixels are decoded when asked for, all channels of a part in one read.
std::unique_ptr<FrameSource> open_frame_source(const std::string& pattern, const ReadOptions& options);
void write_sequence(const Sequence& sequence, const std::string& pattern, const WriteOptions& options);
// The writer as a sink for frames of `attributes`' frame numbers, channel names and metadata (kept
// alive by the caller): everything is checked here, the frames become visible at commit.
std::unique_ptr<FrameSink> open_frame_sink(const std::string& pattern, const WriteOptions& options,
                                           const Sequence& attributes, const OutputChecks& checks);

}  // namespace statfilter
