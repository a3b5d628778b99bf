// The oidn filter plugin: Intel Open Image Denoise's "RT" filter on every frame, HDR colour with
// optional albedo and normal guides. A single-frame filter, so it can be any temporal filter's
// prefilter (statfilter denoise IN OUT --method pca --prefilter oidn).
#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include <statfilter/statfilter_plugin.h>

#include "aux_passes.hpp"
#include "oidn_library.hpp"

namespace statfilter_oidn {
namespace {

void write_message(char* error, size_t size, const std::string& message) {
    if (error && size) std::snprintf(error, size, "%s", message.c_str());
}

sf_param_info param(const char* name, sf_param_type type, const char* default_value, const char* description,
                    double min, double max, const char* choices) {
    sf_param_info p;
    p.struct_size = sizeof p;
    p.name = name;
    p.type = type;
    p.default_value = default_value;
    p.description = description;
    p.min = min;
    p.max = max;
    p.choices = choices;
    return p;
}

const sf_param_info kParams[] = {
    param("quality", SF_PARAM_STRING, "high", "OIDN's quality setting (high: final frames)", 0, 0,
          "high,balanced,fast,default"),
    param("hdr", SF_PARAM_INT, "1", "1: the colour is HDR (linear, any non-negative value); 0: LDR in [0, 1]", 0, 1, ""),
    param("albedo", SF_PARAM_STRING, "",
          "albedo guide: a frame pattern (albedo.####.exr) or a layer of the input's files; empty = none", 0, 0, ""),
    param("normal", SF_PARAM_STRING, "",
          "normal guide (needs albedo): a frame pattern or a layer of the input's files; empty = none", 0, 0, ""),
    param("clean_aux", SF_PARAM_INT, "0", "1: the albedo and normal passes are noise-free (OIDN's cleanAux)", 0, 1, ""),
    param("threads", SF_PARAM_INT, "0", "CPU threads OIDN may use; 0 = its own choice (all cores)", 0, 1024, ""),
    param("max_memory_mb", SF_PARAM_INT, "0",
          "most scratch memory OIDN may use per frame being denoised, in MiB (its maxMemoryMB: it then denoises "
          "in overlapping tiles, a little slower); 0 = its own choice (about 6 GB above 2K). Not part of the run's "
          "--memory budget", 0, 1 << 20, ""),
};

struct Settings {
    std::string quality = "high", albedo, normal;
    int hdr = 1, clean_aux = 0, threads = 0, max_memory_mb = 0;
};

// An OIDN failure, with OIDN's own message.
struct OidnFailure : std::runtime_error {
    OidnFailure(sf_status s, const std::string& m) : std::runtime_error(m), status(s) {}
    sf_status status;
};

sf_status status_of(int oidn_error) {
    switch (oidn_error) {
    case kOidnErrorInvalidArgument: return SF_ERROR_INVALID_ARGUMENT;
    case kOidnErrorOutOfMemory: return SF_ERROR_OUT_OF_MEMORY;
    case kOidnErrorUnsupportedHardware: return SF_ERROR_UNSUPPORTED;
    case kOidnErrorCancelled: return SF_ERROR_CANCELLED;
    default: return SF_ERROR_INTERNAL;
    }
}

void check_device(const OidnApi& api, OidnDevice device, const char* during) {
    const char* message = nullptr;
    const int error = api.getDeviceError(device, &message);
    if (error != kOidnErrorNone)
        throw OidnFailure(status_of(error), std::string("OIDN error ") + std::to_string(error) + " during " + during + ": " +
                                                (message ? message : "(no message)"));
}

int quality_value(const std::string& q) {
    if (q == "fast") return kOidnQualityFast;
    if (q == "balanced") return kOidnQualityBalanced;
    if (q == "default") return kOidnQualityDefault;
    return kOidnQualityHigh;
}

const float& sample(const float* base, const sf_strides& s, int64_t f, int64_t y, int64_t x, int64_t c) {
    return *reinterpret_cast<const float*>(reinterpret_cast<const char*>(base) + f * s.frame + y * s.row + x * s.pixel +
                                           c * s.channel);
}

class Denoiser {
public:
    explicit Denoiser(const OidnApi& api) : api_(api) {}
    ~Denoiser() {
        if (filter_) api_.releaseFilter(filter_);
        if (device_) api_.releaseDevice(device_);
    }

    Settings settings;

