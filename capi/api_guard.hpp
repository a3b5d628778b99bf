// The boundary between the C ABI and the C++ core: handle structs, and the guard that turns every
// exception into a status code plus a message (thread-local, and on the handle when there is one).
#pragma once
#include <memory>
#include <new>
#include <string>

#include "statfilter/error.hpp"
#include "statfilter/filter.hpp"
#include "statfilter/sequence.hpp"
#include "statfilter/statfilter.h"

struct sf_sequence_s {
    std::unique_ptr<statfilter::Sequence> sequence;
};

struct sf_filter_s {
    std::unique_ptr<statfilter::Filter> filter;
    std::string name;
    std::string last_error;
    sf_progress_callback progress = nullptr;
    void* progress_user = nullptr;
};

namespace statfilter::capi {

// Records a failure: thread-local message, optional handle message, error callback.
sf_status fail(sf_status status, const std::string& message, std::string* handle_error = nullptr);
void clear_error();

template <class T>
T& require(T* pointer, const char* what) {
    if (!pointer) throw Error(Status::InvalidArgument, std::string("argument '") + what + "' is NULL");
    return *pointer;
}

inline Sequence& require_sequence(sf_sequence handle, const char* what) {
    return *require(handle, what).sequence;
}

inline const char* require_string(const char* text, const char* what) {
    if (!text) throw Error(Status::InvalidArgument, std::string("argument '") + what + "' is NULL");
    return text;
}

// Runs body; maps exceptions to status codes. Never lets an exception cross the C boundary.
template <class Body>
sf_status guarded(Body&& body, std::string* handle_error = nullptr) noexcept {
    try {
        body();
        clear_error();
        return SF_OK;
    } catch (const Error& e) {
        return fail(static_cast<sf_status>(e.status()), e.what(), handle_error);
    } catch (const std::bad_alloc&) {
        return fail(SF_ERROR_OUT_OF_MEMORY, "out of memory", handle_error);
    } catch (const std::exception& e) {
        return fail(SF_ERROR_INTERNAL, std::string("internal error: ") + e.what(), handle_error);
    } catch (...) {
        return fail(SF_ERROR_INTERNAL, "internal error: unknown exception", handle_error);
    }
}

Progress make_progress(sf_progress_callback callback, void* user);

}  // namespace statfilter::capi
