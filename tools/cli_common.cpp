#include "cli_common.hpp"

#include <cctype>
#include <cstdlib>

namespace statfilter_cli {

void check(sf_status status) {
    if (status != SF_OK) throw Failure(sf_last_error());
}

sf_shape SequenceHandle::shape() const {
    sf_shape s{};
    statfilter_cli::check(sf_sequence_shape(handle_, &s));
    return s;
}

std::string SequenceHandle::channel_name(int64_t c) const {
    const char* name = nullptr;
    statfilter_cli::check(sf_sequence_channel_name(handle_, c, &name));
    return name;
}

FilterHandle::FilterHandle(const std::string& name) { statfilter_cli::check(sf_filter_create(name.c_str(), &handle_)); }

void FilterHandle::check(sf_status status) const {
    if (status != SF_OK) throw Failure(sf_filter_last_error(handle_));
}

const std::set<std::string> kInputOptions = {"channels", "frames", "ocio", "in-colorspace", "working-colorspace"};
const std::set<std::string> kOutputOptions = {"compression", "out-colorspace", "tiled"};

const char* const kInputHelp =
    "input:\n"
    "  --channels LIST         channels and/or layers, e.g. R,G,B or \"ViewLayer.Diffuse Indirect\";\n"
    "                          several layers keep their full names; * = every channel of every part\n"
    "                          (default: a file without layers whole, else its light passes only:\n"
    "                          no Normal, Albedo, *Color, Depth/Z, Vector, Alpha/A, Denoising*, ...;\n"
    "                          'statfilter info' shows what the default takes)\n"
    "  --frames SPEC           frames to use, e.g. 1-48 or 1-10,12 (default: all on disk, no gaps)\n"
    "  --ocio CONFIG           OpenColorIO config (default: $OCIO)\n"
    "  --in-colorspace NAME    colour space of the input files ...\n"
    "  --working-colorspace NAME  ... converted to this one for filtering\n";

const char* const kOutputHelp =
    "output:\n"
    "  --float                 write 32-bit float (default: half)\n"
    "  --clamp-half            clamp values beyond half's range instead of failing\n"
    "  --compression NAME      EXR compression: zip (default), none, piz, dwaa, ...\n"
    "  --tiled N               write N x N tiles (default: scanlines)\n"
    "  --out-colorspace NAME   convert from the working space to this one on write\n"
    "                          (default: --in-colorspace)\n";

// --tiled N: a whole number of pixels (the library checks the range).
static int tile_size(const std::string& text) {
    char* end = nullptr;
    const long n = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || n < 0 || n > 65536)
        throw UsageError("--tiled '" + text + "': give the tile size in pixels, e.g. --tiled 64");
    return static_cast<int>(n);
}

static const char* nullable(const std::string& s) { return s.empty() ? nullptr : s.c_str(); }

IoSettings::IoSettings(const Args& args)
    : channels_(args.option("channels")), frames_(args.option("frames")), ocio_(args.option("ocio")),
      in_cs_(args.option("in-colorspace")), work_cs_(args.option("working-colorspace")),
      out_cs_(args.option("out-colorspace", args.option("in-colorspace"))), compression_(args.option("compression", "zip")) {
    sf_read_options_init(&read);
    read.channels = nullable(channels_);
    read.frames = nullable(frames_);
    read.ocio_config = nullable(ocio_);
    sf_write_options_init(&write);
    write.pixel_type = args.flag("float") ? SF_PIXEL_FLOAT : SF_PIXEL_HALF;
    write.half_overflow = args.flag("clamp-half") ? 1 : 0;
    write.tile_size = tile_size(args.option("tiled", "0"));
    write.compression = compression_.c_str();
    write.ocio_config = nullable(ocio_);
    if (!work_cs_.empty()) {  // convert into the working space on read and back on write
        read.colorspace_in = nullable(in_cs_);
        read.colorspace_out = nullable(work_cs_);
        write.colorspace_in = nullable(work_cs_);
        write.colorspace_out = nullable(out_cs_);
    }
}

void read_input(const Args& args, const std::string& pattern, ProgressLine& progress, SequenceHandle& out) {
    IoSettings io(args);
    io.read.progress = &ProgressLine::callback;
    io.read.progress_user = &progress;
    check(sf_sequence_read(pattern.c_str(), &io.read, out.out()));
}

void check_exr_output(const std::string& pattern) {
    const std::string ext = pattern.size() >= 4 ? pattern.substr(pattern.size() - 4) : "";
    std::string lower;
    for (char c : ext) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower != ".exr")
        throw UsageError("output '" + pattern + "' is not an .exr file: frames are written as EXR only (another "
                         "format would lose the HDR values); false-colour PNG previews are what --save and the "
                         "--*-preview options write");
}

void write_output(const Args& args, const SequenceHandle& seq, const std::string& pattern, ProgressLine& progress) {
    check_exr_output(pattern);
    IoSettings io(args);
    io.write.progress = &ProgressLine::callback;
    io.write.progress_user = &progress;
    check(sf_sequence_write(seq.get(), pattern.c_str(), &io.write));
}

std::set<std::string> merged(std::initializer_list<std::set<std::string>> sets) {
    std::set<std::string> out;
    for (const auto& s : sets) out.insert(s.begin(), s.end());
    return out;
}

std::string frame_list_text(const std::vector<int64_t>& frames) {
    std::string out;
    for (size_t i = 0; i < frames.size();) {
        size_t j = i;
        while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
        if (!out.empty()) out += ",";
        out += std::to_string(frames[i]);
        if (j > i) out += "-" + std::to_string(frames[j]);
        i = j + 1;
    }
    return out;
}

}  // namespace statfilter_cli
