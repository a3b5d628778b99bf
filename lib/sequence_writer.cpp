// Writes a frame sequence as EXR (or any format OIIO writes by extension). Everything that can be
// checked is checked before the first file is touched; each frame is written to a temporary file in
// the target directory and all are renamed into place at the end, so a failed run changes nothing.
#include <OpenImageIO/half.h>
#include <OpenImageIO/imageio.h>

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <set>

#include "pipeline/frame_source.hpp"
#include "statfilter/color_convert.hpp"
#include "statfilter/exr_into.hpp"
#include "statfilter/error.hpp"
#include "statfilter/half_samples.hpp"
#include "statfilter/frame_metadata.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/sequence_io.hpp"

namespace fs = std::filesystem;

namespace statfilter {
namespace {


// The level after "name:" (the writer checks the name): a whole number 1-9 for zip and zips, a
// number > 0 for dwaa and dwab, none for the others. OpenEXR would otherwise ignore it silently.
void check_compression_level(const std::string& compression) {
    const size_t colon = compression.find(':');
    if (colon == std::string::npos) return;
    const std::string name = compression.substr(0, colon), level = compression.substr(colon + 1);
    const bool zip = name == "zip" || name == "zips", dwa = name == "dwaa" || name == "dwab";
    if (!zip && !dwa)
        throw Error(Status::InvalidArgument, "EXR compression '" + compression + "': " + name +
                                                 " takes no level (only zip, zips, dwaa and dwab do)");
    char* end = nullptr;
    const double value = level.empty() || std::isspace(static_cast<unsigned char>(level[0]))
                             ? 0.0
                             : std::strtod(level.c_str(), &end);
    const bool number = end && *end == '\0' && std::isfinite(value);
    if (zip && !(number && value == std::floor(value) && value >= 1 && value <= 9))
        throw Error(Status::InvalidArgument, "EXR compression '" + compression +
                                                 "': the zip level must be a whole number from 1 to 9");
    if (dwa && !(number && value > 0))
        throw Error(Status::InvalidArgument, "EXR compression '" + compression +
                                                 "': the DWA level must be a number above 0 (default 45)");
}

void check_compression(const std::string& compression) {
    static const char* known[] = {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};
    const std::string base = compression.substr(0, compression.find(':'));
    for (const char* k : known)
        if (base == k) return check_compression_level(compression);
    throw Error(Status::InvalidArgument, "unknown EXR compression '" + compression +
                                             "' (none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab)");
}

std::string temporary_name(const std::string& final_path) {
    static std::atomic<unsigned> counter{0};
    const fs::path p(final_path);
    const std::string tmp = "." + p.filename().string() + ".tmp" + std::to_string(::getpid()) + "_" +
                            std::to_string(counter++) + p.extension().string();
    return (p.parent_path() / tmp).string();
}

bool process_alive(long pid) { return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

// The pid in a temporary name ".NAME.tmpPID_N.EXT" (0 when the name is not one of ours).
long temporary_owner(const std::string& name) {
    const size_t at = name.rfind(".tmp");
    if (name.empty() || name[0] != '.' || at == std::string::npos) return 0;
    char* end = nullptr;
    const long pid = std::strtol(name.c_str() + at + 4, &end, 10);
    return end && *end == '_' ? pid : 0;
}

// The frame back where it was read from: its data window inside its display window. A frame of
// another size than it was read at (or not read from a file) goes at the origin of a display
// window of its own size.
void place_in_windows(OIIO::ImageSpec& spec, const FrameMetadata& md) {
    if (md.window.empty() || md.window.width != spec.width || md.window.height != spec.height) return;
    spec.x = static_cast<int>(md.window.x);
    spec.y = static_cast<int>(md.window.y);
    const PixelWindow& display = md.display.empty() ? md.window : md.display;
    spec.full_x = static_cast<int>(display.x);
    spec.full_y = static_cast<int>(display.y);
    spec.full_width = static_cast<int>(display.width);
    spec.full_height = static_cast<int>(display.height);
}

// Writes one frame to a temporary file beside its final name and returns that file's name.
// `pixels` are of the file's type (half or float): the library writes them without a conversion
// buffer of its own.
std::string write_temporary(const std::string& path, const void* pixels, const Sequence& attributes, int64_t f,
                            const Shape& s, const WriteOptions& options,
                            const std::vector<std::pair<std::string, std::string>>& extra) {
    OIIO::ImageSpec spec(static_cast<int>(s.width), static_cast<int>(s.height), static_cast<int>(s.channels),
                         options.half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    place_in_windows(spec, attributes.metadata()[f]);
    spec.channelnames = attributes.channel_names();
    spec.alpha_channel = -1;
    for (int64_t c = 0; c < s.channels; ++c)
        if (attributes.channel_names()[c] == "A") spec.alpha_channel = static_cast<int>(c);
    for (const auto& p : attributes.metadata()[f]) spec.attribute(p.name().string(), p.type(), p.data());
    for (const auto& [name, value] : extra) spec.attribute(name, value);
    spec.attribute("compression", options.compression);
    if (options.tile_size > 0) spec.tile_width = spec.tile_height = options.tile_size;

    const std::string tmp = temporary_name(path);
    auto out = OIIO::ImageOutput::create(tmp);
    if (!out) throw Error(Status::Io, "cannot write '" + path + "': " + OIIO::geterror());
    bool ok = out->open(tmp, spec) && out->write_image(spec.format, pixels);
    ok = out->close() && ok;
    const std::string why = out->geterror();
    out.reset();
    if (!ok) {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw Error(Status::Io, "cannot write '" + path + "': " + (why.empty() ? std::string("write failed") : why));
    }
    return tmp;
}

// Frame f as a copy of the file it was read from, its channels put back, in a temporary file beside
// its final name; returns that file's name.
std::string write_into_temporary(const std::string& path, const float* pixels, const Sequence& attributes, int64_t f,
                                 const WriteOptions& options,
                                 const std::vector<std::pair<std::string, std::string>>& extra) {
    const std::string source = FramePattern(attributes.source().pattern).format(attributes.frame_numbers()[f]);
    IntoFrame frame;
    frame.pixels = pixels;
    frame.window = attributes.metadata()[f].window;
    frame.targets = locate_file_channels(source, attributes.source().channels);
    const std::string tmp = temporary_name(path);
    try {
        write_into_copy(source, tmp, frame, extra, options.clamp_half);
    } catch (...) {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw;
    }
    return tmp;
}

// Into mode: the frames must have come from EXR files, at the size they were read, and their
// channels must be able to go back (checked on the first frame, before any work).
void check_into(const Sequence& attributes, const Shape& shape, const WriteOptions& options, const FramePattern& pattern) {
    if (attributes.source().pattern.empty())
        throw Error(Status::InvalidArgument, "writing into copies of the input needs frames read from EXR files");
    if (options.tile_size > 0)
        throw Error(Status::InvalidArgument, "writing into copies of the input keeps each part's own tiling: "
                                             "a tile size does not apply");
    std::string ext = fs::path(pattern.text()).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext != ".exr")
        throw Error(Status::InvalidArgument, "output '" + pattern.text() + "': copies of EXR frames are EXR files (.exr)");
    const FrameMetadata& md = attributes.metadata().front();
    if (md.window.width != shape.width || md.window.height != shape.height)
        throw Error(Status::InvalidArgument, "the frames are not the size they were read at: they cannot go back into "
                                             "copies of their files");
    const std::string source = FramePattern(attributes.source().pattern).format(attributes.frame_numbers().front());
    IntoFrame frame;
    frame.window = md.window;
    frame.targets = locate_file_channels(source, attributes.source().channels);
    if (static_cast<int64_t>(frame.targets.size()) != shape.channels)
        throw Error(Status::InvalidArgument, "'" + source + "' gives " + std::to_string(frame.targets.size()) +
                                                 " channels for the " + std::to_string(shape.channels) + " of the output");
    check_into_source(source, frame);
}

// The EXR writer as a sink. Checked at construction, before any work: the pattern, compression,
// colour conversion, frame numbers, the directory (created when missing), that the output is not the
// input (unless overwrite), and that no other run writes it (a lock file beside the frames). Frames
// go to temporary files as they come; commit renames them all into place, so a failed or cancelled
// run leaves the previous frames as they were. Temporary files of dead runs are removed.
class ExrFrameSink final : public FrameSink {
public:
    ExrFrameSink(const std::string& pattern_text, const WriteOptions& options, const Sequence& attributes,
                 const OutputChecks& checks)
        : pattern_(pattern_text), options_(options), attributes_(attributes),
          shape_{attributes.shape().frames, checks.height, checks.width, attributes.shape().channels} {
        const int64_t frames = attributes.shape().frames;
        if (!pattern_.has_frame_token() && frames > 1)
            throw Error(Status::InvalidArgument, "output pattern '" + pattern_text +
                                                     "' has no frame token (#, @ or %0Nd) but the sequence has " +
                                                     std::to_string(frames) + " frames");
        check_compression(options.compression);
        if (options.tile_size < 0 || options.tile_size > 65536)
            throw Error(Status::InvalidArgument, "EXR tile size " + std::to_string(options.tile_size) +
                                                     " is out of range (0 = scanlines, or 1 to 65536 pixels)");
        std::vector<int64_t> numbers = attributes.frame_numbers();
        std::sort(numbers.begin(), numbers.end());
        if (std::adjacent_find(numbers.begin(), numbers.end()) != numbers.end())
            throw Error(Status::InvalidArgument, "frame number " +
                                                     std::to_string(*std::adjacent_find(numbers.begin(), numbers.end())) +
                                                     " appears twice: each frame needs its own file");
        check_color_conversion(options.color, shape_.channels);
        if (options.into && frames > 0) check_into(attributes, shape_, options, pattern_);
        for (int64_t f = 0; f < frames; ++f) paths_.push_back(pattern_.format(attributes.frame_numbers()[f]));
        // A file format the library can write (by the name's extension): found now, not after the work.
        if (!paths_.empty() && !OIIO::ImageOutput::create(paths_.front()))
            throw Error(Status::InvalidArgument, "output '" + paths_.front() + "': no writer for its file format (" +
                                                     fs::path(paths_.front()).extension().string() + "); use .exr, or .png for a picture");
        dir_ = fs::path(paths_.front()).parent_path();
        if (dir_.empty()) dir_ = ".";
        std::error_code ec;
        if (!fs::is_directory(dir_, ec)) {
            fs::create_directories(dir_, ec);  // as render outputs do; refused clearly when it cannot be
            if (ec || !fs::is_directory(dir_))
                throw Error(Status::Io, "output directory '" + dir_.string() + "' does not exist and cannot be created" +
                                            (ec ? ": " + ec.message() : std::string()));
        }
        if (::access(dir_.c_str(), W_OK) != 0)
            throw Error(Status::Io, "output directory '" + dir_.string() + "' is not writable");
        if (!checks.input_pattern.empty() && !checks.overwrite) refuse_input(checks.input_pattern);
        lock();
        remove_stale_temporaries();
        temporaries_.resize(paths_.size());
    }

    ~ExrFrameSink() override {
        std::error_code ec;
        for (const std::string& tmp : temporaries_)
            if (!tmp.empty()) fs::remove(tmp, ec);
        if (!lock_path_.empty()) fs::remove(lock_path_, ec);
    }

    void write_frame(int64_t f, const float* pixels) override {
        const size_t count = static_cast<size_t>(shape_.pixels() * shape_.channels);
        // A float copy only to convert the colours; a half file's values are rounded here, in one
        // pass (the library's own conversion allocates three half frames' worth per frame).
        std::vector<float> converted;
        const float* frame = pixels;
        if (options_.color.active()) {
            converted.assign(pixels, pixels + count);
            convert_colors(converted.data(), shape_.width, shape_.height, shape_.channels, options_.color);
            frame = converted.data();
        }
        std::vector<std::pair<std::string, std::string>> extra;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            extra = extra_;
        }
        const std::string& path = paths_[static_cast<size_t>(f)];
        std::string& tmp = temporaries_[static_cast<size_t>(f)];
        if (options_.into) {  // each channel in its file's type, checked there
            tmp = write_into_temporary(path, frame, attributes_, f, options_, extra);
        } else if (options_.half) {
            if (!options_.clamp_half) check_half_range(frame, count, attributes_, f);
            std::vector<uint16_t> halves(count);
            to_half(frame, count, options_.clamp_half, halves.data());
            tmp = write_temporary(path, halves.data(), attributes_, f, shape_, options_, extra);
        } else {
            tmp = write_temporary(path, frame, attributes_, f, shape_, options_, extra);
        }
    }

    void set_attribute(const std::string& name, const std::string& value) override {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& [n, v] : extra_)
            if (n == name) {
                v = value;
                return;
            }
        extra_.emplace_back(name, value);
    }

