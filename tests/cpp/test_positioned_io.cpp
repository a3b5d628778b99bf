// Whole-range positioned reads and writes: what is written at an offset reads back, a range past the
// end of the file is an error naming it (not a short read taken for data), and a bad descriptor says
// the system's reason.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "pipeline/positioned_io.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

struct ScratchFile {
    ScratchFile() {
        char name[] = "/tmp/statfilter-positioned-io-XXXXXX";
        fd = ::mkstemp(name);
        if (fd >= 0) ::unlink(name);
    }
    ~ScratchFile() {
        if (fd >= 0) ::close(fd);
    }
    int fd = -1;
};

std::string message_of(void (*call)(int), int fd) {
    try {
        call(fd);
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Io);
        return e.what();
    }
    return "";
}

TEST(PositionedIo, WhatIsWrittenAtAnOffsetReadsBack) {
    ScratchFile file;
    ASSERT_GE(file.fd, 0);
    std::vector<float> out(100000);
    for (size_t i = 0; i < out.size(); ++i) out[i] = static_cast<float>(i) * 0.5f;
    const int64_t offset = 4096 + 12;
    write_at(file.fd, out.data(), out.size() * sizeof(float), offset, "test file");
    std::vector<float> in(out.size(), -1.0f);
    read_at(file.fd, in.data(), in.size() * sizeof(float), offset, "test file");
    EXPECT_EQ(in, out);
    float first = -1;
    read_at(file.fd, &first, sizeof first, 0, "test file");  // the gap before the offset reads as zeros
    EXPECT_EQ(first, 0.0f);
}

TEST(PositionedIo, ARangePastTheEndIsAnErrorNamingTheFile) {
    ScratchFile file;
    ASSERT_GE(file.fd, 0);
    const char bytes[10] = {};
    write_at(file.fd, bytes, sizeof bytes, 0, "test file");
    const std::string message = message_of(
        [](int fd) {
            char buffer[20];
            read_at(fd, buffer, sizeof buffer, 0, "cannot read 'partial-3.bin'", " (rerun its task)");
        },
        file.fd);
    EXPECT_EQ(message, "cannot read 'partial-3.bin': unexpected end of file (rerun its task)");
}

TEST(PositionedIo, ABadDescriptorGivesTheSystemsReason) {
    const std::string message = message_of(
        [](int fd) {
            const float value = 1;
            write_at(fd, &value, sizeof value, 0, "cannot write 'first.f32'");
        },
        -1);
    EXPECT_EQ(message.rfind("cannot write 'first.f32': ", 0), 0u) << message;
    EXPECT_GT(message.size(), std::string("cannot write 'first.f32': ").size());
}

}  // namespace
}  // namespace statfilter
