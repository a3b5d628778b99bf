// Fuzz target: the sequence reader on arbitrary bytes. The bytes become a one-frame EXR file in a
// private temporary directory, read through the C ABI as the CLI and Python read it. Any status is
// fine; a crash, a sanitizer report or a hang is a finding.
#include <OpenImageIO/imageio.h>

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <statfilter/statfilter.h>

namespace {

// Frames beyond this many samples are refused up front: a header asking for gigabytes is the
// reader's memory check's business (tested elsewhere), not something a fuzzer can afford. So are
// rows wider than kMaxWidth: OpenImageIO's scanline read buffers ~1024 rows' bytes at once, so a
// 4194309 x 3 frame (12.6M samples) made it ask for 4 GiB, beyond the fuzzer's malloc limit.
constexpr int64_t kMaxSamples = int64_t{1} << 24;
constexpr int64_t kMaxWidth = int64_t{1} << 16;

std::string g_dir;

void remove_frame() {
    std::remove((g_dir + "/frame.0001.exr").c_str());
    rmdir(g_dir.c_str());
}

const std::string& frame_path() {
    static const std::string path = [] {
        std::string dir = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") + "/statfilter-fuzz-XXXXXX";
        if (!mkdtemp(dir.data())) std::abort();
        g_dir = dir;
        std::atexit(remove_frame);
        return dir + "/frame.0001.exr";
    }();
    return path;
}

bool small_enough(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return true;  // the reader must refuse it; let it
    int64_t samples = 0;
    for (int s = 0; in->seek_subimage(s, 0); ++s) {
        if (in->spec().width > kMaxWidth) return false;
        samples += int64_t{in->spec().width} * in->spec().height * std::max(1, in->spec().nchannels);
    }
    return samples <= kMaxSamples;
}

}  // namespace

// One thread for OpenImageIO and OpenEXR: a pool started per file costs more than the read.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
    OIIO::attribute("threads", 1);
    OIIO::attribute("exr_threads", 1);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string& path = frame_path();
    if (FILE* f = std::fopen(path.c_str(), "wb")) {
        if (size) std::fwrite(data, 1, size, f);
        std::fclose(f);
    } else {
        std::abort();
    }
    if (!small_enough(path)) return 0;
    sf_read_options options;
    sf_read_options_init(&options);
    options.frames = "1";
    const std::string pattern = path.substr(0, path.size() - 8) + "####.exr";
    sf_sequence seq = nullptr;
    if (sf_sequence_read(pattern.c_str(), &options, &seq) == SF_OK) {
        sf_shape shape{};
        sf_sequence_shape(seq, &shape);
        for (int64_t c = 0; c < shape.channels; ++c) {
            sf_channel_stats stats;
            sf_sequence_channel_stats(seq, c, &stats);
        }
        sf_sequence_release(seq);
    }
    return 0;
}