    void commit() override {
        for (size_t f = 0; f < paths_.size(); ++f)
            if (temporaries_[f].empty())
                throw Error(Status::Internal, "frame " + std::to_string(attributes_.frame_numbers()[f]) + " was never written");
        for (size_t f = 0; f < paths_.size(); ++f) {
            std::error_code ec;
            fs::rename(temporaries_[f], paths_[f], ec);
            if (ec) {
                std::string done = f == 0 ? "none" : "frames before " + std::to_string(attributes_.frame_numbers()[f]);
                throw Error(Status::Io, "cannot rename into '" + paths_[f] + "': " + ec.message() + " (" + done +
                                            " of this run are in place)");
            }
            temporaries_[f].clear();
        }
    }

private:
    void refuse_input(const std::string& input_pattern) const {
        const FramePattern input(input_pattern);
        for (size_t f = 0; f < paths_.size(); ++f) {
            const std::string in = input.format(attributes_.frame_numbers()[f]);
            std::error_code ec;
            if (paths_[f] == in || fs::equivalent(paths_[f], in, ec))
                throw Error(Status::InvalidArgument, "output '" + paths_[f] + "' is the input frame '" + in +
                                                         "': refusing to overwrite the input (give overwrite to replace it; "
                                                         "the new frames replace the old only once all are written)");
        }
    }

