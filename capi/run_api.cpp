// sf_filter_run: a filter from files to files through the scheduler (streamed where it can be).
#include "api_guard.hpp"
#include "options.hpp"
#include "pipeline/frame_source.hpp"
#include "pipeline/memory_budget.hpp"
#include "pipeline/scheduler.hpp"
#include "statfilter/sequence_io.hpp"

using namespace statfilter;
using namespace statfilter::capi;

extern "C" {

void sf_run_options_init(sf_run_options* options) {
    if (!options) return;
    std::memset(options, 0, sizeof *options);
    options->struct_size = sizeof *options;
}

sf_status sf_memory_size_parse(const char* text, int64_t* bytes) {
    return guarded([&] { require(bytes, "bytes") = parse_memory_size(require_string(text, "text")); });
}

sf_status sf_filter_run(sf_filter filter, const char* input_pattern, const sf_read_options* read,
                        const char* output_pattern, const sf_write_options* write, const sf_run_options* run) {
    std::string* handle_error = filter ? &filter->last_error : nullptr;
    return guarded([&] {
        Filter& f = *require(filter, "filter").filter;
        const sf_run_options r = read_versioned(run, sf_run_options_init);
        check_run_options(r, "the default", "every core");
        const std::string in = require_string(input_pattern, "input_pattern");
        const std::string out = require_string(output_pattern, "output_pattern");
        f.check();  // the filter's configuration first: cheaper than opening every frame
        ReadOptions ro = read_options_from(read);
        WriteOptions wo = write_options_from(write);
        ro.progress = Progress();
        wo.progress = Progress();
        auto source = open_frame_source(in, ro);
        OutputChecks checks;
        checks.width = source->shape().width;
        checks.height = source->shape().height;
        checks.input_pattern = in;
        checks.overwrite = r.overwrite != 0;
        auto sink = open_frame_sink(out, wo, source->attributes(), checks);
        // Provenance in every frame: who made it, with what (the parameters not at their defaults).
        std::string changed;
        for (const ParamSpec& spec : f.params().specs()) {
            const std::string& value = f.params().get_string(spec.name);
            if (value != spec.default_value) changed += (changed.empty() ? "" : " ") + spec.name + "=" + value;
        }
        sink->set_attribute("statfilter:version", sf_version_string());
        sink->set_attribute("statfilter:filter", filter->name);
        sink->set_attribute("statfilter:parameters", changed);
        RunOptions options;
        options.budget_bytes = static_cast<double>(r.memory);
        options.threads = r.threads;
        options.progress = make_progress(r.progress, r.progress_user);
        f.execute(*source, *sink, options);
    }, handle_error);
}

}  // extern "C"
