#include "filters/hybrid_analysis_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "statfilter/error.hpp"

namespace statfilter {
namespace {

constexpr const char* kFrameFiles[] = {"temporal.f32", "first_pass.f32", "guides.f32"};

std::string path_in(const std::string& dir, const std::string& name) { return dir + "/" + name; }

void write_bytes(const std::string& path, const void* data, size_t bytes, std::ios::openmode mode = std::ios::trunc) {
    std::ofstream out(path, std::ios::binary | mode);
    if (out) out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
    if (!out) throw Error(Status::Io, "cannot write '" + path + "': " + std::strerror(errno));
}

std::string read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(Status::Io, "the analysis file '" + path + "' is not there: run the analysis task first");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// Frames of a shape, frame after frame as float32, read from a file as they are asked for.
class FileFrames final : public FrameSource {
public:
    FileFrames(const std::string& path, const Shape& shape, const Sequence& attributes)
        : path_(path), shape_(shape), attributes_(Shape{shape.frames, 1, 1, shape.channels}) {
        attributes_.copy_attributes_from(attributes);
        fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd_ < 0) throw Error(Status::Io, "the analysis file '" + path + "' is not there: run the analysis task first");
        const off_t size = ::lseek(fd_, 0, SEEK_END);
        const double expected = static_cast<double>(shape.frames) * shape.pixels() * shape.channels * sizeof(float);
        if (static_cast<double>(size) != expected) {
            ::close(fd_);
            throw Error(Status::InvalidArgument, "'" + path + "' holds " + std::to_string(size) + " bytes, not the " +
                                                     std::to_string(static_cast<int64_t>(expected)) + " of the shot's frames");
        }
    }
    ~FileFrames() override { ::close(fd_); }
    FileFrames(const FileFrames&) = delete;
    FileFrames& operator=(const FileFrames&) = delete;
    const Shape& shape() const override { return shape_; }
    const Sequence& attributes() const override { return attributes_; }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override {
        const int64_t row = shape_.width * shape_.channels * static_cast<int64_t>(sizeof(float));
        auto* data = reinterpret_cast<char*>(dst);
        size_t bytes = static_cast<size_t>((y1 - y0) * row);
        off_t offset = static_cast<off_t>((f * shape_.height + y0) * row);
        while (bytes > 0) {
            const ssize_t n = ::pread(fd_, data, bytes, offset);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) throw Error(Status::Io, "cannot read '" + path_ + "': " + (n < 0 ? std::strerror(errno) : "short file"));
            data += n;
            bytes -= static_cast<size_t>(n);
            offset += n;
        }
    }

private:
    std::string path_;
    Shape shape_;
    Sequence attributes_;
    int fd_ = -1;
};

}  // namespace

void save_hybrid_analysis(const HybridAnalysis& a, const Shape& s, const std::string& dir, const std::string& extra) {
    const FrameSource* frames[] = {a.temporal, a.first_pass, a.guides};
    const size_t frame_samples = static_cast<size_t>(s.pixels() * s.channels);
    std::vector<float> frame(frame_samples);
    for (size_t k = 0; k < 3; ++k) {
        if (!frames[k]) continue;
        const std::string path = path_in(dir, kFrameFiles[k]);
        write_bytes(path, nullptr, 0);
        for (int64_t f = 0; f < s.frames; ++f) {
            frames[k]->read_rows(f, 0, s.height, frame.data());
            write_bytes(path, frame.data(), frame_samples * sizeof(float), std::ios::app);
        }
    }
    write_bytes(path_in(dir, "grown.f32"), a.grown.data(), a.grown.size() * sizeof(float));
    std::vector<char> fireflies;
    for (size_t f = 0; f < a.fireflies.size(); ++f)
        for (const auto& [index, value] : a.fireflies[f]) {
            const int64_t frame_index = static_cast<int64_t>(f);
            for (const void* field : {static_cast<const void*>(&frame_index), static_cast<const void*>(&index)})
                fireflies.insert(fireflies.end(), static_cast<const char*>(field), static_cast<const char*>(field) + sizeof(int64_t));
            fireflies.insert(fireflies.end(), reinterpret_cast<const char*>(&value), reinterpret_cast<const char*>(&value) + sizeof(float));
        }
    write_bytes(path_in(dir, "fireflies.bin"), fireflies.data(), fireflies.size());
    std::ostringstream json;
    json << "{\n  \"format\": \"statfilter-hybrid-analysis\",\n  \"version\": 1,\n";
    json << "  \"shape\": [" << s.frames << ", " << s.height << ", " << s.width << ", " << s.channels << "],\n";
    json << "  \"still\": " << (a.still ? "true" : "false") << ",\n  \"frames\": [";
    for (size_t k = 0; k < 3; ++k) json << (k ? ", " : "") << (frames[k] ? json_quote(kFrameFiles[k]) : "null");
    json << "],\n  \"guide_scale\": " << json_number(a.guide_scale) << ",\n  \"frame_gain\": [";
    for (size_t f = 0; f < a.frame_gain.size(); ++f) json << (f ? ", " : "") << json_number(a.frame_gain[f]);
    json << "],\n  \"grown_pixels\": " << a.grown.size() << ",\n  \"fireflies\": " << fireflies.size() / 20;
    if (!extra.empty()) json << ",\n  " << extra;
    json << "\n}\n";
    const std::string text = json.str();
    write_bytes(path_in(dir, "analysis.json"), text.data(), text.size());
}

