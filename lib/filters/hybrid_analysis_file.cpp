#include "filters/hybrid_analysis_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "pipeline/positioned_io.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

std::string in(const std::string& dir, const std::string& name) { return dir + "/" + name; }

void write_bytes(const std::string& path, const void* data, size_t bytes, std::ios::openmode mode = std::ios::trunc) {
    std::ofstream out(path, std::ios::binary | mode);
    if (out && bytes > 0) out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
    out.close();  // a failure to flush counts too (a full disk)
    if (out.fail()) throw Error(Status::Io, "cannot write '" + path + "' (is the disk full?)");
}

std::string read_all(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw Error(Status::Io, "'" + path + "' is not there: run the task that makes it first");
    std::ostringstream text;
    text << file.rdbuf();
    return text.str();
}

template <class T>
void write_vector(const std::string& path, const std::vector<T>& v) {
    write_bytes(path, v.data(), v.size() * sizeof(T));
}

template <class T>
std::vector<T> read_vector(const std::string& path, size_t count) {
    const std::string bytes = read_all(path);
    if (bytes.size() != count * sizeof(T))
        throw Error(Status::InvalidArgument, "'" + path + "' holds " + std::to_string(bytes.size()) + " bytes, not " +
                                                 std::to_string(count * sizeof(T)));
    std::vector<T> v(count);
    if (count > 0) std::memcpy(v.data(), bytes.data(), bytes.size());
    return v;
}

template <class T>
std::string json_list(const std::vector<T>& v) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + json_number(static_cast<double>(v[i]));
    return s + "]";
}

std::vector<double> numbers(const JsonValue& v) {
    std::vector<double> out;
    for (const JsonValue& x : v.array()) out.push_back(x.number());
    return out;
}

struct JsonFile {
    std::string path;
    JsonValue json;
    explicit JsonFile(const std::string& p) : path(p), json(parse(p)) {}
    static JsonValue parse(const std::string& p) {
        try {
            return parse_json(read_all(p));
        } catch (const Error& e) {
            if (e.status() == Status::Io) throw;
            throw Error(Status::InvalidArgument, "'" + p + "': " + e.what());
        }
    }
    const JsonValue& operator[](const char* key) const {
        const JsonValue* v = json.find(key);
        if (!v) throw Error(Status::InvalidArgument, "'" + path + "' has no '" + key + "'");
        return *v;
    }
};

void check_shape(const JsonFile& file, const Shape& s) {
    const auto& shape = file["shape"].array();
    if (shape.size() != 4 || shape[0].number() != s.frames || shape[1].number() != s.height ||
        shape[2].number() != s.width || shape[3].number() != s.channels)
        throw Error(Status::InvalidArgument, "'" + file.path + "' was made for another shot's shape");
}

std::string shape_json(const Shape& s) {
    return "[" + std::to_string(s.frames) + ", " + std::to_string(s.height) + ", " + std::to_string(s.width) + ", " +
           std::to_string(s.channels) + "]";
}

// Frames [begin, begin + count) of a shape, float32 frame after frame, read from a file as asked.
class FileFrames final : public FrameSource {
public:
    FileFrames(const std::string& path, const Shape& shape, const Sequence& attributes, int64_t begin, int64_t count)
        : path_(path), shape_(shape), attributes_(Shape{shape.frames, 1, 1, shape.channels}), begin_(begin), count_(count) {
        attributes_.copy_attributes_from(attributes);
        fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd_ < 0) throw Error(Status::Io, "'" + path + "' is not there: run the task that makes it first");
        const off_t size = ::lseek(fd_, 0, SEEK_END);
        const int64_t expected = count * frame_bytes();
        if (size != expected) {
            ::close(fd_);
            throw Error(Status::InvalidArgument, "'" + path + "' holds " + std::to_string(size) + " bytes, not the " +
                                                     std::to_string(expected) + " of its frames");
        }
    }
    ~FileFrames() override { ::close(fd_); }
    FileFrames(const FileFrames&) = delete;
    FileFrames& operator=(const FileFrames&) = delete;
    const Shape& shape() const override { return shape_; }
    const Sequence& attributes() const override { return attributes_; }
    bool holds(int64_t f) const { return f >= begin_ && f < begin_ + count_; }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override {
        const int64_t row = shape_.width * shape_.channels * static_cast<int64_t>(sizeof(float));
        read_at(fd_, dst, static_cast<size_t>((y1 - y0) * row), ((f - begin_) * shape_.height + y0) * row,
                "cannot read '" + path_ + "'");
    }

