#include "filters/prefilter.hpp"

#include <algorithm>

#include "statfilter/error.hpp"
#include "statfilter/filter_registry.hpp"

namespace statfilter {

std::vector<ParamSpec> prefilter_params() {
    ParamSpec name = choice_param("prefilter", "", {},
                                  "single-frame filter run on every frame first (e.g. oidn, diffusion or a plugin); "
                                  "empty = none");
    ParamSpec list = choice_param("prefilter_params", "", {},
                                  "the prefilter's parameters as name=value,name=value (e.g. quality=high); "
                                  "its defaults otherwise");
    return {name, list};
}

void set_param_list(ParamSet& params, const std::string& list, const std::string& what) {
    std::vector<std::pair<std::string, std::string>> items;
    size_t start = 0;
    while (start < list.size()) {
        const size_t comma = std::min(list.find(',', start), list.size());
        const std::string piece = list.substr(start, comma - start);
        const size_t eq = piece.find('=');
        if (eq != std::string::npos && eq > 0) {
            items.emplace_back(piece.substr(0, eq), piece.substr(eq + 1));
        } else if (!items.empty()) {
            items.back().second += "," + piece;
        } else if (!piece.empty()) {
            throw Error(Status::InvalidArgument, what + ": expected name=value, got '" + piece + "'");
        }
        start = comma + 1;
    }
    for (const auto& [name, value] : items) {
        try {
            params.set_string(name, value);
        } catch (const Error& e) {
            throw Error(e.status(), what + ": " + e.what());
        }
    }
}

std::unique_ptr<Sequence> run_prefilter(const ParamSet& params, const Sequence& input, const Progress& progress,
                                        Results& results) {
    const std::string& name = params.get_string("prefilter");
    if (name.empty()) return nullptr;
    const FilterEntry& entry = find_filter(name);
    auto filter = entry.create();  // a plugin that cannot be used throws its own error here
    if (entry.kind != FilterKind::SingleFrame)
        throw Error(Status::InvalidArgument, "prefilter '" + name + "' is a temporal filter; a prefilter works frame by "
                                             "frame (single-frame filters: see statfilter plugins)");
    set_param_list(filter->params(), params.get_string("prefilter_params"), "prefilter_params");
    auto out = std::make_unique<Sequence>(input.shape());
    filter->execute(input, *out, progress);
    const Results& own = filter->results();
    for (const auto& result : own.names()) {
        try {
            results.set("prefilter." + result, own.get_float(result));
        } catch (const Error&) {  // a text result
            results.set("prefilter." + result, own.get_string(result));
        }
    }
    return out;
}

}  // namespace statfilter
