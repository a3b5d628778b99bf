// Version, status names, last-error message and the error callback.
#include <atomic>
#include <mutex>

#include "api_guard.hpp"

namespace {

thread_local std::string t_last_error;
std::mutex g_callback_mutex;
sf_error_callback g_callback = nullptr;
void* g_callback_user = nullptr;

}  // namespace

namespace statfilter::capi {

sf_status fail(sf_status status, const std::string& message, std::string* handle_error) {
    t_last_error = message;
    if (handle_error) *handle_error = message;
    sf_error_callback callback;
    void* user;
    {
        std::lock_guard<std::mutex> lock(g_callback_mutex);
        callback = g_callback;
        user = g_callback_user;
    }
    if (callback) callback(user, status, message.c_str());
    return status;
}

void clear_error() { t_last_error.clear(); }

Progress make_progress(sf_progress_callback callback, void* user) {
    if (!callback) return Progress();
    return Progress([callback, user](double fraction, const char* stage) { return callback(user, fraction, stage) == 0; });
}

}  // namespace statfilter::capi

extern "C" {

int sf_version(void) { return SF_VERSION; }

const char* sf_version_string(void) {
#define SF_STR2(x) #x
#define SF_STR(x) SF_STR2(x)
    return SF_STR(SF_VERSION_MAJOR) "." SF_STR(SF_VERSION_MINOR) "." SF_STR(SF_VERSION_PATCH);
}

const char* sf_status_name(sf_status status) {
    switch (status) {
    case SF_OK: return "SF_OK";
    case SF_ERROR_INVALID_ARGUMENT: return "SF_ERROR_INVALID_ARGUMENT";
    case SF_ERROR_OUT_OF_MEMORY: return "SF_ERROR_OUT_OF_MEMORY";
    case SF_ERROR_IO: return "SF_ERROR_IO";
    case SF_ERROR_NOT_FOUND: return "SF_ERROR_NOT_FOUND";
    case SF_ERROR_UNSUPPORTED: return "SF_ERROR_UNSUPPORTED";
    case SF_ERROR_CANCELLED: return "SF_ERROR_CANCELLED";
    case SF_ERROR_NUMERIC: return "SF_ERROR_NUMERIC";
    case SF_ERROR_INTERNAL: return "SF_ERROR_INTERNAL";
    }
    return "SF_ERROR_UNKNOWN";
}

const char* sf_last_error(void) { return t_last_error.c_str(); }

void sf_set_error_callback(sf_error_callback callback, void* user) {
    std::lock_guard<std::mutex> lock(g_callback_mutex);
    g_callback = callback;
    g_callback_user = user;
}

}  // extern "C"
