// Reads a frame sequence: resolves the frames and channels once from the first file, then reads
// every frame straight into the sequence's memory, checking each file has the same layout.
#include <OpenImageIO/imageio.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "pipeline/frame_source.hpp"
#include "statfilter/color_convert.hpp"
#include "statfilter/error.hpp"
#include "statfilter/frame_metadata.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/sequence_io.hpp"

namespace statfilter {
namespace {

struct FileChannel {
    int subimage;
    int index;  // within the subimage
    std::string name;
};

// A selected channel and the name it takes in the sequence.
struct Selected {
    FileChannel source;
    std::string name;
};

struct FileLayout {
    int width = 0, height = 0;
    std::vector<FileChannel> channels;
    std::vector<OIIO::ImageSpec> specs;  // one per subimage
};

const char* file_kind(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

// Only a readable regular file is a frame: a FIFO or a device (say a symlink to /dev/zero) would
// block or never end, and an unreadable file is said to be one, not "not an image".
void check_frame_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        if (errno == ENOENT || errno == ENOTDIR) throw Error(Status::NotFound, "missing frame: '" + path + "' does not exist");
        throw Error(Status::Io, "cannot read '" + path + "': " + std::strerror(errno));
    }
    if (!S_ISREG(st.st_mode))
        throw Error(Status::Io, "cannot read '" + path + "': it is " + file_kind(st.st_mode) + ", not a regular file");
    if (::access(path.c_str(), R_OK) != 0) throw Error(Status::Io, "cannot read '" + path + "': " + std::strerror(errno));
}

std::unique_ptr<OIIO::ImageInput> open_image(const std::string& path) {
    check_frame_file(path);
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string why = OIIO::geterror();
        throw Error(Status::Io, "cannot read '" + path + "': " + (why.empty() ? "not a readable image" : why));
    }
    return in;
}

FileLayout read_layout(OIIO::ImageInput& in, const std::string& path) {
    FileLayout layout;
    for (int s = 0; in.seek_subimage(s, 0); ++s) {
        const OIIO::ImageSpec& spec = in.spec();
        if (s == 0) {
            layout.width = spec.width;
            layout.height = spec.height;
        }
        for (int c = 0; c < spec.nchannels; ++c)
            layout.channels.push_back({s, c, spec.channel_name(c)});
        layout.specs.push_back(spec);
    }
    if (layout.specs.empty()) throw Error(Status::Io, "cannot read '" + path + "': no image in file");
    return layout;
}

std::vector<std::string> split_list(const std::string& text) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= text.size()) {
        size_t comma = text.find(',', start);
        if (comma == std::string::npos) comma = text.size();
        std::string item = text.substr(start, comma - start);
        const size_t b = item.find_first_not_of(' '), e = item.find_last_not_of(' ');
        if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
        start = comma + 1;
    }
    return out;
}

std::vector<Selected> select_channels(const FileLayout& layout, const std::string& request, const std::string& path) {
    std::vector<Selected> out;
    if (request.empty()) {
        for (const auto& ch : layout.channels) out.push_back({ch, ch.name});
        if (out.empty()) throw Error(Status::Io, "cannot read '" + path + "': the file has no channels");
        return out;
    }
    const std::vector<std::string> items = split_list(request);
    if (items.empty())
        throw Error(Status::InvalidArgument, "the channel list '" + request +
                                                 "' names no channel or layer (give names such as R,G,B, or leave it "
                                                 "empty for every channel)");
    for (const std::string& item : items) {
        bool found = false;
        for (const auto& ch : layout.channels)
            if (ch.name == item) {
                out.push_back({ch, ch.name});
                found = true;
                break;
            }
        if (found) continue;
        const std::string prefix = item + ".";
        for (const auto& ch : layout.channels)
            if (ch.name.compare(0, prefix.size(), prefix) == 0 && ch.name.size() > prefix.size()) {
                out.push_back({ch, ch.name.substr(prefix.size())});
                found = true;
            }
        if (!found) {
            std::string available;
            for (const auto& ch : layout.channels) available += (available.empty() ? "" : ", ") + ch.name;
            throw Error(Status::NotFound,
                        "no channel or layer '" + item + "' in '" + path + "' (channels: " + available + ")");
        }
    }
    return out;
}

