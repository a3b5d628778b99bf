// Writing and inspecting EXR files with OpenImageIO directly, independent of statfilter's own I/O,
// so the core's reader is tested against files it did not write (including Blender-style
// multi-part files).
#pragma once
#include <OpenImageIO/imageio.h>

#include <stdexcept>
#include <utility>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace statfilter_test {

// One part (OIIO subimage) of an EXR file: interleaved pixels, width * height * channels.size().
struct ExrPart {
    std::string name;
    std::vector<std::string> channels;
    std::vector<float> pixels;  // of the data window
    // The part's data window inside the file's display window (width x height at 0, 0); a width of
    // 0 = the whole display window.
    int x = 0, y = 0, data_width = 0, data_height = 0;
    std::vector<std::pair<std::string, std::string>> attributes = {};  // header attributes, as text
    std::string compression = "";  // empty = the file's
};

// Pixels of a frame of the given size, from sample_value() shifted by `offset`.
inline std::vector<float> make_pixels(int width, int height, int channels, int64_t frame, float offset = 0) {
    std::vector<float> px;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c) px.push_back(sample_value(frame, y, x, c) + offset);
    return px;
}

// Writes a single- or multi-part EXR of width x height pixels.
inline void write_exr(const std::string& path, int width, int height, const std::vector<ExrPart>& parts,
                      OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT, const std::string& compression = "zip") {
    std::vector<OIIO::ImageSpec> specs;
    for (const ExrPart& part : parts) {
        const int w = part.data_width ? part.data_width : width, h = part.data_width ? part.data_height : height;
        if (part.pixels.size() != static_cast<size_t>(w) * h * part.channels.size())
            throw std::runtime_error("write_exr: pixel count does not match the part's size");
        OIIO::ImageSpec spec(w, h, static_cast<int>(part.channels.size()), type);
        spec.x = part.x;
        spec.y = part.y;
        spec.full_x = spec.full_y = 0;
        spec.full_width = width;
        spec.full_height = height;
        for (const auto& [name, value] : part.attributes) spec.attribute(name, value);
        spec.channelnames = part.channels;
        spec.alpha_channel = -1;
        spec.attribute("compression", part.compression.empty() ? compression : part.compression);
        if (!part.name.empty()) spec.attribute("oiio:subimagename", part.name);
        specs.push_back(spec);
    }
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw std::runtime_error("write_exr: " + OIIO::geterror());
    bool ok = out->open(path, static_cast<int>(specs.size()), specs.data());
    for (size_t i = 0; ok && i < parts.size(); ++i) {
        if (i > 0) ok = out->open(path, specs[i], OIIO::ImageOutput::AppendSubimage);
        ok = ok && out->write_image(OIIO::TypeDesc::FLOAT, parts[i].pixels.data());
    }
    ok = out->close() && ok;
    if (!ok) throw std::runtime_error("write_exr '" + path + "': " + out->geterror());
}

// Single-part shorthand.
inline void write_exr(const std::string& path, int width, int height, const std::vector<std::string>& channels,
                      const std::vector<float>& pixels, OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT) {
    write_exr(path, width, height, {ExrPart{"", channels, pixels}}, type);
}

struct ExrImage {
    OIIO::ImageSpec spec;
    std::vector<float> pixels;  // interleaved, as float
};

// Reads one part of a file with OIIO, all channels converted to float.
inline ExrImage read_exr(const std::string& path, int subimage = 0) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw std::runtime_error("read_exr: " + OIIO::geterror());
    if (!in->seek_subimage(subimage, 0)) throw std::runtime_error("read_exr: no subimage in " + path);
    ExrImage image;
    image.spec = in->spec();
    image.pixels.resize(image.spec.image_pixels() * image.spec.nchannels);
    if (!in->read_image(subimage, 0, 0, image.spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
        throw std::runtime_error("read_exr '" + path + "': " + in->geterror());
    return image;
}

}  // namespace statfilter_test