private:
    int64_t frame_bytes() const { return shape_.pixels() * shape_.channels * static_cast<int64_t>(sizeof(float)); }
    std::string path_;
    Shape shape_;
    Sequence attributes_;
    int64_t begin_, count_;
    int fd_ = -1;
};

// The shot's frames from the chunks' files that hold them.
class ChunkedFrames final : public FrameSource {
public:
    ChunkedFrames(const Shape& shape, const Sequence& attributes) : shape_(shape), attributes_(Shape{shape.frames, 1, 1, shape.channels}) {
        attributes_.copy_attributes_from(attributes);
    }
    void add(std::unique_ptr<FileFrames> chunk) { chunks_.push_back(std::move(chunk)); }
    const Shape& shape() const override { return shape_; }
    const Sequence& attributes() const override { return attributes_; }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override {
        for (const auto& c : chunks_)
            if (c->holds(f)) return c->read_rows(f, y0, y1, dst);
        throw Error(Status::InvalidArgument, "no chunk of first passes holds frame index " + std::to_string(f));
    }

private:
    Shape shape_;
    Sequence attributes_;
    std::vector<std::unique_ptr<FileFrames>> chunks_;
};

// Every frame of `frames` into path.
void save_frames(const FrameSource& frames, const Shape& s, const std::string& path) {
    std::vector<float> frame(static_cast<size_t>(s.pixels() * s.channels));
    write_bytes(path, nullptr, 0);
    for (int64_t f = 0; f < s.frames; ++f) {
        frames.read_rows(f, 0, s.height, frame.data());
        write_bytes(path, frame.data(), frame.size() * sizeof(float), std::ios::app);
    }
}

constexpr size_t kFireflyBytes = 2 * sizeof(int64_t) + sizeof(float);

}  // namespace

void save_hybrid_passes(const HybridAnalysis& a, const Shape& s, const std::string& dir, const std::string& extra) {
    save_frames(*a.temporal, s, in(dir, "temporal.f32"));
    write_vector(in(dir, "grown.f32"), a.grown);
    write_vector(in(dir, "crossings.f32"), a.crossings);
    std::vector<char> fireflies;
    for (size_t f = 0; f < a.fireflies.size(); ++f)
        for (const auto& [index, value] : a.fireflies[f]) {
            const int64_t fields[] = {static_cast<int64_t>(f), index};
            fireflies.insert(fireflies.end(), reinterpret_cast<const char*>(fields), reinterpret_cast<const char*>(fields) + sizeof fields);
            fireflies.insert(fireflies.end(), reinterpret_cast<const char*>(&value), reinterpret_cast<const char*>(&value) + sizeof value);
        }
    write_vector(in(dir, "fireflies.bin"), fireflies);
    std::ostringstream json;
    json << "{\n  \"format\": \"statfilter-hybrid-passes\",\n  \"version\": 1,\n  \"shape\": " << shape_json(s) << ",\n";
    json << "  \"still\": " << (a.still ? "true" : "false") << ",\n  \"grown_pixels\": " << a.grown.size()
         << ",\n  \"crossing_pixels\": " << a.crossings.size() << ",\n  \"fireflies\": " << fireflies.size() / kFireflyBytes;
    if (a.change) {
        const TemporalChangeModel m = a.change->model();
        write_vector(in(dir, "change_sigma.f64"), m.sigma);
        write_vector(in(dir, "change_centre.f64"), m.centre);
        write_vector(in(dir, "change_departures.u32"), m.departures);
        write_vector(in(dir, "change_gain.f64"), m.gain);  // binary: a level may be non-finite
        json << ",\n  \"change\": {\"unit\": " << json_number(m.unit) << ", \"floor\": " << json_number(m.floor)
             << ", \"gain_frames\": " << m.gain.size() << "}";
    }
    if (!extra.empty()) json << ",\n  " << extra;
    json << "\n}\n";
    const std::string text = json.str();
    write_bytes(in(dir, "analysis.json"), text.data(), text.size());
}

