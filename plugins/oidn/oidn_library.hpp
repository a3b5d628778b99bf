// libOpenImageDenoise (OIDN 2.x) opened at run time. Only the functions the plugin calls are
// declared, as function-pointer types matching OIDN's documented C API.
#pragma once
#include <cstddef>
#include <string>

namespace statfilter_oidn {

struct OidnDeviceImpl;
struct OidnFilterImpl;
using OidnDevice = OidnDeviceImpl*;
using OidnFilter = OidnFilterImpl*;

// OIDN's enum values used here (C enums are int-sized).
enum : int { kOidnDeviceDefault = 0 };
enum : int { kOidnFormatFloat3 = 3 };
enum : int { kOidnErrorNone = 0, kOidnErrorInvalidArgument = 2, kOidnErrorOutOfMemory = 4,
             kOidnErrorUnsupportedHardware = 5, kOidnErrorCancelled = 6 };
enum : int { kOidnQualityDefault = 0, kOidnQualityFast = 4, kOidnQualityBalanced = 5, kOidnQualityHigh = 6 };

struct OidnApi {
    std::string path;  // the file that was loaded
    OidnDevice (*newDevice)(int type);
    void (*setDeviceInt)(OidnDevice device, const char* name, int value);
    void (*commitDevice)(OidnDevice device);
    int (*getDeviceError)(OidnDevice device, const char** message);
    void (*releaseDevice)(OidnDevice device);
    OidnFilter (*newFilter)(OidnDevice device, const char* type);
    void (*setSharedFilterImage)(OidnFilter filter, const char* name, void* data, int format, size_t width,
                                 size_t height, size_t byte_offset, size_t pixel_byte_stride, size_t row_byte_stride);
    void (*setFilterBool)(OidnFilter filter, const char* name, bool value);
    void (*setFilterInt)(OidnFilter filter, const char* name, int value);
    void (*commitFilter)(OidnFilter filter);
    void (*executeFilter)(OidnFilter filter);
    void (*releaseFilter)(OidnFilter filter);
};

// The library, loaded once per process: from $STATFILTER_OIDN_LIBRARY when set (and only from
// there), else the system search path, else the copy inside an installed PyPI package pyoidn in
// the usual Python prefixes. nullptr when none works; `why` then says what was tried and how to
// get the library.
const OidnApi* oidn_api(std::string& why);

}  // namespace statfilter_oidn