    // statfilter calls this once per frame (execute_frame), one call at a time: the plugin is not
    // marked thread-safe, as OIDN already spreads one frame over every core. The OIDN filter is kept
    // from call to call while the frame size, guides and settings stay the same.
    void run(const sf_plugin_run& run) {
        const sf_shape& s = run.shape;
        if (s.channels != 1 && s.channels != 3 && s.channels != 4)
            throw OidnFailure(SF_ERROR_INVALID_ARGUMENT, "OIDN denoises colour: give 3 channels (R,G,B), 4 (alpha is "
                                                         "copied) or 1, not " + std::to_string(s.channels) +
                                                         " (select them with --channels)");
        if (!settings.normal.empty() && settings.albedo.empty())
            throw OidnFailure(SF_ERROR_INVALID_ARGUMENT, "a normal pass needs an albedo pass too (OIDN's RT filter)");
        std::vector<float> albedo, normal;
        try {
            if (!settings.albedo.empty()) albedo = read_pass(run, "albedo", settings.albedo);
            if (!settings.normal.empty()) normal = read_pass(run, "normal", settings.normal);
        } catch (const PassError& e) {
            throw OidnFailure(e.status, e.what());
        }

        open_device();
        const FilterKey key{s.width, s.height, !albedo.empty(), !normal.empty(), settings.hdr, settings.clean_aux,
                            settings.quality, settings.max_memory_mb};
        if (!filter_ || !(key == key_)) make_filter(key);
        const size_t frame_floats = static_cast<size_t>(s.width * s.height) * 3;
        for (int64_t f = 0; f < s.frames; ++f) {
            load_color(run, f, color_);
            // A black frame stays black: OIDN's HDR mode returns a faint level (about 4e-6) on a frame
            // of zeros, which has no brightness for its auto-exposure to measure.
            if (std::all_of(color_.begin(), color_.begin() + static_cast<std::ptrdiff_t>(frame_floats),
                            [](float v) { return v == 0.0f; })) {
                std::fill(output_.begin(), output_.begin() + static_cast<std::ptrdiff_t>(frame_floats), 0.0f);
                store_output(run, f, output_);
                continue;
            }
            // This frame's guides: re-pointing a shared image needs a new commit.
            if (!albedo.empty()) share("albedo", albedo.data() + f * frame_floats);
            if (!normal.empty()) share("normal", normal.data() + f * frame_floats);
            if (!committed_ || !albedo.empty()) {
                api_.commitFilter(filter_);
                check_device(api_, device_, "oidnCommitFilter");
                committed_ = true;
            }
            api_.executeFilter(filter_);
            check_device(api_, device_, "oidnExecuteFilter");
            store_output(run, f, output_);
        }
    }

private:
    // What an OIDN filter was set up for; another value needs a new filter.
    struct FilterKey {
        int64_t width = 0, height = 0;
        bool albedo = false, normal = false;
        int hdr = 1, clean_aux = 0;
        std::string quality;
        int max_memory_mb = 0;
        bool operator==(const FilterKey& o) const {
            return width == o.width && height == o.height && albedo == o.albedo && normal == o.normal && hdr == o.hdr &&
                   clean_aux == o.clean_aux && quality == o.quality && max_memory_mb == o.max_memory_mb;
        }
    };

    void share(const char* name, float* data) {
        api_.setSharedFilterImage(filter_, name, data, kOidnFormatFloat3, static_cast<size_t>(key_.width),
                                  static_cast<size_t>(key_.height), 0, 3 * sizeof(float),
                                  3 * sizeof(float) * static_cast<size_t>(key_.width));
    }

    void make_filter(const FilterKey& key) {
        if (filter_) api_.releaseFilter(filter_);
        filter_ = api_.newFilter(device_, "RT");
        committed_ = false;  // also when a call fails before its commit: the next one commits
        check_device(api_, device_, "oidnNewFilter");
        key_ = key;
        const size_t floats = static_cast<size_t>(key.width * key.height) * 3;
        color_.assign(floats, 0.0f);  // sized once per filter: OIDN keeps pointers into them
        output_.assign(floats, 0.0f);
        share("color", color_.data());
        share("output", output_.data());
        api_.setFilterBool(filter_, "hdr", key.hdr != 0);
        api_.setFilterBool(filter_, "cleanAux", key.clean_aux != 0);
        api_.setFilterInt(filter_, "quality", quality_value(key.quality));
        if (key.max_memory_mb > 0) api_.setFilterInt(filter_, "maxMemoryMB", key.max_memory_mb);
    }

    void open_device() {
        if (device_) return;
        device_ = api_.newDevice(kOidnDeviceDefault);
        if (!device_) {
            const char* message = nullptr;
            api_.getDeviceError(nullptr, &message);  // errors without a device are per thread
            throw OidnFailure(SF_ERROR_UNSUPPORTED, std::string("OIDN could not create a device: ") +
                                                        (message ? message : "(no message)"));
        }
        if (settings.threads > 0) api_.setDeviceInt(device_, "numThreads", settings.threads);
        api_.commitDevice(device_);
        check_device(api_, device_, "oidnCommitDevice");
    }

    // Frame f into the packed RGB buffer. OIDN's HDR mode takes non-negative values: negatives
    // (float noise around black) become 0; NaN/Inf is an error naming the sample.
    static void load_color(const sf_plugin_run& run, int64_t f, std::vector<float>& color) {
        const sf_shape& s = run.shape;
        size_t i = 0;
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < 3; ++c) {
                    const float v = sample(run.input, run.input_strides, f, y, x, s.channels == 1 ? 0 : c);
                    if (!std::isfinite(v))
                        throw OidnFailure(SF_ERROR_NUMERIC, "non-finite value at frame " +
                                                                std::to_string(run.frame_numbers[f]) + ", pixel (" +
                                                                std::to_string(x) + ", " + std::to_string(y) + ")");
                    color[i++] = v > 0 ? v : 0;
                }
    }