HybridAnalysis load_hybrid_passes(const Shape& s, const Sequence& attributes, const TemporalChangeOptions& change,
                                  const std::string& dir, JsonValue* json_out) {
    const JsonFile json(in(dir, "analysis.json"));
    check_shape(json, s);
    HybridAnalysis a;
    a.still = json["still"].boolean();
    a.held.push_back(std::make_unique<FileFrames>(in(dir, "temporal.f32"), s, attributes, 0, s.frames));
    a.temporal = a.held.back().get();
    a.grown = read_vector<float>(in(dir, "grown.f32"), static_cast<size_t>(json["grown_pixels"].number()));
    a.crossings = read_vector<float>(in(dir, "crossings.f32"), static_cast<size_t>(json["crossing_pixels"].number()));
    const auto P = static_cast<size_t>(s.pixels());
    if ((!a.still && a.grown.size() != P) || (!a.crossings.empty() && a.crossings.size() != P))
        throw Error(Status::InvalidArgument, "'" + json.path + "': its maps are not one value a pixel of the shot");
    const auto fireflies = read_vector<char>(in(dir, "fireflies.bin"), static_cast<size_t>(json["fireflies"].number()) * kFireflyBytes);
    a.fireflies.resize(a.still ? 0 : static_cast<size_t>(s.frames));
    for (size_t at = 0; at < fireflies.size(); at += kFireflyBytes) {
        int64_t fields[2] = {};
        float value = 0;
        std::memcpy(fields, fireflies.data() + at, sizeof fields);
        std::memcpy(&value, fireflies.data() + at + sizeof fields, sizeof value);
        if (fields[0] < 0 || fields[0] >= s.frames || fields[1] < 0 || fields[1] >= s.pixels() * s.channels)
            throw Error(Status::InvalidArgument, "'" + in(dir, "fireflies.bin") + "' names a sample outside the shot");
        if (a.fireflies.empty()) a.fireflies.resize(static_cast<size_t>(s.frames));
        a.fireflies[static_cast<size_t>(fields[0])].emplace_back(fields[1], value);
    }
    if (const JsonValue* c = json.json.find("change")) {
        TemporalChangeModel m;
        m.sigma = read_vector<double>(in(dir, "change_sigma.f64"), P);
        m.centre = read_vector<double>(in(dir, "change_centre.f64"), P);
        m.departures = read_vector<uint32_t>(in(dir, "change_departures.u32"), P);
        const auto number = [&](const char* key) {
            const JsonValue* v = c->find(key);
            if (!v || !v->is(JsonValue::Type::Number)) throw Error(Status::InvalidArgument, "'" + json.path + "': the change test has no '" + key + "'");
            return v->number();
        };
        m.unit = number("unit");
        m.floor = number("floor");
        m.gain = read_vector<double>(in(dir, "change_gain.f64"), static_cast<size_t>(number("gain_frames")));
        a.change = TemporalChange::from_model(s, change, std::move(m));
    }
    if (json_out) *json_out = json.json;
    return a;
}

JsonValue hybrid_passes_json(const std::string& dir) { return JsonFile(in(dir, "analysis.json")).json; }

FirstPassFiles::FirstPassFiles(const std::string& dir, const Shape& s, int64_t begin, int64_t end)
    : dir_(dir), begin_(begin), end_(end), frame_bytes_(s.pixels() * s.channels * static_cast<int64_t>(sizeof(float))) {
    const std::string path = in(dir, "first.f32");
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) throw Error(Status::Io, "cannot create '" + path + "': " + std::strerror(errno));
}

FirstPassFiles::~FirstPassFiles() {
    if (fd_ >= 0) ::close(fd_);
}