HybridAnalysis load_hybrid_analysis(const Shape& s, const Sequence& attributes, const std::string& dir, JsonValue* json_out) {
    const std::string json_path = path_in(dir, "analysis.json");
    const JsonValue json = parse_json(read_all(json_path));
    const auto member = [&](const char* key) -> const JsonValue& {
        const JsonValue* v = json.find(key);
        if (!v) throw Error(Status::InvalidArgument, "'" + json_path + "' has no '" + key + "'");
        return *v;
    };
    const auto& shape = member("shape").array();
    if (shape.size() != 4 || shape[0].number() != s.frames || shape[1].number() != s.height ||
        shape[2].number() != s.width || shape[3].number() != s.channels)
        throw Error(Status::InvalidArgument, "'" + json_path + "' was made for another shot's shape");
    HybridAnalysis a;
    a.still = member("still").boolean();
    a.guide_scale = member("guide_scale").number();
    for (const JsonValue& v : member("frame_gain").array()) a.frame_gain.push_back(v.number());
    const FrameSource** frames[] = {&a.temporal, &a.first_pass, &a.guides};
    const auto& names = member("frames").array();
    for (size_t k = 0; k < 3 && k < names.size(); ++k)
        if (names[k].is(JsonValue::Type::String)) {
            a.held.push_back(std::make_unique<FileFrames>(path_in(dir, names[k].string()), s, attributes));
            *frames[k] = a.held.back().get();
        }
    const std::string grown = read_all(path_in(dir, "grown.f32"));
    if (grown.size() != static_cast<size_t>(member("grown_pixels").number()) * sizeof(float))
        throw Error(Status::InvalidArgument, "'" + path_in(dir, "grown.f32") + "' is not the size analysis.json says");
    a.grown.resize(grown.size() / sizeof(float));
    std::memcpy(a.grown.data(), grown.data(), grown.size());
    const std::string fireflies = read_all(path_in(dir, "fireflies.bin"));
    if (fireflies.size() != static_cast<size_t>(member("fireflies").number()) * 20)
        throw Error(Status::InvalidArgument, "'" + path_in(dir, "fireflies.bin") + "' is not the size analysis.json says");
    a.fireflies.resize(a.still ? 0 : static_cast<size_t>(s.frames));
    for (size_t at = 0; at + 20 <= fireflies.size(); at += 20) {
        int64_t frame = 0, index = 0;
        float value = 0;
        std::memcpy(&frame, fireflies.data() + at, sizeof frame);
        std::memcpy(&index, fireflies.data() + at + 8, sizeof index);
        std::memcpy(&value, fireflies.data() + at + 16, sizeof value);
        if (frame < 0 || frame >= s.frames || index < 0 || index >= s.pixels() * s.channels)
            throw Error(Status::InvalidArgument, "'" + path_in(dir, "fireflies.bin") + "' names a sample outside the shot");
        if (a.fireflies.empty()) a.fireflies.resize(static_cast<size_t>(s.frames));
        a.fireflies[static_cast<size_t>(frame)].emplace_back(index, value);
    }
    if (json_out) *json_out = json;
    return a;
}

}  // namespace statfilter