    static void store_output(const sf_plugin_run& run, int64_t f, const std::vector<float>& output) {
        const sf_shape& s = run.shape;
        size_t i = 0;
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x, i += 3) {
                const int64_t colour_channels = s.channels == 1 ? 1 : 3;
                for (int64_t c = 0; c < colour_channels; ++c)
                    const_cast<float&>(sample(run.output, run.output_strides, f, y, x, c)) = output[i + c];
                if (s.channels == 4)  // alpha, unchanged (read before the write: output may be the input)
                    const_cast<float&>(sample(run.output, run.output_strides, f, y, x, 3)) =
                        sample(run.input, run.input_strides, f, y, x, 3);
            }
    }

    const OidnApi& api_;
    OidnDevice device_ = nullptr;
    OidnFilter filter_ = nullptr;
    bool committed_ = false;
    FilterKey key_;
    std::vector<float> color_, output_;
};

// ---- the plugin's C functions: no exception leaves them -----------------------------------------

template <class Body>
sf_status guarded(char* error, size_t size, Body&& body) noexcept {
    try {
        body();
        return SF_OK;
    } catch (const OidnFailure& e) {
        write_message(error, size, e.what());
        return e.status;
    } catch (const std::bad_alloc&) {
        write_message(error, size, "out of memory");
        return SF_ERROR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        write_message(error, size, e.what());
        return SF_ERROR_INTERNAL;
    } catch (...) {
        write_message(error, size, "unknown error");
        return SF_ERROR_INTERNAL;
    }
}

// OIDN's TBB loads libtbbbind with RTLD_DEEPBIND, which the AddressSanitizer runtime refuses by
// aborting the process: in a sanitized process, say so instead of letting that happen.
bool under_address_sanitizer() { return dlsym(RTLD_DEFAULT, "__asan_init") != nullptr; }

// The library, or why the plugin cannot run here.
const OidnApi* usable_api(std::string& why) {
    const OidnApi* api = oidn_api(why);
    if (api && under_address_sanitizer()) {
        why = "OIDN cannot run under AddressSanitizer: its TBB opens libtbbbind with RTLD_DEEPBIND, which "
              "the sanitizer runtime refuses";
        return nullptr;
    }
    return api;
}

sf_status probe(char* error, size_t size) {
    std::string why;
    if (usable_api(why)) return SF_OK;
    write_message(error, size, why);
    return SF_ERROR_UNSUPPORTED;
}

sf_status create(void** instance, char* error, size_t size) {
    return guarded(error, size, [&] {
        std::string why;
        const OidnApi* api = usable_api(why);
        if (!api) throw OidnFailure(SF_ERROR_UNSUPPORTED, why);
        *instance = new Denoiser(*api);
    });
}

sf_status set_param(void* instance, const char* name, const char* value, char* error, size_t size) {
    return guarded(error, size, [&] {
        Settings& s = static_cast<Denoiser*>(instance)->settings;
        const std::string n = name, v = value;
        // Values arrive checked against kParams by statfilter.
        if (n == "quality") s.quality = v;
        else if (n == "hdr") s.hdr = std::stoi(v);
        else if (n == "albedo") s.albedo = v;
        else if (n == "normal") s.normal = v;
        else if (n == "clean_aux") s.clean_aux = std::stoi(v);
        else if (n == "threads") s.threads = std::stoi(v);
        else if (n == "max_memory_mb") s.max_memory_mb = std::stoi(v);
        else throw OidnFailure(SF_ERROR_NOT_FOUND, "unknown parameter '" + n + "'");
    });
}

sf_status execute_frame(void* instance, const sf_plugin_run* frame, char* error, size_t size) {
    return guarded(error, size, [&] { static_cast<Denoiser*>(instance)->run(*frame); });
}

void release(void* instance) { delete static_cast<Denoiser*>(instance); }

const sf_plugin kPlugin = {
    SF_PLUGIN_ABI_VERSION,
    "oidn",
    "1.0.0",
    "Intel Open Image Denoise per frame (HDR, optional albedo/normal guides); loads libOpenImageDenoise at run time",
    SF_FILTER_SINGLE_FRAME,
    static_cast<int>(sizeof kParams / sizeof kParams[0]),
    kParams,
    probe,
    create,
    set_param,
    nullptr,  // no whole-sequence execute: statfilter runs the frames through execute_frame
    release,
    0,  // not thread-safe: one call at a time (OIDN spreads each frame over the cores itself)
    execute_frame,
};

}  // namespace
}  // namespace statfilter_oidn

SF_PLUGIN_EXPORT const sf_plugin* sf_plugin_entry(void) { return &statfilter_oidn::kPlugin; }
