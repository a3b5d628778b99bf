// The caller's versioned option structs (struct_size first) read into the core's options: one
// place for the copy that honours struct_size and for each struct's translation.
#pragma once
#include <cstring>
#include <string>

#include "statfilter/error.hpp"
#include "statfilter/sequence_io.hpp"
#include "statfilter/statfilter.h"

namespace statfilter::capi {

// Reads the fields of a caller's options struct that its struct_size says it has; defaults (init)
// for the rest and for a NULL struct. Every versioned struct of the header goes through these.
template <class T>
T read_versioned(const T* options, void (*init)(T*)) {
    T copy;
    init(&copy);
    if (!options) return copy;
    if (options->struct_size < sizeof(size_t) || options->struct_size > sizeof(T))
        throw Error(Status::InvalidArgument, "options.struct_size " + std::to_string(options->struct_size) +
                                                 " is not a size this library knows (call the *_init function)");
    std::memcpy(&copy, options, options->struct_size);
    return copy;
}

// The other direction: the caller's output struct gets the fields of `full` its struct_size says
// it has. The size is checked first, so a bad struct fails before any work.
template <class T>
T& require_versioned_out(T* out, const char* what) {
    if (!out) throw Error(Status::InvalidArgument, std::string("argument '") + what + "' is NULL");
    if (out->struct_size < sizeof(size_t) || out->struct_size > sizeof(T))
        throw Error(Status::InvalidArgument, std::string(what) + ".struct_size " + std::to_string(out->struct_size) +
                                                 " is not a size this library knows (call the *_init function)");
    return *out;
}
template <class T>
void write_versioned(T& out, T full) {
    full.struct_size = out.struct_size;
    std::memcpy(&out, &full, out.struct_size);
}

inline std::string text_or_empty(const char* s) { return s ? std::string(s) : std::string(); }

ReadOptions read_options_from(const sf_read_options* options);
WriteOptions write_options_from(const sf_write_options* options);
// run.memory and run.threads, neither negative; the message says what their 0 stands for (a run's
// default and every core, or what the plan says).
void check_run_options(const sf_run_options& run, const char* memory_zero, const char* threads_zero);

}  // namespace statfilter::capi
