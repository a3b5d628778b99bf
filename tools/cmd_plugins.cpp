// statfilter plugins: every filter the library finds, built-in or plugin, with kind, version,
// origin and parameters; plugins that cannot be used are listed with the reason.
#include <cstdio>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "cli_json.hpp"
#include "commands.hpp"

namespace statfilter_cli {
namespace {

const char* kind_name(sf_filter_kind kind) { return kind == SF_FILTER_SINGLE_FRAME ? "single-frame" : "temporal"; }

const char* param_type_name(sf_param_type t) {
    switch (t) {
    case SF_PARAM_INT: return "int";
    case SF_PARAM_FLOAT: return "float";
    case SF_PARAM_STRING: return "text";
    }
    return "?";
}

struct Param {
    std::string name, type, default_value, description, choices;
};

std::vector<Param> params_of(const std::string& name) {
    FilterHandle filter(name);
    int count = 0;
    filter.check(sf_filter_param_count(filter.get(), &count));
    std::vector<Param> out;
    for (int i = 0; i < count; ++i) {
        sf_param_info info;
        info.struct_size = sizeof info;
        filter.check(sf_filter_param_info(filter.get(), i, &info));
        out.push_back({info.name, param_type_name(info.type), info.default_value, info.description, info.choices});
    }
    return out;
}

}  // namespace

int cmd_plugins(int argc, char** argv) {
    const Args args(argc, argv, 2, {"json", "help"}, {});
    if (args.flag("help")) {
        std::printf("usage: statfilter plugins [--json]\n\n"
                    "Lists every filter: the built-ins, then the plugins (statfilter_NAME.so) found in the\n"
                    "directories of $STATFILTER_PLUGIN_PATH (colon-separated) and next to libstatfilter,\n"
                    "with kind (temporal, or single-frame: usable as --prefilter), version, origin and\n"
                    "parameters. A plugin that cannot be used is listed with the reason.\n");
        return 0;
    }
    if (!args.positionals().empty()) throw UsageError("takes no arguments (see --help)");
    if (!args.extras().empty()) throw UsageError("unknown option '--" + args.extras().front().first + "'");
    const bool json = args.flag("json");
    std::string j = "[";
    const int count = sf_filter_info_count();
    for (int i = 0; i < count; ++i) {
        sf_filter_info info;
        sf_filter_info_init(&info);
        check(sf_filter_info_at(i, &info));
        std::vector<Param> params;
        std::string problem = info.problem;
        // A filter that loaded but cannot make an instance now is listed as unavailable, not fatal.
        if (info.available) {
            try {
                params = params_of(info.name);
            } catch (const Failure& e) {
                info.available = 0;
                problem = e.what();
            }
        }
        if (json) {
            j += std::string(i ? "," : "") + "\n  {\"name\": " + json_string(info.name) + ", \"kind\": " +
                 json_string(kind_name(info.kind)) + ", \"version\": " + json_string(info.version) +
                 ", \"origin\": " + json_string(info.origin) + ", \"available\": " +
                 (info.available ? "true" : "false") + ", \"problem\": " + json_string(problem) +
                 ", \"description\": " + json_string(info.description) + ", \"parameters\": [";
            for (size_t p = 0; p < params.size(); ++p)
                j += std::string(p ? ", " : "") + "{\"name\": " + json_string(params[p].name) + ", \"type\": " +
                     json_string(params[p].type) + ", \"default\": " + json_string(params[p].default_value) +
                     ", \"choices\": " + json_string(params[p].choices) + ", \"description\": " +
                     json_string(params[p].description) + "}";
            j += "]}";
            continue;
        }
        // A plugin that did not load declares nothing: its kind is unknown.
        const char* kind = info.available || *info.version ? kind_name(info.kind) : "-";
        std::printf("%-16s %-12s %-8s %s\n", info.name, kind, *info.version ? info.version : "-", info.origin);
        if (*info.description) std::printf("    %s\n", info.description);
        if (!info.available) std::printf("    UNAVAILABLE: %s\n", problem.c_str());
        for (const Param& p : params) {
            std::string detail = p.type;
            if (!p.choices.empty()) detail += ": " + p.choices;
            std::printf("    --%-20s %s (%s; default '%s')\n", p.name.c_str(), p.description.c_str(), detail.c_str(),
                        p.default_value.c_str());
        }
    }
    if (json) std::printf("%s\n]\n", j.c_str());
    return 0;
}

}  // namespace statfilter_cli