void FirstPassFiles::write(int64_t frame, const float* pixels) {
    write_at(fd_, pixels, static_cast<size_t>(frame_bytes_), (frame - begin_) * frame_bytes_,
             "cannot write '" + in(dir_, "first.f32") + "'");
}

void FirstPassFiles::finish(const HybridAnalysis& a) {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) throw Error(Status::Io, "cannot write '" + in(dir_, "first.f32") + "': " + std::strerror(errno));
    const auto part = [&](const auto& v) {
        using T = typename std::decay_t<decltype(v)>::value_type;
        return json_list(std::vector<T>(v.begin() + begin_, v.begin() + end_));
    };
    std::ostringstream json;
    json << "{\n  \"format\": \"statfilter-hybrid-first-pass\",\n  \"version\": 1,\n  \"frames\": [" << begin_ << ", " << end_
         << "],\n  \"sums\": " << part(a.first_sums) << ",\n  \"still_levels\": " << part(a.still_levels)
         << ",\n  \"own_counts\": " << part(a.own_counts) << "\n}\n";
    const std::string text = json.str();
    write_bytes(in(dir_, "first.json"), text.data(), text.size());
}

void load_first_passes(const Shape& s, const Sequence& attributes, const std::vector<WindowedFiles::Chunk>& chunks,
                       HybridAnalysis& a) {
    auto frames = std::make_unique<ChunkedFrames>(s, attributes);
    const auto F = static_cast<size_t>(s.frames);
    a.first_sums.assign(F, 0.0);
    a.still_levels.assign(F, 0.0);
    a.own_counts.assign(F, 0);
    for (const WindowedFiles::Chunk& c : chunks) {
        const JsonFile json(in(c.dir, "first.json"));
        const auto range = numbers(json["frames"]);
        const auto sums = numbers(json["sums"]), levels = numbers(json["still_levels"]), counts = numbers(json["own_counts"]);
        const int64_t n = c.end - c.begin;
        if (range.size() != 2 || range[0] != c.begin || range[1] != c.end || static_cast<int64_t>(sums.size()) != n ||
            levels.size() != sums.size() || counts.size() != sums.size())
            throw Error(Status::InvalidArgument, "'" + json.path + "' does not hold frames " + std::to_string(c.begin) +
                                                     " to " + std::to_string(c.end - 1));
        for (int64_t i = 0; i < n; ++i) {
            a.first_sums[static_cast<size_t>(c.begin + i)] = sums[static_cast<size_t>(i)];
            a.still_levels[static_cast<size_t>(c.begin + i)] = levels[static_cast<size_t>(i)];
            a.own_counts[static_cast<size_t>(c.begin + i)] = static_cast<int64_t>(counts[static_cast<size_t>(i)]);
        }
        frames->add(std::make_unique<FileFrames>(in(c.dir, "first.f32"), s, attributes, c.begin, n));
    }
    a.first_pass = frames.get();
    a.held.push_back(std::move(frames));
}

void save_guides(const HybridAnalysis& a, const Shape& s, const std::string& dir) {
    save_frames(*a.guides, s, in(dir, "guides.f32"));
    std::ostringstream json;
    json << "{\n  \"format\": \"statfilter-hybrid-guides\",\n  \"version\": 1,\n  \"shape\": " << shape_json(s)
         << ",\n  \"guide_scale\": " << json_number(a.guide_scale) << ",\n  \"frame_gain\": " << json_list(a.frame_gain)
         << "\n}\n";
    const std::string text = json.str();
    write_bytes(in(dir, "guides.json"), text.data(), text.size());
}

void load_guides(const Shape& s, const Sequence& attributes, const std::string& dir, HybridAnalysis& a) {
    const JsonFile json(in(dir, "guides.json"));
    check_shape(json, s);
    a.guide_scale = json["guide_scale"].number();
    a.frame_gain = numbers(json["frame_gain"]);
    a.held.push_back(std::make_unique<FileFrames>(in(dir, "guides.f32"), s, attributes, 0, s.frames));
    a.guides = a.held.back().get();
}

}  // namespace statfilter
