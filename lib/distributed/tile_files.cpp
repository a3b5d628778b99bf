#include "distributed/tile_files.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "pipeline/positioned_io.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

namespace fs = std::filesystem;
constexpr char kMagic[8] = {'S', 'F', 'S', 'T', 'A', 'T', 'S', '1'};
constexpr char kRowsMagic[8] = {'S', 'F', 'I', 'R', 'O', 'W', 'S', '1'};

std::string system_error(const std::string& what, const std::string& path) {
    return what + " '" + path + "': " + std::strerror(errno);
}

std::string host_name() {
    char host[256] = {};
    if (::gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
    return host;
}

// The temporary is named by host and process: two nodes running the same task never share one.
std::string temporary_name(const std::string& path) { return path + ".tmp-" + host_name() + "-" + std::to_string(::getpid()); }

// Temporaries of `path` that processes of this host left when they died (a task killed, as a farm
// preempts one): the task run again removes them. Another host's are left alone (whether their
// process is alive cannot be told from here), as is any whose process is alive.
void remove_stale_temporaries(const std::string& path) {
    const fs::path p(path);
    const std::string prefix = p.filename().string() + ".tmp-" + host_name() + "-";
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(p.parent_path().empty() ? fs::path(".") : p.parent_path(), ec)) {
        const std::string name = entry.path().filename().string();
        if (name.compare(0, prefix.size(), prefix) != 0) continue;
        char* end = nullptr;
        const long pid = std::strtol(name.c_str() + prefix.size(), &end, 10);
        if (pid <= 0 || !end || *end != '\0' || pid == ::getpid()) continue;
        if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
            std::error_code rm;
            fs::remove_all(entry.path(), rm);  // a file, or an AtomicDirectory's directory
        }
    }
}

}  // namespace

AtomicFile::AtomicFile(const std::string& path) : path_(path), temporary_(temporary_name(path)) {
    remove_stale_temporaries(path);
    fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd_ < 0) throw Error(Status::Io, system_error("cannot create", temporary_));
}

AtomicDirectory::AtomicDirectory(const std::string& path) : path_(path), temporary_(temporary_name(path)) {
    remove_stale_temporaries(path);
    std::error_code ec;
    fs::remove_all(temporary_, ec);
    if (!fs::create_directories(temporary_, ec) || ec) throw Error(Status::Io, "cannot create the directory '" + temporary_ + "': " + ec.message());
}

AtomicDirectory::~AtomicDirectory() {
    std::error_code ec;
    if (!temporary_.empty()) fs::remove_all(temporary_, ec);
}

int64_t AtomicDirectory::commit() {
    int64_t bytes = 0;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(temporary_, ec))
        if (entry.is_regular_file(ec)) bytes += static_cast<int64_t>(entry.file_size(ec));
    // A finished run's directory there (this task run again, perhaps while later tasks read it):
    // the two are swapped in one step, so a reader sees the old one or the new one whole, and the
    // old one, now under the temporary's name, goes after. A plain rename when there is none.
    if (::renameat2(AT_FDCWD, temporary_.c_str(), AT_FDCWD, path_.c_str(), RENAME_EXCHANGE) == 0) {
        fs::remove_all(temporary_, ec);
    } else if (errno == ENOENT || errno == EINVAL || errno == ENOSYS) {
        // None there; or a file system that cannot swap (then the old one goes first: killed between
        // the two, the task leaves none, and the tasks after it say so).
        if (errno != ENOENT) fs::remove_all(path_, ec);
        if (::rename(temporary_.c_str(), path_.c_str()) != 0) throw Error(Status::Io, system_error("cannot rename into", path_));
    } else {
        throw Error(Status::Io, system_error("cannot put the finished directory in place of", path_));
    }
    temporary_.clear();
    return bytes;
}

AtomicFile::~AtomicFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!temporary_.empty()) ::unlink(temporary_.c_str());
}

void AtomicFile::write_at(int64_t offset, const void* data, size_t bytes) {
    statfilter::write_at(fd_, data, bytes, offset, "cannot write '" + temporary_ + "'");
}

void AtomicFile::commit() {
    if (::close(fd_) != 0) {
        fd_ = -1;
        throw Error(Status::Io, system_error("cannot write", temporary_));
    }
    fd_ = -1;
    if (::rename(temporary_.c_str(), path_.c_str()) != 0) throw Error(Status::Io, system_error("cannot rename into", path_));
    temporary_.clear();
}

void write_file(const std::string& path, const void* data, size_t bytes) {
    AtomicFile file(path);
    file.write_at(0, data, bytes);
    file.commit();
}

void read_file_at(const std::string& path, int64_t offset, void* data, size_t bytes) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) throw Error(Status::Io, system_error("cannot open", path) + " (has the task that writes it run?)");
    try {
        read_at(fd, data, bytes, offset, "cannot read '" + path + "' at byte " + std::to_string(offset));
    } catch (...) {
        ::close(fd);
        throw;
    }
    ::close(fd);
}

namespace {

// A whole file read at once, taken apart front to back; names the file when it is short.
class WholeFile {
public:
    WholeFile(const std::string& path, const char* kind) : path_(path), kind_(kind) {
        std::error_code ec;
        const auto size = fs::file_size(path, ec);
        if (ec) throw Error(Status::Io, "cannot read '" + path + "': " + ec.message() + " (has the task that writes it run?)");
        bytes_.resize(static_cast<size_t>(size));
        read_file_at(path, 0, bytes_.data(), bytes_.size());
    }
    void take(void* p, size_t n) {
        if (at_ + n > bytes_.size()) throw Error(Status::Io, "'" + path_ + "' is truncated or not a " + kind_ + " file");
        std::memcpy(p, bytes_.data() + at_, n);
        at_ += n;
    }
    int64_t take64() {
        int64_t v = 0;
        take(&v, 8);
        return v;
    }
    size_t left() const { return bytes_.size() - at_; }

private:
    std::string path_, kind_;
    std::vector<char> bytes_;
    size_t at_ = 0;
};

}  // namespace

