// Filtered channels back into a copy of their EXR frame, through OpenEXR itself: OpenImageIO would
// re-encode every part and rewrite the headers in its own terms, where a pipeline expects the parts
// it did not ask to change to come out exactly as they went in.
#include "statfilter/exr_into.hpp"

#include <ImfChannelList.h>
#include <ImfDeepScanLineInputPart.h>
#include <ImfDeepScanLineOutputPart.h>
#include <ImfDeepTiledInputPart.h>
#include <ImfDeepTiledOutputPart.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfMultiPartInputFile.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfStringAttribute.h>
#include <ImfTiledInputPart.h>
#include <ImfTiledOutputPart.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "statfilter/error.hpp"
#include "statfilter/half_samples.hpp"

namespace statfilter {
namespace {

// A part's type; single-part files written before multi-part EXR carry none.
std::string part_type(const Imf::Header& header) {
    if (header.hasType()) return header.type();
    return header.hasTileDescription() ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE;
}

std::string part_text(const Imf::MultiPartInputFile& in, int part) {
    if (in.parts() == 1) return "";
    const Imf::Header& h = in.header(part);
    return " part " + std::to_string(part) + (h.hasName() ? " ('" + h.name() + "')" : std::string());
}

std::vector<std::vector<size_t>> channels_by_part(const IntoFrame& frame, int parts, const std::string& source) {
    std::vector<std::vector<size_t>> by_part(static_cast<size_t>(parts));
    for (size_t c = 0; c < frame.targets.size(); ++c) {
        const int p = frame.targets[c].part;
        if (p < 0 || p >= parts)
            throw Error(Status::InvalidArgument, "'" + source + "' has no part " + std::to_string(p) + " for channel '" +
                                                     frame.targets[c].name + "'");
        by_part[static_cast<size_t>(p)].push_back(c);
    }
    return by_part;
}

void check_part(const Imf::MultiPartInputFile& in, int p, const std::vector<size_t>& mine, const IntoFrame& frame,
                const std::string& source) {
    const Imf::Header& h = in.header(p);
    const std::string where = "'" + source + "'" + part_text(in, p);
    const std::string type = part_type(h);
    if (type != Imf::SCANLINEIMAGE && type != Imf::TILEDIMAGE)
        throw Error(Status::Unsupported, "cannot write filtered channels into " + where + ": it is a deep part");
    if (type == Imf::TILEDIMAGE && h.tileDescription().mode != Imf::ONE_LEVEL)
        throw Error(Status::Unsupported, "cannot write filtered channels into " + where +
                                             ": it holds mip or rip levels, which would no longer match");
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it)
        if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
            throw Error(Status::Unsupported, "cannot write filtered channels into " + where + ": its channel '" +
                                                 std::string(it.name()) + "' is subsampled");
    for (size_t c : mine)
        if (!h.channels().findChannel(frame.targets[c].name))
            throw Error(Status::NotFound, where + " has no channel '" + frame.targets[c].name + "'");
    const Imath::Box2i dw = h.dataWindow();
    const PixelWindow& w = frame.window;
    if (dw.min.x < w.x || dw.min.y < w.y || dw.max.x >= w.x + w.width || dw.max.y >= w.y + w.height)
        throw Error(Status::InvalidArgument, where + "'s data window lies outside the frame that was filtered");
}

void copy_part(Imf::MultiPartInputFile& in, Imf::MultiPartOutputFile& out, int p) {
    const std::string type = part_type(in.header(p));
    if (type == Imf::TILEDIMAGE) {
        Imf::TiledInputPart from(in, p);
        Imf::TiledOutputPart(out, p).copyPixels(from);
    } else if (type == Imf::DEEPSCANLINE) {
        Imf::DeepScanLineInputPart from(in, p);
        Imf::DeepScanLineOutputPart(out, p).copyPixels(from);
    } else if (type == Imf::DEEPTILE) {
        Imf::DeepTiledInputPart from(in, p);
        Imf::DeepTiledOutputPart(out, p).copyPixels(from);
    } else {
        Imf::InputPart from(in, p);
        Imf::OutputPart(out, p).copyPixels(from);
    }
}

// One channel of a part, in the file's own pixel type.
struct ChannelBuffer {
    std::string name;
    Imf::PixelType type;
    std::vector<char> data;
    size_t size() const { return type == Imf::HALF ? 2 : 4; }
};

void store(ChannelBuffer& buffer, size_t i, float v, bool clamp_half, const std::string& what) {
    char* at = buffer.data.data() + i * buffer.size();
    if (buffer.type == Imf::FLOAT) {
        std::memcpy(at, &v, sizeof v);
    } else if (buffer.type == Imf::HALF) {
        if (!clamp_half && std::isfinite(v) && std::fabs(v) > kHalfMax)
            throw Error(Status::Numeric, what + ": value " + std::to_string(v) +
                                             " exceeds half's range (65504): clamp it, or store the channel as float");
        to_half(&v, 1, clamp_half, reinterpret_cast<uint16_t*>(at));
    } else {  // UINT: rounded and held in its range
        const double d = std::isfinite(v) ? std::round(static_cast<double>(v)) : 0.0;
        const auto u = static_cast<uint32_t>(std::clamp(d, 0.0, 4294967295.0));
        std::memcpy(at, &u, sizeof u);
    }
}

// All of a one-level part through the frame buffer set on it: every tile, or every scanline.
void read_all(Imf::TiledInputPart& part) { part.readTiles(0, part.numXTiles(0) - 1, 0, part.numYTiles(0) - 1); }
void write_all(Imf::TiledOutputPart& part) { part.writeTiles(0, part.numXTiles(0) - 1, 0, part.numYTiles(0) - 1); }
void read_all(Imf::InputPart& part) {
    const Imath::Box2i dw = part.header().dataWindow();
    part.readPixels(dw.min.y, dw.max.y);
}
void write_all(Imf::OutputPart& part) {
    const Imath::Box2i dw = part.header().dataWindow();
    part.writePixels(dw.max.y - dw.min.y + 1);
}

// Reads every channel of part p, puts the frame's channels in, writes it: the other channels of the
// part stay as they were. The parts are OpenEXR's tiled or scanline ones, as the part is stored.
template <class InputPart, class OutputPart>
void rewrite_part(Imf::MultiPartInputFile& in, Imf::MultiPartOutputFile& out, int p, const std::vector<size_t>& mine,
                  const IntoFrame& frame, bool clamp_half, const std::string& destination) {
    const Imf::Header& h = in.header(p);
    const Imath::Box2i dw = h.dataWindow();
    const int64_t width = int64_t{dw.max.x} - dw.min.x + 1, height = int64_t{dw.max.y} - dw.min.y + 1;
    const auto pixels = static_cast<size_t>(width * height);
    std::vector<ChannelBuffer> buffers;
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it) buffers.push_back({it.name(), it.channel().type, {}});
    Imf::FrameBuffer fb;
    for (ChannelBuffer& b : buffers) {
        b.data.resize(pixels * b.size());
        fb.insert(b.name, Imf::Slice::Make(b.type, b.data.data(), dw, b.size(), b.size() * static_cast<size_t>(width)));
    }
    {
        InputPart from(in, p);
        from.setFrameBuffer(fb);
        read_all(from);
    }