std::vector<int64_t> resolve_frames(const FramePattern& pattern, const std::string& spec) {
    if (!spec.empty()) {
        if (!pattern.has_frame_token() && spec != "1")
            throw Error(Status::InvalidArgument, "pattern '" + pattern.text() + "' has no frame token (#, @ or %0Nd)");
        return parse_frame_spec(spec);
    }
    std::vector<int64_t> frames = pattern.scan();
    if (frames.empty()) throw Error(Status::NotFound, "no files match '" + pattern.text() + "'");
    const int64_t expected = frames.back() - frames.front() + 1;
    if (static_cast<int64_t>(frames.size()) != expected) {
        std::vector<int64_t> missing;
        size_t i = 0;
        for (int64_t f = frames.front(); f <= frames.back(); ++f) {
            if (i < frames.size() && frames[i] == f) {
                ++i;
            } else {
                missing.push_back(f);
            }
        }
        throw Error(Status::NotFound, "gap in sequence '" + pattern.text() + "': frames " +
                                          format_frame_list(missing) + " are missing (found " +
                                          format_frame_list(frames) + "); choose frames explicitly to skip them");
    }
    return frames;
}

// Frames asked for by number must all be there, reported together, before anything is allocated.
void check_frames_exist(const FramePattern& pattern, const std::vector<int64_t>& frames) {
    std::vector<int64_t> missing, found;
    for (int64_t f : frames) {
        struct stat st {};
        if (::stat(pattern.format(f).c_str(), &st) != 0 && (errno == ENOENT || errno == ENOTDIR))
            missing.push_back(f);
        else
            found.push_back(f);
    }
    if (!missing.empty())
        throw Error(Status::NotFound, "sequence '" + pattern.text() + "': frames " + format_frame_list(missing) +
                                          " are missing (found " + (found.empty() ? "none" : format_frame_list(found)) +
                                          "; the first missing is '" + pattern.format(missing.front()) + "')");
}

// Bytes this process may still allocate: the kernel's MemAvailable, within a cgroup's limit.
uint64_t available_memory() {
    uint64_t available = std::numeric_limits<uint64_t>::max();
    std::ifstream meminfo("/proc/meminfo");
    for (std::string line; std::getline(meminfo, line);)
        if (line.rfind("MemAvailable:", 0) == 0) {
            std::istringstream in(line.substr(13));
            uint64_t kb = 0;
            if (in >> kb) available = kb * 1024;
        }
    std::ifstream max_file("/sys/fs/cgroup/memory.max"), current_file("/sys/fs/cgroup/memory.current");
    uint64_t limit = 0, current = 0;
    if (max_file >> limit && current_file >> current) available = std::min(available, limit > current ? limit - current : 0);
    return available;
}

std::string gigabytes(uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f GB", static_cast<double>(bytes) / 1e9);
    return text;
}

// A typo such as --frames 1-20000 must not take the machine's memory: refuse what cannot fit.
void check_fits_in_memory(const Shape& shape, const std::string& pattern) {
    const uint64_t needed = static_cast<uint64_t>(shape.frames) * static_cast<uint64_t>(shape.pixels()) *
                            static_cast<uint64_t>(shape.channels) * sizeof(float);
    const uint64_t available = available_memory();
    if (needed > available)
        throw Error(Status::OutOfMemory,
                    "sequence '" + pattern + "': " + std::to_string(shape.frames) + " frames of " +
                        std::to_string(shape.width) + " x " + std::to_string(shape.height) + " x " +
                        std::to_string(shape.channels) + " float channels need " + std::to_string(needed) + " bytes (" +
                        gigabytes(needed) + "), more than the " + gigabytes(available) +
                        " of memory available: read fewer frames (--frames) or channels");
}

FrameMetadata frame_metadata(const OIIO::ImageSpec& spec) {
    FrameMetadata out;
    for (const auto& p : spec.extra_attribs) {
        const std::string name = p.name().string();
        // Format bookkeeping that the writer sets itself.
        if (name.rfind("oiio:", 0) == 0 || name == "openexr:chunkCount" || name == "compression") continue;
        out.push_back(p);
    }
    return out;
}

