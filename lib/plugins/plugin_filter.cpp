#include "plugins/plugin_filter.hpp"

#include <cstdio>
#include <vector>

#include "pipeline/parallel.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

constexpr size_t kMessageSize = 4096;

// The plugin calls this per frame. Cancellation must not throw through the plugin's C frames: it is
// recorded here and thrown after the plugin has returned.
struct ProgressBridge {
    const Progress* progress;
    bool cancelled = false;
    std::string stage;

    static int call(void* user, double fraction, const char* stage) {
        auto* self = static_cast<ProgressBridge*>(user);
        try {
            self->progress->report(fraction, stage ? stage : "plugin");
            return 0;
        } catch (const Error&) {
            self->cancelled = true;
            self->stage = stage ? stage : "plugin";
            return 1;
        }
    }
};

sf_strides c_strides(const Strides& s) { return sf_strides{s.channel, s.pixel, s.row, s.frame}; }

class PluginFilter final : public Filter {
public:
    PluginFilter(std::shared_ptr<const PluginDescriptor> plugin, std::string path)
        : Filter(plugin->params), plugin_(std::move(plugin)), path_(std::move(path)) {
        char message[kMessageSize] = "";
        void* instance = nullptr;
        sf_status status;
        {
            auto lock = call_lock();
            status = plugin_->create(&instance, message, sizeof message);
        }
        if (status != SF_OK || !instance) {
            if (status == SF_OK && instance == nullptr) std::snprintf(message, sizeof message, "create returned no instance");
            fail(status == SF_OK ? SF_ERROR_INTERNAL : status, plugin_message(message, sizeof message));
        }
        instance_ = instance;
    }

    ~PluginFilter() override {
        auto lock = call_lock();
        plugin_->release(instance_);
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        pass_parameters();
        std::vector<const char*> channel_names;
        for (const auto& n : input.channel_names()) channel_names.push_back(n.c_str());
        sf_plugin_run run = whole_run(input, output, channel_names);
        if (plugin_->execute_frame)
            run_frames(run, progress);
        else
            run_whole(run, progress);
    }

private:
    // A plugin that is not thread-safe gets one call at a time, over all its instances.
    std::unique_lock<std::mutex> call_lock() const {
        return plugin_->thread_safe ? std::unique_lock<std::mutex>() : std::unique_lock<std::mutex>(plugin_->calls);
    }

    void pass_parameters() {
        char message[kMessageSize] = "";
        for (const ParamSpec& spec : params().specs()) {
            const std::string& value = params().get_string(spec.name);
            sf_status status;
            {
                auto lock = call_lock();
                status = plugin_->set_param(instance_, spec.name.c_str(), value.c_str(), message, sizeof message);
            }
            if (status != SF_OK) fail(status, "parameter '" + spec.name + "' = '" + value + "': " + plugin_message(message, sizeof message));
        }
    }

    static sf_plugin_run whole_run(const Sequence& input, Sequence& output, const std::vector<const char*>& channel_names) {
        const Shape& shape = input.shape();
        sf_plugin_run run{};
        run.struct_size = sizeof run;
        run.shape = sf_shape{shape.frames, shape.height, shape.width, shape.channels};
        run.input = input.data();
        run.input_strides = c_strides(input.strides());
        run.output = output.data();
        run.output_strides = c_strides(output.strides());
        run.frame_numbers = input.frame_numbers().data();
        run.channel_names = channel_names.data();
        run.source_pattern = input.source().pattern.c_str();
        run.source_channels = input.source().channels.c_str();
        return run;
    }

    // The plugin's own loop over the whole sequence, reporting progress through the bridge.
    void run_whole(sf_plugin_run run, const Progress& progress) {
        ProgressBridge bridge{&progress, false, ""};
        run.progress = &ProgressBridge::call;
        run.progress_user = &bridge;
        char message[kMessageSize] = "";
        sf_status status;
        {
            auto lock = call_lock();
            status = plugin_->execute(instance_, &run, message, sizeof message);
        }
        if (bridge.cancelled) throw Error(Status::Cancelled, "cancelled during " + bridge.stage);
        if (status != SF_OK) fail(status, plugin_message(message, sizeof message));
    }

    // The host's loop: one execute_frame per frame, on every core when the plugin is thread-safe,
    // else one after the other; progress and cancellation between frames, on the calling thread.
    void run_frames(const sf_plugin_run& whole, const Progress& progress) {
        const int threads = plugin_->thread_safe ? resolve_threads(0) : 1;
        parallel_for(whole.shape.frames, threads, [&](int64_t f) {
            sf_plugin_run frame = whole;
            frame.shape.frames = 1;
            frame.input = reinterpret_cast<const float*>(reinterpret_cast<const char*>(whole.input) + f * whole.input_strides.frame);
            frame.output = reinterpret_cast<float*>(reinterpret_cast<char*>(whole.output) + f * whole.output_strides.frame);
            frame.frame_numbers = whole.frame_numbers + f;
            char message[kMessageSize] = "";
            sf_status status;
            {
                auto lock = call_lock();
                status = plugin_->execute_frame(instance_, &frame, message, sizeof message);
            }
            if (status != SF_OK) fail(status, plugin_message(message, sizeof message));
        }, {progress, 0, 1, plugin_->name.c_str()});
    }

    // The plugin's message, prefixed with its name unless it already starts with it.
    [[noreturn]] void fail(sf_status status, std::string message) const {
        const std::string& name = plugin_->name;
        if (message.empty()) message = "failed without a message (" + path_ + ")";
        if (message.compare(0, name.size() + 1, name + ":") != 0) message = name + ": " + message;
        throw Error(plugin_status(status), message);
    }

    std::shared_ptr<const PluginDescriptor> plugin_;
    std::string path_;
    void* instance_ = nullptr;
};

}  // namespace

std::unique_ptr<Filter> make_plugin_filter(std::shared_ptr<const PluginDescriptor> plugin, const std::string& path) {
    return std::make_unique<PluginFilter>(std::move(plugin), path);
}

}  // namespace statfilter