int64_t tile_statistics_bytes(const TileStatistics& s) {
    int64_t bytes = 8 + 3 * 8;
    for (const GroupStatistics& g : s.groups)
        bytes += 2 * 8 + static_cast<int64_t>(g.gram.size() + g.basis.eigenvalues.size() + g.basis.vectors.size()) * 8;
    return bytes;
}

void write_tile_statistics(const std::string& path, const TileStatistics& s) {
    std::vector<char> out;
    auto put = [&](const void* p, size_t n) { out.insert(out.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n); };
    auto put64 = [&](int64_t v) { put(&v, 8); };
    put(kMagic, 8);
    put64(s.frames);
    put64(s.repaired);
    put64(static_cast<int64_t>(s.groups.size()));
    const auto FF = static_cast<size_t>(s.frames * s.frames);
    for (const GroupStatistics& g : s.groups) {
        if (g.gram.size() != FF) throw Error(Status::Internal, "a Gram of the wrong size for '" + path + "'");
        put64(g.series);
        put64(g.basis.frames);
        put(g.gram.data(), FF * 8);
        if (g.basis.frames) {
            put(g.basis.eigenvalues.data(), static_cast<size_t>(s.frames) * 8);
            put(g.basis.vectors.data(), FF * 8);
        }
    }
    write_file(path, out.data(), out.size());
}

TileStatistics read_tile_statistics(const std::string& path) {
    WholeFile file(path, "statistics");
    const auto take = [&](void* p, size_t n) { file.take(p, n); };
    const auto take64 = [&] { return file.take64(); };
    char magic[8];
    take(magic, 8);
    if (std::memcmp(magic, kMagic, 8) != 0) throw Error(Status::Io, "'" + path + "' is not a statfilter statistics file");
    TileStatistics s;
    s.frames = take64();
    s.repaired = take64();
    const int64_t groups = take64();
    if (s.frames <= 0 || s.frames > (1 << 20) || groups <= 0 || groups > (1 << 16))
        throw Error(Status::Io, "'" + path + "' has a bad header");
    const auto FF = static_cast<size_t>(s.frames * s.frames);
    for (int64_t i = 0; i < groups; ++i) {
        GroupStatistics g;
        g.series = take64();
        g.basis.frames = take64();
        g.gram.resize(FF);
        take(g.gram.data(), FF * 8);
        if (g.basis.frames) {
            g.basis.series = g.series;
            g.basis.eigenvalues.resize(static_cast<size_t>(s.frames));
            g.basis.vectors.resize(FF);
            take(g.basis.eigenvalues.data(), static_cast<size_t>(s.frames) * 8);
            take(g.basis.vectors.data(), FF * 8);
        }
        s.groups.push_back(std::move(g));
    }
    return s;
}

std::vector<char> image_rows_file(const Sequence& image, int64_t y0, int64_t y1) {
    const Shape& s = image.shape();
    if (!(0 <= y0 && y0 < y1 && y1 <= s.height)) throw Error(Status::Internal, "rows out of the image");
    std::vector<char> out;
    auto put = [&](const void* p, size_t n) { out.insert(out.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n); };
    auto put64 = [&](int64_t v) { put(&v, 8); };
    put(kRowsMagic, 8);
    put64(y1 - y0);
    put64(s.width);
    put64(s.channels);
    for (const std::string& name : image.channel_names()) {
        put64(static_cast<int64_t>(name.size()));
        put(name.data(), name.size());
    }
    for (int64_t y = y0; y < y1; ++y)
        for (int64_t x = 0; x < s.width; ++x)
            for (int64_t c = 0; c < s.channels; ++c) {
                const float v = image.at(0, y, x, c);
                put(&v, sizeof v);
            }
    return out;
}

std::unique_ptr<Sequence> read_image_rows_file(const std::string& path) {
    WholeFile file(path, "image rows");
    char magic[8];
    file.take(magic, 8);
    if (std::memcmp(magic, kRowsMagic, 8) != 0) throw Error(Status::Io, "'" + path + "' is not a statfilter image rows file");
    const int64_t rows = file.take64(), width = file.take64(), channels = file.take64();
    if (rows <= 0 || width <= 0 || channels <= 0 || channels > (1 << 16) ||
        static_cast<double>(rows) * static_cast<double>(width) * static_cast<double>(channels) * 4 > static_cast<double>(file.left()))
        throw Error(Status::Io, "'" + path + "' has a bad header");
    auto image = std::make_unique<Sequence>(Shape{1, rows, width, channels});
    for (int64_t c = 0; c < channels; ++c) {
        const int64_t length = file.take64();
        if (length < 0 || static_cast<size_t>(length) > file.left()) throw Error(Status::Io, "'" + path + "' has a bad channel name");
        std::string name(static_cast<size_t>(length), '\0');
        file.take(name.data(), name.size());
        image->channel_names()[static_cast<size_t>(c)] = name;
    }
    for (int64_t y = 0; y < rows; ++y)
        for (int64_t x = 0; x < width; ++x)
            for (int64_t c = 0; c < channels; ++c) file.take(&image->at(0, y, x, c), sizeof(float));
    if (file.left() != 0) throw Error(Status::Io, "'" + path + "' is longer than its header says");
    return image;
}

}  // namespace statfilter