    // One writer per output sequence: a lock file beside the frames, holding the writer's pid. A lock
    // whose process is gone (killed) is taken over.
    void lock() {
        lock_path_ = (dir_ / ("." + fs::path(pattern_.text()).filename().string() + ".statfilter-lock")).string();
        for (int attempt = 0; attempt < 2; ++attempt) {
            const int fd = ::open(lock_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
            if (fd >= 0) {
                const std::string pid = std::to_string(::getpid()) + "\n";
                const bool ok = ::write(fd, pid.data(), pid.size()) == static_cast<ssize_t>(pid.size());
                ::close(fd);
                if (ok) return;
                break;
            }
            long owner = 0;
            if (FILE* f = std::fopen(lock_path_.c_str(), "r")) {
                if (std::fscanf(f, "%ld", &owner) != 1) owner = 0;
                std::fclose(f);
            }
            if (process_alive(owner)) {
                lock_path_.clear();
                throw Error(Status::Io, "output '" + pattern_.text() + "' is being written by another run (process " +
                                            std::to_string(owner) + ", lock file '" +
                                            (dir_ / ("." + fs::path(pattern_.text()).filename().string() +
                                                     ".statfilter-lock")).string() + "')");
            }
            std::error_code ec;
            fs::remove(lock_path_, ec);  // left by a run that died: take it over
        }
        const std::string path = lock_path_;
        lock_path_.clear();
        throw Error(Status::Io, "cannot create the lock file '" + path + "' for output '" + pattern_.text() + "'");
    }

    // Temporary frames of this sequence left by runs that died (kill -9, power loss).
    void remove_stale_temporaries() {
        std::set<std::string> names;
        for (const std::string& p : paths_) names.insert("." + fs::path(p).filename().string() + ".tmp");
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(dir_, ec)) {
            const std::string name = entry.path().filename().string();
            const size_t at = name.rfind(".tmp");
            if (at == std::string::npos || !names.count(name.substr(0, at + 4))) continue;
            const long owner = temporary_owner(name);
            if (owner > 0 && !process_alive(owner)) {
                std::error_code rm;
                if (fs::remove(entry.path(), rm)) ++stale_removed_;
            }
        }
    }

