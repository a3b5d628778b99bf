// sf_filter_*: filters found by name, parameters by name, results, execution.
#include <cstring>

#include "api_guard.hpp"
#include "options.hpp"
#include "statfilter/filter_registry.hpp"
#include "statfilter/frame_pattern.hpp"

using namespace statfilter;
using namespace statfilter::capi;

namespace {

sf_filter_s& require_filter(sf_filter filter) { return require(filter, "filter"); }

// Runs body against a filter, recording failures on the handle as well as the thread.
template <class Body>
sf_status on_filter(sf_filter filter, Body&& body) {
    std::string* handle_error = filter ? &filter->last_error : nullptr;
    return guarded([&] { body(require_filter(filter)); }, handle_error);
}

}  // namespace

extern "C" {

int sf_filter_count(void) {
    try {
        return static_cast<int>(available_filters().size());
    } catch (...) {
        return 0;
    }
}

const char* sf_filter_name(int index) {
    try {
        const auto filters = available_filters();
        if (index < 0 || static_cast<size_t>(index) >= filters.size()) return nullptr;
        return filters[static_cast<size_t>(index)]->name.c_str();  // entries live until exit
    } catch (...) {
        return nullptr;
    }
}

const char* sf_filter_description(const char* name) {
    if (!name) return nullptr;
    try {
        return find_filter(name).description.c_str();
    } catch (...) {
        return nullptr;
    }
}

sf_status sf_filter_create(const char* name, sf_filter* out) {
    return guarded([&] {
        require(out, "out") = nullptr;
        auto handle = std::make_unique<sf_filter_s>();
        handle->name = require_string(name, "name");
        handle->filter = create_filter(handle->name);
        *out = handle.release();
    });
}

sf_status sf_filter_release(sf_filter filter) {
    return guarded([&] { delete filter; });
}

const char* sf_filter_last_error(sf_filter filter) { return filter ? filter->last_error.c_str() : ""; }

sf_status sf_filter_set_int(sf_filter filter, const char* name, int64_t value) {
    return on_filter(filter, [&](sf_filter_s& f) { f.filter->params().set_int(require_string(name, "name"), value); });
}

sf_status sf_filter_set_float(sf_filter filter, const char* name, double value) {
    return on_filter(filter, [&](sf_filter_s& f) { f.filter->params().set_float(require_string(name, "name"), value); });
}

sf_status sf_filter_set_string(sf_filter filter, const char* name, const char* value) {
    return on_filter(filter, [&](sf_filter_s& f) {
        f.filter->params().set_string(require_string(name, "name"), require_string(value, "value"));
    });
}

sf_status sf_filter_get_int(sf_filter filter, const char* name, int64_t* value) {
    return on_filter(filter, [&](sf_filter_s& f) {
        int64_t& out = require(value, "value");  // NULL checks before the lookup can fail
        out = f.filter->params().get_int(require_string(name, "name"));
    });
}

sf_status sf_filter_get_float(sf_filter filter, const char* name, double* value) {
    return on_filter(filter, [&](sf_filter_s& f) {
        double& out = require(value, "value");
        out = f.filter->params().get_float(require_string(name, "name"));
    });
}

sf_status sf_filter_get_string(sf_filter filter, const char* name, const char** value) {
    return on_filter(filter, [&](sf_filter_s& f) {
        const char*& out = require(value, "value");
        out = f.filter->params().get_string(require_string(name, "name")).c_str();
    });
}

sf_status sf_filter_param_count(sf_filter filter, int* count) {
    return on_filter(filter, [&](sf_filter_s& f) {
        require(count, "count") = static_cast<int>(f.filter->params().specs().size());
    });
}

sf_status sf_filter_param_info(sf_filter filter, int index, sf_param_info* info) {
    return on_filter(filter, [&](sf_filter_s& f) {
        sf_param_info& out = require_versioned_out(info, "info");
        const auto& specs = f.filter->params().specs();
        if (index < 0 || static_cast<size_t>(index) >= specs.size())
            throw Error(Status::InvalidArgument, "parameter index " + std::to_string(index) + " out of range");
        const ParamSpec& s = specs[static_cast<size_t>(index)];
        sf_param_info full;
        full.name = s.name.c_str();
        full.type = static_cast<sf_param_type>(s.type);
        full.default_value = s.default_value.c_str();
        full.description = s.description.c_str();
        full.min = s.min;
        full.max = s.max;
        full.choices = s.choices_text.c_str();  // owned by the filter, like the other strings
        write_versioned(out, full);
    });
}

sf_status sf_filter_result_count(sf_filter filter, int* count) {
    return on_filter(filter, [&](sf_filter_s& f) {
        require(count, "count") = static_cast<int>(f.filter->results().names().size());
    });
}

sf_status sf_filter_result_name(sf_filter filter, int index, const char** name) {
    return on_filter(filter, [&](sf_filter_s& f) {
        const char*& out = require(name, "name");
        const auto& names = f.filter->results().names();
        if (index < 0 || static_cast<size_t>(index) >= names.size())
            throw Error(Status::InvalidArgument, "result index " + std::to_string(index) + " out of range");
        out = names[static_cast<size_t>(index)].c_str();
    });
}

sf_status sf_filter_result_float(sf_filter filter, const char* name, double* value) {
    return on_filter(filter, [&](sf_filter_s& f) {
        double& out = require(value, "value");
        out = f.filter->results().get_float(require_string(name, "name"));
    });
}

sf_status sf_filter_result_string(sf_filter filter, const char* name, const char** value) {
    return on_filter(filter, [&](sf_filter_s& f) {
        const char*& out = require(value, "value");
        out = f.filter->results().get_string(require_string(name, "name")).c_str();
    });
}

sf_status sf_filter_result_sequence(sf_filter filter, const char* name, sf_sequence* out) {
    return on_filter(filter, [&](sf_filter_s& f) {
        sf_sequence& dst = require(out, "out");
        dst = nullptr;
        const auto image = f.filter->results().image(require_string(name, "name"));
        auto copy = std::make_unique<Sequence>(image->shape());
        copy->copy_samples_from(*image);
        copy->copy_attributes_from(*image);
        dst = new sf_sequence_s{std::move(copy)};
    });
}

sf_status sf_filter_set_progress(sf_filter filter, sf_progress_callback callback, void* user) {
    return on_filter(filter, [&](sf_filter_s& f) {
        f.progress = callback;
        f.progress_user = user;
    });
}

sf_status sf_filter_image_result_count(sf_filter filter, int* count) {
    return on_filter(filter, [&](sf_filter_s& f) {
        require(count, "count") = static_cast<int>(f.filter->image_results().size());
    });
}

sf_status sf_filter_image_result_name(sf_filter filter, int index, const char** name) {
    return on_filter(filter, [&](sf_filter_s& f) {
        const auto& names = f.filter->image_results();
        require(name, "name") = nullptr;
        if (index < 0 || static_cast<size_t>(index) >= names.size())
            throw Error(Status::InvalidArgument, "image result index " + std::to_string(index) + " out of range");
        *name = names[static_cast<size_t>(index)].c_str();
    });
}

sf_status sf_filter_check_image_output(sf_filter filter, const char* name, const char* pattern, const char* input_pattern,
                                       const char* frames, const char* other_pattern) {
    return on_filter(filter, [&](sf_filter_s& f) {
        const std::string input = require_string(input_pattern, "input_pattern");
        // The run's frame numbers: the selection, or every frame of the input on disk (none: the run
        // says so before its work).
        std::vector<int64_t> numbers;
        if (frames && *frames) {
            numbers = parse_frame_spec(frames);
        } else {
            try {
                numbers = FramePattern(input).scan();
            } catch (const Error&) {
            }
        }
        check_image_result_output(*f.filter, require_string(name, "name"), require_string(pattern, "pattern"), numbers,
                                  input, other_pattern ? other_pattern : "");
    });
}

sf_status sf_filter_execute(sf_filter filter, sf_sequence input, sf_sequence output) {
    return on_filter(filter, [&](sf_filter_s& f) {
        Sequence& in = require_sequence(input, "input");
        Sequence& out = require_sequence(output, "output");
        f.filter->execute(in, out, make_progress(f.progress, f.progress_user));
    });
}

}  // extern "C"
