// Positioned reads and writes of a whole range: pread and pwrite may move fewer bytes than asked
// (and be interrupted), so every file of frames, partials and first passes goes through these.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace statfilter {

// Reads `bytes` at `offset` of `fd`, or throws Error(Status::Io) saying "<what>: <reason><hint>";
// the reason is the system's, or "unexpected end of file" for a file shorter than the range.
void read_at(int fd, void* data, size_t bytes, int64_t offset, const std::string& what, const std::string& hint = "");

// Writes `bytes` at `offset` of `fd`; the same error.
void write_at(int fd, const void* data, size_t bytes, int64_t offset, const std::string& what, const std::string& hint = "");

}  // namespace statfilter
