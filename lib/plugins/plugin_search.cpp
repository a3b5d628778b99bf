#include "plugins/plugin_search.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace statfilter {
namespace {

const char* const kPrefix = "statfilter_";
const char* const kSuffix = ".so";

std::string directory_of(const std::string& path) {
    const auto slash = path.rfind('/');
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

// The file this code was loaded from: libstatfilter.so in normal use (a test executable when the
// core is linked statically).
std::string own_directory() {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&plugin_directories), &info) && info.dli_fname && *info.dli_fname)
        return directory_of(info.dli_fname);
    return "";
}

}  // namespace

std::vector<std::string> plugin_directories() {
    std::vector<std::string> dirs;
    auto add = [&](std::string d) {
        while (d.size() > 1 && d.back() == '/') d.pop_back();
        if (!d.empty() && std::find(dirs.begin(), dirs.end(), d) == dirs.end()) dirs.push_back(d);
    };
    if (const char* env = std::getenv("STATFILTER_PLUGIN_PATH")) {
        std::string list = env;
        size_t start = 0;
        while (start <= list.size()) {
            const size_t colon = std::min(list.find(':', start), list.size());
            add(list.substr(start, colon - start));
            start = colon + 1;
        }
    }
    add(own_directory());
    return dirs;
}

std::string plugin_search_text() {
    std::string text;
    for (const auto& d : plugin_directories()) text += (text.empty() ? "" : ", ") + d;
    return "$STATFILTER_PLUGIN_PATH and the library's directory: " + (text.empty() ? "(none)" : text);
}

std::string plugin_file_name(const std::string& filter_name) { return kPrefix + filter_name + kSuffix; }

bool valid_plugin_name(const std::string& name) {
    if (name.empty() || name[0] == '.') return false;
    for (char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) return false;
    return true;
}

std::string plugin_name_from_file(const std::string& file) {
    const std::string prefix = kPrefix, suffix = kSuffix;
    if (file.size() <= prefix.size() + suffix.size()) return "";
    if (file.compare(0, prefix.size(), prefix) != 0) return "";
    if (file.compare(file.size() - suffix.size(), suffix.size(), suffix) != 0) return "";
    const std::string name = file.substr(prefix.size(), file.size() - prefix.size() - suffix.size());
    return valid_plugin_name(name) ? name : "";
}

}  // namespace statfilter