    FramePattern pattern_;
    WriteOptions options_;
    const Sequence& attributes_;
    Shape shape_;
    std::vector<std::string> paths_, temporaries_;
    fs::path dir_;
    std::string lock_path_;
    int64_t stale_removed_ = 0;
    std::mutex mutex_;
    std::vector<std::pair<std::string, std::string>> extra_;
};

}  // namespace

std::unique_ptr<FrameSink> open_frame_sink(const std::string& pattern, const WriteOptions& options,
                                           const Sequence& attributes, const OutputChecks& checks) {
    return std::make_unique<ExrFrameSink>(pattern, options, attributes, checks);
}

void write_sequence(const Sequence& seq, const std::string& pattern_text, const WriteOptions& options) {
    const Shape& s = seq.shape();
    Sequence attributes(Shape{s.frames, 1, 1, s.channels});
    attributes.copy_attributes_from(seq);
    OutputChecks checks;
    checks.width = s.width;
    checks.height = s.height;
    auto sink = open_frame_sink(pattern_text, options, attributes, checks);
    std::vector<float> frame(static_cast<size_t>(s.pixels() * s.channels));
    for (int64_t f = 0; f < s.frames; ++f) {
        options.progress.report(static_cast<double>(f) / s.frames, "write");
        seq.get_frame(f, frame.data());
        sink->write_frame(f, frame.data());
    }
    sink->commit();
    options.progress.report(1.0, "write");
}

}  // namespace statfilter
