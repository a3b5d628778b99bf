#include "statfilter/color_convert.hpp"

#include <OpenColorIO/OpenColorIO.h>

#include "statfilter/error.hpp"

namespace OCIO = OCIO_NAMESPACE;

namespace statfilter {
namespace {

OCIO::ConstCPUProcessorRcPtr make_processor(const ColorConversion& conv) {
    if (conv.from.empty() || conv.to.empty())
        throw Error(Status::InvalidArgument, "colour conversion needs both an input and an output colour space");
    try {
        OCIO::ConstConfigRcPtr config =
            conv.config.empty() ? OCIO::GetCurrentConfig() : OCIO::Config::CreateFromFile(conv.config.c_str());
        return config->getProcessor(conv.from.c_str(), conv.to.c_str())->getDefaultCPUProcessor();
    } catch (const OCIO::Exception& e) {
        throw Error(Status::InvalidArgument, std::string("OpenColorIO: ") + e.what());
    }
}

}  // namespace

void check_color_conversion(const ColorConversion& conv, int64_t channels) {
    if (!conv.active()) return;
    if (channels != 3 && channels != 4)
        throw Error(Status::Unsupported, "colour conversion needs 3 (RGB) or 4 (RGBA) channels, got " +
                                             std::to_string(channels));
    make_processor(conv);
}

void convert_colors(float* pixels, int64_t width, int64_t height, int64_t channels, const ColorConversion& conv) {
    if (!conv.active()) return;
    check_color_conversion(conv, channels);
    auto processor = make_processor(conv);
    try {
        OCIO::PackedImageDesc desc(pixels, width, height, channels);
        processor->apply(desc);
    } catch (const OCIO::Exception& e) {
        throw Error(Status::Internal, std::string("OpenColorIO: ") + e.what());
    }
}

}  // namespace statfilter