// Every frame must hold the first frame's selected channels at the first frame's size.
void check_frame_layout(const FileLayout& layout, const std::vector<Selected>& selection, const Shape& shape,
                        const std::string& path) {
    for (const Selected& sel : selection) {
        const auto s = static_cast<size_t>(sel.source.subimage);
        if (s >= layout.specs.size() || layout.specs[s].nchannels <= sel.source.index ||
            layout.specs[s].channel_name(sel.source.index) != sel.source.name)
            throw Error(Status::NotFound, "'" + path + "' lacks channel '" + sel.source.name + "' found in the first frame");
        const OIIO::ImageSpec& spec = layout.specs[s];
        if (spec.width != shape.width || spec.height != shape.height)
            throw Error(Status::InvalidArgument, "'" + path + "' is " + std::to_string(spec.width) + " x " +
                                                     std::to_string(spec.height) + ", the first frame is " +
                                                     std::to_string(shape.width) + " x " + std::to_string(shape.height));
    }
}

void read_frame(const std::string& path, const std::vector<Selected>& selection, Sequence& seq, int64_t f) {
    auto in = open_image(path);
    const FileLayout layout = read_layout(*in, path);
    check_frame_layout(layout, selection, seq.shape(), path);
    const Strides& st = seq.strides();
    for (size_t c = 0; c < selection.size(); ++c) {
        const FileChannel& src = selection[c].source;
        float* dst = &seq.at(f, 0, 0, static_cast<int64_t>(c));
        if (!in->read_image(src.subimage, 0, src.index, src.index + 1, OIIO::TypeDesc::FLOAT, dst, st.pixel, st.row,
                            OIIO::AutoStride)) {
            std::string why = in->geterror();
            throw Error(Status::Io, "cannot read '" + path + "': " + (why.empty() ? "read failed" : why));
        }
    }
    seq.metadata()[f] = frame_metadata(layout.specs[selection.front().source.subimage]);
}

}  // namespace

std::unique_ptr<Sequence> read_sequence(const std::string& pattern_text, const ReadOptions& options) {
    const FramePattern pattern(pattern_text);
    const std::vector<int64_t> frames = resolve_frames(pattern, options.frames);
    if (!options.frames.empty()) check_frames_exist(pattern, frames);

    const std::string first_path = pattern.format(frames.front());
    FileLayout first;
    {
        auto in = open_image(first_path);
        first = read_layout(*in, first_path);
    }
    const std::vector<Selected> selection = select_channels(first, options.channels, first_path);
    Shape shape;
    shape.frames = static_cast<int64_t>(frames.size());
    shape.width = first.specs[selection.front().source.subimage].width;
    shape.height = first.specs[selection.front().source.subimage].height;
    shape.channels = static_cast<int64_t>(selection.size());
    validate_shape(shape);
    check_fits_in_memory(shape, pattern_text);
    check_color_conversion(options.color, shape.channels);

    auto seq = std::make_unique<Sequence>(shape);
    for (size_t c = 0; c < selection.size(); ++c) seq->channel_names()[c] = selection[c].name;
    seq->source() = SequenceSource{pattern_text, options.channels};
    for (int64_t f = 0; f < shape.frames; ++f) {
        options.progress.report(static_cast<double>(f) / shape.frames, "read");
        seq->frame_numbers()[f] = frames[f];
        read_frame(pattern.format(frames[f]), selection, *seq, f);
        if (options.color.active())
            convert_colors(&seq->at(f, 0, 0, 0), shape.width, shape.height, shape.channels, options.color);
    }
    options.progress.report(1.0, "read");
    return seq;
}

}  // namespace statfilter

// ---- a sequence opened for reading in pieces (bands of scanlines, whole frames) ----------------

