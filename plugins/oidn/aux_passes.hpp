// The optional albedo and normal passes OIDN uses as guides, read through statfilter's own C ABI
// for exactly the frames being denoised.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include <statfilter/statfilter.h>

namespace statfilter_oidn {

struct PassError : std::runtime_error {
    PassError(sf_status s, const std::string& message) : std::runtime_error(message), status(s) {}
    sf_status status;
};

// `value` is a frame pattern (albedo.####.exr; its R,G,B or X,Y,Z channels, or its only three) or a
// layer of the input's own files (e.g. "ViewLayer.Denoising Albedo"). Returns frames x height x
// width x 3 contiguous floats. Throws PassError naming `what` and the files.
std::vector<float> read_pass(const sf_plugin_run& run, const std::string& what, const std::string& value);

}  // namespace statfilter_oidn
