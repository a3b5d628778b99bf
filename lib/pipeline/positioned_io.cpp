#include "pipeline/positioned_io.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "statfilter/error.hpp"

namespace statfilter {
namespace {

void transfer(int fd, char* data, size_t bytes, int64_t offset, bool write, const std::string& what, const std::string& hint) {
    while (bytes > 0) {
        const ssize_t n = write ? ::pwrite(fd, data, bytes, static_cast<off_t>(offset))
                                : ::pread(fd, data, bytes, static_cast<off_t>(offset));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw Error(Status::Io, what + ": " + (n < 0 ? std::strerror(errno) : "unexpected end of file") + hint);
        data += n;
        bytes -= static_cast<size_t>(n);
        offset += n;
    }
}

}  // namespace

void read_at(int fd, void* data, size_t bytes, int64_t offset, const std::string& what, const std::string& hint) {
    transfer(fd, static_cast<char*>(data), bytes, offset, false, what, hint);
}

void write_at(int fd, const void* data, size_t bytes, int64_t offset, const std::string& what, const std::string& hint) {
    // pwrite does not write through its pointer; the one loop serves both directions.
    transfer(fd, const_cast<char*>(static_cast<const char*>(data)), bytes, offset, true, what, hint);
}

}  // namespace statfilter
