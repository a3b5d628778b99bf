#include "pipeline/scratch_frames.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "pipeline/positioned_io.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

const char kWhat[] = "scratch file for frames between stages";
const char kHint[] = " (set TMPDIR to a disk with room)";

}  // namespace

ScratchFrames::ScratchFrames(const Shape& shape, const Sequence& attributes)
    : shape_(shape), attributes_(Shape{shape.frames, 1, 1, shape.channels}) {
    attributes_.copy_attributes_from(attributes);
    const char* dir = std::getenv("TMPDIR");
    std::string path = std::string(dir && *dir ? dir : "/tmp") + "/statfilter-scratch-XXXXXX";
    std::vector<char> name(path.begin(), path.end());
    name.push_back('\0');
    fd_ = ::mkstemp(name.data());
    if (fd_ < 0) throw Error(Status::Io, "cannot create a scratch file in '" + path.substr(0, path.rfind('/')) + "': " + std::strerror(errno));
    ::unlink(name.data());  // gone with the descriptor, whatever happens to the process
}

ScratchFrames::~ScratchFrames() {
    if (fd_ >= 0) ::close(fd_);
}

void ScratchFrames::read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const {
    const int64_t row = shape_.width * shape_.channels * static_cast<int64_t>(sizeof(float));
    read_at(fd_, dst, static_cast<size_t>((y1 - y0) * row), (f * shape_.height + y0) * row, kWhat, kHint);
    if (gain_.empty()) return;
    const int64_t count = (y1 - y0) * shape_.width;
    for (int64_t p = 0; p < count; ++p)
        for (int64_t c = 0; c < shape_.channels; ++c) dst[p * shape_.channels + c] *= gain_[static_cast<size_t>(c)];
}

void ScratchFrames::write_frame(int64_t f, const float* pixels) { write_rows(f, 0, shape_.height, pixels); }

void ScratchFrames::write_rows(int64_t f, int64_t y0, int64_t y1, const float* rows) {
    const int64_t row = shape_.width * shape_.channels * static_cast<int64_t>(sizeof(float));
    write_at(fd_, rows, static_cast<size_t>((y1 - y0) * row), (f * shape_.height + y0) * row, kWhat, kHint);
}

}  // namespace statfilter
