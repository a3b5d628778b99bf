#include "oidn_library.hpp"

#include <dlfcn.h>
#include <glob.h>

#include <cstdlib>
#include <mutex>
#include <vector>

namespace statfilter_oidn {
namespace {

const char* const kHowToGet =
    "The oidn plugin needs libOpenImageDenoise (Intel Open Image Denoise 2.x). Get it with "
    "`pip install pyoidn` (its copy is found in the usual Python prefixes; otherwise point "
    "STATFILTER_OIDN_LIBRARY at it: STATFILTER_OIDN_LIBRARY=$(python3 -c \"import pyoidn,os;"
    "print(os.path.join(os.path.dirname(pyoidn.__file__),'oidn','lib','libOpenImageDenoise.so.2'))\")), "
    "or install OIDN 2.x and set STATFILTER_OIDN_LIBRARY to its libOpenImageDenoise.so.2";

template <class F>
bool bind(void* library, const char* name, F& out, std::string& missing) {
    out = reinterpret_cast<F>(dlsym(library, name));
    if (!out) missing += (missing.empty() ? "" : ", ") + std::string(name);
    return out != nullptr;
}

// Opens one candidate; on failure appends the reason to `tried`.
bool try_load(const std::string& path, OidnApi& api, std::string& tried) {
    dlerror();
    void* library = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        const char* e = dlerror();
        tried += "\n  " + path + ": " + (e ? e : "cannot load");
        return false;
    }
    std::string missing;
    bind(library, "oidnNewDevice", api.newDevice, missing);
    bind(library, "oidnSetDeviceInt", api.setDeviceInt, missing);
    bind(library, "oidnCommitDevice", api.commitDevice, missing);
    bind(library, "oidnGetDeviceError", api.getDeviceError, missing);
    bind(library, "oidnReleaseDevice", api.releaseDevice, missing);
    bind(library, "oidnNewFilter", api.newFilter, missing);
    bind(library, "oidnSetSharedFilterImage", api.setSharedFilterImage, missing);
    bind(library, "oidnSetFilterBool", api.setFilterBool, missing);  // OIDN 1.x lacks these two
    bind(library, "oidnSetFilterInt", api.setFilterInt, missing);
    bind(library, "oidnCommitFilter", api.commitFilter, missing);
    bind(library, "oidnExecuteFilter", api.executeFilter, missing);
    bind(library, "oidnReleaseFilter", api.releaseFilter, missing);
    if (!missing.empty()) {
        tried += "\n  " + path + ": not OIDN 2.x (missing " + missing + ")";
        dlclose(library);
        return false;
    }
    api.path = path;
    return true;  // kept open until exit
}

// pyoidn's bundled library under the Python prefixes a studio machine usually has.
std::vector<std::string> pyoidn_candidates() {
    std::vector<std::string> prefixes;
    for (const char* var : {"VIRTUAL_ENV", "CONDA_PREFIX", "PYTHONUSERBASE"})
        if (const char* v = std::getenv(var); v && *v) prefixes.push_back(v);
    if (const char* home = std::getenv("HOME"); home && *home) {
        prefixes.push_back(std::string(home) + "/.local");
        prefixes.push_back(std::string(home) + "/.pyenv/versions/*");
    }
    if (const char* pyenv = std::getenv("PYENV_ROOT"); pyenv && *pyenv) prefixes.push_back(std::string(pyenv) + "/versions/*");
    prefixes.push_back("/usr/local");
    prefixes.push_back("/usr");
    std::vector<std::string> found;
    for (const auto& prefix : prefixes) {
        for (const char* packages : {"site-packages", "dist-packages"}) {
            const std::string pattern = prefix + "/lib/python3*/" + packages + "/pyoidn/oidn/lib/libOpenImageDenoise.so.2";
            glob_t g{};
            if (glob(pattern.c_str(), 0, nullptr, &g) == 0)
                for (size_t i = 0; i < g.gl_pathc; ++i) found.push_back(g.gl_pathv[i]);
            globfree(&g);
        }
    }
    return found;
}

}  // namespace

const OidnApi* oidn_api(std::string& why) {
    static std::once_flag once;
    static OidnApi api;
    static bool loaded = false;
    static std::string failure;
    std::call_once(once, [] {
        std::string tried;
        if (const char* env = std::getenv("STATFILTER_OIDN_LIBRARY"); env && *env) {
            loaded = try_load(env, api, tried);
            if (!loaded) failure = "STATFILTER_OIDN_LIBRARY does not name a usable library:" + tried + "\n" + kHowToGet;
            return;
        }
        std::vector<std::string> candidates = {"libOpenImageDenoise.so.2", "libOpenImageDenoise.so"};
        for (const auto& c : pyoidn_candidates()) candidates.push_back(c);
        for (const auto& c : candidates)
            if ((loaded = try_load(c, api, tried))) return;
        failure = "libOpenImageDenoise not found; tried:" + tried + "\n" + kHowToGet;
    });
    why = failure;
    return loaded ? &api : nullptr;
}

}  // namespace statfilter_oidn
