#include "cli_run_setup.hpp"

#include <cstdlib>

#include "commands.hpp"

namespace statfilter_cli {
namespace {

std::string dashes_to_underscores(std::string s) {
    for (char& c : s)
        if (c == '-') c = '_';
    return s;
}

}  // namespace

const std::set<std::string> kRunOptions = {"memory", "threads"};
const char* const kRunHelp =
    "run:\n"
    "  --memory SIZE           memory budget, e.g. 512M or 6G (default: half of physical memory); a run\n"
    "                          that cannot fit is refused before any work, naming the size it needs\n"
    "  --threads N             threads (default 0: every core)\n"
    "  --overwrite             let OUT replace frames of IN (refused otherwise)\n";

std::string denoise_method(const Args& args) {
    bool prefiltered = false, quality = false;
    for (const auto& [name, value] : args.extras()) {
        prefiltered = prefiltered || (name == "prefilter" && !value.empty());
        quality = quality || name == "quality";
    }
    // --quality is a parameter of the auto filter, which picks the method itself.
    if (quality && !args.option("method").empty() && args.option("method") != "auto")
        throw UsageError("--quality picks the method itself (it is a parameter of --method auto); give one or the other");
    if (quality) return "auto";
    return args.option("method", prefiltered ? kDefaultMethodWithPrefilter : kDefaultMethod);
}

void set_filter_parameters(FilterHandle& filter, const Args& args) {
    for (const auto& [name, value] : args.extras())
        filter.check(sf_filter_set_string(filter.get(), dashes_to_underscores(name).c_str(), value.c_str()));
}

sf_run_options run_options(const Args& args) {
    sf_run_options run;
    sf_run_options_init(&run);
    if (args.has("memory") && sf_memory_size_parse(args.option("memory").c_str(), &run.memory) != SF_OK)
        throw UsageError("--memory: " + std::string(sf_last_error()));
    if (args.has("threads")) {
        const std::string text = args.option("threads");
        char* end = nullptr;
        const long n = std::strtol(text.c_str(), &end, 10);
        if (text.empty() || *end != '\0' || n < 0 || n > 4096)
            throw UsageError("--threads takes a count of threads (0 = every core), got '" + text + "'");
        run.threads = static_cast<int>(n);
    }
    run.overwrite = args.flag("overwrite") ? 1 : 0;
    return run;
}

void set_vectors_input(FilterHandle& filter, const Args& args, const std::string& method) {
    if (args.has("vectors") && sf_filter_set_input_files(filter.get(), "vectors", args.option("vectors").c_str()) != SF_OK)
        throw UsageError("--vectors: method " + method + " does not use motion vectors (" +
                         sf_filter_last_error(filter.get()) + "); they are for the hybrid and --quality");
}

const char* const kVectorsHelp =
    "  --vectors PATTERN       the renderer's motion vectors (Cycles Vector pass) for the hybrid and --quality\n"
    "                          balanced/high; of a multilayer file (such as the input's own), its Vector layer;\n"
    "                          or a layer's name (ViewLayer.Vector): that layer of the input's files\n";

}  // namespace statfilter_cli
