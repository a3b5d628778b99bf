// Writes a frame sequence as EXR (or any format OIIO writes by extension). Everything that can be
// checked is checked before the first file is touched; each frame is written to a temporary file in
// the target directory and renamed into place, so no half-written frame is ever visible.
#include <OpenImageIO/imageio.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "statfilter/color_convert.hpp"
#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/sequence_io.hpp"

namespace fs = std::filesystem;

namespace statfilter {
namespace {

constexpr float kHalfMax = 65504.0f;

void check_compression(const std::string& compression) {
    static const char* known[] = {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};
    const std::string base = compression.substr(0, compression.find(':'));
    for (const char* k : known)
        if (base == k) return;
    throw Error(Status::InvalidArgument, "unknown EXR compression '" + compression +
                                             "' (none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab)");
}

void check_directory(const std::string& path) {
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw Error(Status::Io, "output directory '" + dir.string() + "' does not exist");
    if (::access(dir.c_str(), W_OK) != 0) throw Error(Status::Io, "output directory '" + dir.string() + "' is not writable");
}

// Finite values beyond half's range would become Inf: refuse, or clamp when asked.
void check_half_range(const std::vector<float>& frame, const Sequence& seq, int64_t f) {
    for (size_t i = 0; i < frame.size(); ++i) {
        const float v = frame[i];
        if (std::isfinite(v) && std::fabs(v) > kHalfMax) {
            const int64_t c = static_cast<int64_t>(i) % seq.shape().channels;
            throw Error(Status::Numeric, "frame " + std::to_string(seq.frame_numbers()[f]) + " channel '" +
                                             seq.channel_names()[c] + "' holds " + std::to_string(v) +
                                             ", beyond half float's range (65504): write float, or clamp");
        }
    }
}

std::string temporary_name(const std::string& final_path) {
    static std::atomic<unsigned> counter{0};
    const fs::path p(final_path);
    const std::string tmp = "." + p.filename().string() + ".tmp" + std::to_string(::getpid()) + "_" +
                            std::to_string(counter++) + p.extension().string();
    return (p.parent_path() / tmp).string();
}

void write_frame(const std::string& path, const std::vector<float>& pixels, const Sequence& seq, int64_t f,
                 const WriteOptions& options) {
    const Shape& s = seq.shape();
    OIIO::ImageSpec spec(static_cast<int>(s.width), static_cast<int>(s.height), static_cast<int>(s.channels),
                         options.half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    spec.channelnames = seq.channel_names();
    spec.alpha_channel = -1;
    for (int64_t c = 0; c < s.channels; ++c)
        if (seq.channel_names()[c] == "A") spec.alpha_channel = static_cast<int>(c);
    for (const auto& p : seq.metadata()[f]) spec.attribute(p.name().string(), p.type(), p.data());
    spec.attribute("compression", options.compression);

    const std::string tmp = temporary_name(path);
    auto out = OIIO::ImageOutput::create(tmp);
    if (!out) throw Error(Status::Io, "cannot write '" + path + "': " + OIIO::geterror());
    bool ok = out->open(tmp, spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
    ok = out->close() && ok;
    std::string why = out->geterror();
    out.reset();
    std::error_code ec;
    if (ok) fs::rename(tmp, path, ec);
    if (!ok || ec) {
        fs::remove(tmp, ec);
        throw Error(Status::Io, "cannot write '" + path + "': " + (why.empty() ? std::string("rename failed") : why));
    }
}

}  // namespace

void write_sequence(const Sequence& seq, const std::string& pattern_text, const WriteOptions& options) {
    const FramePattern pattern(pattern_text);
    const Shape& s = seq.shape();
    if (!pattern.has_frame_token() && s.frames > 1)
        throw Error(Status::InvalidArgument, "output pattern '" + pattern_text + "' has no frame token (#, @ or %0Nd) but the sequence has " +
                                                 std::to_string(s.frames) + " frames");
    check_compression(options.compression);
    std::vector<int64_t> numbers = seq.frame_numbers();
    std::sort(numbers.begin(), numbers.end());
    if (std::adjacent_find(numbers.begin(), numbers.end()) != numbers.end())
        throw Error(Status::InvalidArgument, "frame number " + std::to_string(*std::adjacent_find(numbers.begin(), numbers.end())) +
                                                 " appears twice: each frame needs its own file");
    check_color_conversion(options.color, s.channels);
    check_directory(pattern.format(seq.frame_numbers().front()));

    std::vector<float> frame(static_cast<size_t>(s.pixels() * s.channels));
    auto prepare = [&](int64_t f) {
        seq.get_frame(f, frame.data());
        convert_colors(frame.data(), s.width, s.height, s.channels, options.color);
        if (options.half && options.clamp_half)
            for (float& v : frame)
                if (std::isfinite(v)) v = std::max(-kHalfMax, std::min(kHalfMax, v));
    };
    // Range check over every frame first, so a bad value late in the sequence writes nothing at all.
    if (options.half && !options.clamp_half)
        for (int64_t f = 0; f < s.frames; ++f) {
            prepare(f);
            check_half_range(frame, seq, f);
        }
    for (int64_t f = 0; f < s.frames; ++f) {
        options.progress.report(static_cast<double>(f) / s.frames, "write");
        prepare(f);
        write_frame(pattern.format(seq.frame_numbers()[f]), frame, seq, f, options);
    }
    options.progress.report(1.0, "write");
}

}  // namespace statfilter
