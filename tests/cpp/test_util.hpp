// Helpers shared by the C++ tests: temporary directories, listing and damaging files, the shared
// render data. Standard library only, so the C ABI test can use it without seeing the core.
// EXR writing through OpenImageIO lives in exr_util.hpp (for the core's tests).
#pragma once
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace statfilter_test {

namespace fs = std::filesystem;

// A fresh, empty directory removed (with everything in it) when the object goes away.
class TempDir {
public:
    TempDir() {
        std::string templ = (fs::temp_directory_path() / "statfilter-test-XXXXXX").string();
        if (!::mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed: " + std::string(std::strerror(errno)));
        path_ = templ;
    }
    ~TempDir() {
        std::error_code ec;
        // A test may have made a directory read-only; give permissions back before removing.
        for (auto it = fs::recursive_directory_iterator(path_, ec); !ec && it != fs::recursive_directory_iterator();
             it.increment(ec))
            fs::permissions(it->path(), fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const fs::path& path() const { return path_; }
    // A path (file or pattern) inside the directory, as text for the APIs under test.
    std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    fs::path path_;
};

// Every entry of a directory, hidden ones (temporary files) included, sorted by name.
inline std::vector<std::string> files_in(const fs::path& dir) {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

inline void write_text_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + path);
}

// Cuts a file to half its size (a render interrupted mid-write, a broken copy).
inline void truncate_to_half(const std::string& path) {
    fs::resize_file(path, fs::file_size(path) / 2);
}

inline bool running_as_root() { return ::geteuid() == 0; }

// The real renders from $STATFILTER_SHARED_DATA, or an empty path when absent (tests then skip).
inline fs::path shared_data_dir() {
    const char* dir = std::getenv("STATFILTER_SHARED_DATA");
    std::error_code ec;
    if (!dir || !*dir || !fs::is_directory(dir, ec)) return {};
    return dir;
}

// A deterministic test value for sample (f, y, x, c): distinct everywhere, sign changes included.
inline float sample_value(int64_t f, int64_t y, int64_t x, int64_t c) {
    return static_cast<float>(f * 1000 + y * 100 + x * 10 + c) * 0.25f - 7.0f;
}

// Bit pattern of a float, so comparisons can be exact even for NaN and -0.
inline uint32_t float_bits(float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    return bits;
}

}  // namespace statfilter_test
