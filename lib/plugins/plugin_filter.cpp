#include "plugins/plugin_filter.hpp"

#include <cstdio>
#include <cstring>

#include "statfilter/error.hpp"

namespace statfilter {

Status plugin_status(sf_status status) {
    const int s = static_cast<int>(status);
    if (s >= static_cast<int>(Status::InvalidArgument) && s <= static_cast<int>(Status::Internal)) return static_cast<Status>(s);
    return Status::Internal;
}

std::string plugin_message(const char* buffer, size_t size) { return std::string(buffer, strnlen(buffer, size)); }

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
    PluginFilter(const sf_plugin* plugin, std::string path, std::vector<ParamSpec> specs)
        : Filter(std::move(specs)), plugin_(plugin), path_(std::move(path)) {
        char message[kMessageSize] = "";
        void* instance = nullptr;
        const sf_status status = plugin_->create(&instance, message, sizeof message);
        if (status != SF_OK || !instance) {
            if (status == SF_OK && instance == nullptr) std::snprintf(message, sizeof message, "create returned no instance");
            fail(status == SF_OK ? SF_ERROR_INTERNAL : status, plugin_message(message, sizeof message));
        }
        instance_ = instance;
    }

    ~PluginFilter() override { plugin_->release(instance_); }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        char message[kMessageSize] = "";
        for (const ParamSpec& spec : params().specs()) {
            const std::string& value = params().get_string(spec.name);
            const sf_status status = plugin_->set_param(instance_, spec.name.c_str(), value.c_str(), message, sizeof message);
            if (status != SF_OK) fail(status, "parameter '" + spec.name + "' = '" + value + "': " + plugin_message(message, sizeof message));
        }

        const Shape& shape = input.shape();
        std::vector<const char*> channel_names;
        for (const auto& n : input.channel_names()) channel_names.push_back(n.c_str());
        ProgressBridge bridge{&progress, false, ""};
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
        run.progress = &ProgressBridge::call;
        run.progress_user = &bridge;

        const sf_status status = plugin_->execute(instance_, &run, message, sizeof message);
        if (bridge.cancelled) throw Error(Status::Cancelled, "cancelled during " + bridge.stage);
        if (status != SF_OK) fail(status, plugin_message(message, sizeof message));
    }

private:
    // The plugin's message, prefixed with its name unless it already starts with it.
    [[noreturn]] void fail(sf_status status, std::string message) const {
        const std::string name = plugin_->name;
        if (message.empty()) message = "failed without a message (" + path_ + ")";
        if (message.compare(0, name.size() + 1, name + ":") != 0) message = name + ": " + message;
        throw Error(plugin_status(status), message);
    }

    const sf_plugin* plugin_;
    std::string path_;
    void* instance_ = nullptr;
};

}  // namespace

std::unique_ptr<Filter> make_plugin_filter(const sf_plugin* plugin, const std::string& path, std::vector<ParamSpec> specs) {
    return std::make_unique<PluginFilter>(plugin, path, std::move(specs));
}

}  // namespace statfilter