    const PixelWindow& w = frame.window;
    const auto channels = static_cast<int64_t>(frame.targets.size());
    for (size_t c : mine) {
        ChannelBuffer& b = *std::find_if(buffers.begin(), buffers.end(),
                                         [&](const ChannelBuffer& x) { return x.name == frame.targets[c].name; });
        const std::string what = "'" + destination + "' channel '" + b.name + "'";
        for (int64_t y = 0; y < height; ++y)
            for (int64_t x = 0; x < width; ++x) {
                const int64_t fx = dw.min.x + x - w.x, fy = dw.min.y + y - w.y;
                store(b, static_cast<size_t>(y * width + x), frame.pixels[(fy * w.width + fx) * channels + static_cast<int64_t>(c)],
                      clamp_half, what + " pixel (" + std::to_string(dw.min.x + x) + ", " + std::to_string(dw.min.y + y) + ")");
            }
    }

    OutputPart to(out, p);
    to.setFrameBuffer(fb);
    write_all(to);
}

template <class Work>
void with_exr_errors(const std::string& what, Work&& work) {
    try {
        work();
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(Status::Io, what + ": " + e.what());
    }
}

}  // namespace

void check_into_source(const std::string& source, const IntoFrame& frame) {
    with_exr_errors("cannot read '" + source + "' to write into a copy of it", [&] {
        Imf::MultiPartInputFile in(source.c_str());
        const auto by_part = channels_by_part(frame, in.parts(), source);
        for (int p = 0; p < in.parts(); ++p)
            if (!by_part[static_cast<size_t>(p)].empty()) check_part(in, p, by_part[static_cast<size_t>(p)], frame, source);
    });
}

void write_into_copy(const std::string& source, const std::string& destination, const IntoFrame& frame,
                     const std::vector<std::pair<std::string, std::string>>& attributes, bool clamp_half) {
    with_exr_errors("cannot write '" + destination + "' as a copy of '" + source + "'", [&] {
        Imf::MultiPartInputFile in(source.c_str());
        const int parts = in.parts();
        const auto by_part = channels_by_part(frame, parts, source);
        std::vector<Imf::Header> headers;
        for (int p = 0; p < parts; ++p) {
            headers.push_back(in.header(p));
            if (by_part[static_cast<size_t>(p)].empty()) continue;
            check_part(in, p, by_part[static_cast<size_t>(p)], frame, source);
            for (const auto& [name, value] : attributes) headers.back().insert(name, Imf::StringAttribute(value));
        }
        Imf::MultiPartOutputFile out(destination.c_str(), headers.data(), parts);
        for (int p = 0; p < parts; ++p) {
            const std::vector<size_t>& mine = by_part[static_cast<size_t>(p)];
            if (mine.empty())
                copy_part(in, out, p);
            else if (part_type(in.header(p)) == Imf::TILEDIMAGE)
                rewrite_part<Imf::TiledInputPart, Imf::TiledOutputPart>(in, out, p, mine, frame, clamp_half, destination);
            else
                rewrite_part<Imf::InputPart, Imf::OutputPart>(in, out, p, mine, frame, clamp_half, destination);
        }
    });
}

}  // namespace statfilter
