#include "plugins/plugin_registry.hpp"

#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <deque>
#include <map>
#include <mutex>

#include "plugins/plugin_loader.hpp"

namespace statfilter {
namespace {

bool is_file(const std::string& path) {
    struct stat st{};
    return stat(path.c_str(), &st) == 0 && !S_ISDIR(st.st_mode);
}

// Plugin file names in a directory, sorted so that listings are stable.
std::vector<std::string> plugin_files(const std::string& dir) {
    std::vector<std::string> names;
    if (DIR* d = opendir(dir.c_str())) {
        while (const dirent* e = readdir(d))
            if (!plugin_name_from_file(e->d_name).empty() && is_file(dir + "/" + e->d_name)) names.push_back(e->d_name);
        closedir(d);
    }
    std::sort(names.begin(), names.end());
    return names;
}

class Registry final : public PluginRegistry {
public:
    const FilterEntry* find(const std::string& name) override {
        if (!valid_plugin_name(name)) return nullptr;
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = by_name_.find(name);
        if (it != by_name_.end()) return it->second;
        for (const auto& dir : plugin_directories()) {
            const std::string path = dir + "/" + plugin_file_name(name);
            if (is_file(path)) return load(path, name);
        }
        return nullptr;
    }

    // The directories are scanned once per process, so that indices into the listing stay put.
    std::vector<const FilterEntry*> all() override {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!scanned_) {
            scanned_ = true;
            for (const auto& dir : plugin_directories())
                for (const auto& file : plugin_files(dir)) load(dir + "/" + file, plugin_name_from_file(file));
        }
        return listed_;
    }

private:
    // Loads a file once; a name already loaded from an earlier directory shadows later files.
    const FilterEntry* load(const std::string& path, const std::string& name) {
        auto it = by_name_.find(name);
        if (it != by_name_.end()) return it->second;
        entries_.push_back(load_plugin(path, name));
        listed_.push_back(&entries_.back());
        return by_name_[name] = &entries_.back();
    }

    std::mutex mutex_;
    bool scanned_ = false;
    std::deque<FilterEntry> entries_;  // a deque keeps element addresses on push_back
    std::vector<const FilterEntry*> listed_;
    std::map<std::string, const FilterEntry*> by_name_;
};

}  // namespace

PluginRegistry& plugin_registry() {
    static Registry registry;
    return registry;
}

}  // namespace statfilter