namespace statfilter {
namespace {

// Selected channels that sit side by side in one part of the file, read with one call.
struct ChannelRun {
    int subimage = 0, first = 0, count = 0;  // file channels [first, first + count) of the part
    int64_t target = 0;                      // the sequence channel the run starts at
};

std::vector<ChannelRun> channel_runs(const std::vector<Selected>& selection) {
    std::vector<ChannelRun> runs;
    for (size_t c = 0; c < selection.size(); ++c) {
        const FileChannel& src = selection[c].source;
        if (!runs.empty() && runs.back().subimage == src.subimage && runs.back().first + runs.back().count == src.index) {
            ++runs.back().count;
        } else {
            runs.push_back({src.subimage, src.index, 1, static_cast<int64_t>(c)});
        }
    }
    return runs;
}

class ExrFrameSource final : public FrameSource {
public:
    ExrFrameSource(const std::string& pattern_text, const ReadOptions& options)
        : pattern_(pattern_text), color_(options.color) {
        const std::vector<int64_t> frames = resolve_frames(pattern_, options.frames);
        const std::string first_path = pattern_.format(frames.front());
        FileLayout first;
        {
            auto in = open_image(first_path);
            first = read_layout(*in, first_path);
        }
        selection_ = select_channels(first, options.channels, first_path);
        runs_ = channel_runs(selection_);
        const OIIO::ImageSpec& spec = first.specs[selection_.front().source.subimage];
        shape_ = Shape{static_cast<int64_t>(frames.size()), spec.height, spec.width, static_cast<int64_t>(selection_.size())};
        validate_shape(shape_);
        check_color_conversion(options.color, shape_.channels);
        attributes_ = std::make_unique<Sequence>(Shape{shape_.frames, 1, 1, shape_.channels});
        for (size_t c = 0; c < selection_.size(); ++c) attributes_->channel_names()[c] = selection_[c].name;
        attributes_->source() = SequenceSource{pattern_text, options.channels};
        // Every frame's header now, before any pixel: a missing or different frame fails the run
        // before the work starts, and the metadata is at hand for the writer.
        for (int64_t f = 0; f < shape_.frames; ++f) {
            options.progress.report(static_cast<double>(f) / shape_.frames, "open");
            attributes_->frame_numbers()[f] = frames[f];
            const std::string path = pattern_.format(frames[f]);
            auto in = open_image(path);
            const FileLayout layout = read_layout(*in, path);
            check_layout(layout, path);
            attributes_->metadata()[f] = frame_metadata(layout.specs[selection_.front().source.subimage]);
            origins_.push_back(layout.specs[selection_.front().source.subimage].y);
        }
    }

    const Shape& shape() const override { return shape_; }
    const Sequence& attributes() const override { return *attributes_; }

    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override {
        const std::string path = pattern_.format(attributes_->frame_numbers()[f]);
        auto in = open_image(path);
        check_layout(read_layout(*in, path), path);
        const auto pixel = static_cast<OIIO::stride_t>(shape_.channels * sizeof(float));
        const int y = static_cast<int>(origins_[static_cast<size_t>(f)]);
        for (const ChannelRun& run : runs_) {  // all channels of a part in one decode of each chunk
            if (!in->read_scanlines(run.subimage, 0, y + static_cast<int>(y0), y + static_cast<int>(y1), 0, run.first,
                                    run.first + run.count, OIIO::TypeDesc::FLOAT, dst + run.target, pixel,
                                    pixel * shape_.width)) {
                std::string why = in->geterror();
                throw Error(Status::Io, "cannot read '" + path + "': " + (why.empty() ? "read failed" : why));
            }
        }
        if (color_.active()) convert_colors(dst, shape_.width, y1 - y0, shape_.channels, color_);
    }

private:
    void check_layout(const FileLayout& layout, const std::string& path) const {
        check_frame_layout(layout, selection_, shape_, path);
    }

    FramePattern pattern_;
    ColorConversion color_;
    std::vector<Selected> selection_;
    std::vector<ChannelRun> runs_;
    Shape shape_;
    std::unique_ptr<Sequence> attributes_;
    std::vector<int64_t> origins_;  // each frame's data window origin (y)
};

}  // namespace

std::unique_ptr<FrameSource> open_frame_source(const std::string& pattern, const ReadOptions& options) {
    return std::make_unique<ExrFrameSource>(pattern, options);
}

}  // namespace statfilter
