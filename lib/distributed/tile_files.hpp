// The files tile tasks exchange through shared storage: a tile's partial statistics (each channel
// group's series count and F x F Gram), the reduction of them all (the same, plus each group's
// basis), a tile's rebuilt rows of every frame (float32, frame-major), and its rows of an image result. All written to a temporary
// beside the final name and renamed into place, so a reader never sees half a file.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "statfilter/sequence.hpp"
#include "statfilter/temporal_basis.hpp"

namespace statfilter {

struct GroupStatistics {
    int64_t series = 0;
    std::vector<double> gram;   // F x F
    TemporalBasis basis;        // the reduction's (frames == 0 in a partial)
};

struct TileStatistics {
    int64_t frames = 0;
    int64_t repaired = 0;       // non-finite samples repaired
    std::vector<GroupStatistics> groups;
};

void write_tile_statistics(const std::string& path, const TileStatistics& statistics);
TileStatistics read_tile_statistics(const std::string& path);
// Bytes of the file write_tile_statistics makes.
int64_t tile_statistics_bytes(const TileStatistics& statistics);

// Writes the whole file at `path` atomically: bytes go to a temporary (PATH.tmp-HOST-PID) and are
// renamed into place. Opening one removes the temporaries of `path` that dead processes of this
// host left (a killed task run again leaves nothing behind).
class AtomicFile {
public:
    explicit AtomicFile(const std::string& path);
    ~AtomicFile();  // removes the temporary unless committed
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;
    // Writes bytes at offset (thread-safe: positioned writes).
    void write_at(int64_t offset, const void* data, size_t bytes);
    void commit();

private:
    std::string path_, temporary_;
    int fd_ = -1;
};

// A directory made whole or not at all: files go into a temporary directory (PATH.tmp-HOST-PID, a
// dead process' of this host removed as AtomicFile's) that commit renames into place.
class AtomicDirectory {
public:
    explicit AtomicDirectory(const std::string& path);
    ~AtomicDirectory();  // removes the temporary unless committed
    AtomicDirectory(const AtomicDirectory&) = delete;
    AtomicDirectory& operator=(const AtomicDirectory&) = delete;
    const std::string& temporary() const { return temporary_; }
    // Replaces what is at path; returns the bytes of the files it holds.
    int64_t commit();

private:
    std::string path_, temporary_;
};

// Rows [y0, y1) of the first frame of an image result (a rank map) as the bytes of a file: its
// channel names, then its samples (float32, row-major); and such a file read back (one frame).
std::vector<char> image_rows_file(const Sequence& image, int64_t y0, int64_t y1);
std::unique_ptr<Sequence> read_image_rows_file(const std::string& path);

// Writes the whole file at path atomically (an AtomicFile written once and committed).
void write_file(const std::string& path, const void* data, size_t bytes);

// Reads `bytes` at `offset` of the file at path; names the file when it is missing or short.
void read_file_at(const std::string& path, int64_t offset, void* data, size_t bytes);

}  // namespace statfilter
