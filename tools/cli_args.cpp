#include "cli_args.hpp"

#include <algorithm>

#include <statfilter/statfilter.h>

namespace statfilter_cli {
namespace {

std::string dashes(std::string s) {
    std::replace(s.begin(), s.end(), '_', '-');
    return s;
}

// Optimal string alignment distance: insertions, deletions, substitutions and swaps of two
// neighbours ("rnak" is one step from "rank").
size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
    for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (size_t i = 1; i <= a.size(); ++i)
        for (size_t j = 1; j <= b.size(); ++j) {
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[a.size()][b.size()];
}

bool contains(const std::set<std::string>& names, const std::string& name) {
    for (const auto& n : names)
        if (dashes(n) == dashes(name)) return true;
    return false;
}

// The parameter names of one filter, or nothing when it cannot be created (an unavailable plugin).
void add_parameter_names(const char* filter_name, std::set<std::string>& out) {
    sf_filter filter = nullptr;
    if (sf_filter_create(filter_name, &filter) != SF_OK) return;
    int count = 0;
    if (sf_filter_param_count(filter, &count) == SF_OK)
        for (int p = 0; p < count; ++p) {
            sf_param_info info;
            info.struct_size = sizeof info;
            if (sf_filter_param_info(filter, p, &info) == SF_OK) out.insert(info.name);
        }
    sf_filter_release(filter);
}

}  // namespace

const std::set<std::string>& filter_parameter_names() {
    static const std::set<std::string> names = [] {
        std::set<std::string> out;
        for (int i = 0; i < sf_filter_count(); ++i) add_parameter_names(sf_filter_name(i), out);
        return out;
    }();
    return names;
}

std::set<std::string> filter_parameter_names(const std::string& filter) {
    std::set<std::string> out;
    add_parameter_names(filter.c_str(), out);
    return out;
}

std::string nearest_name(const std::string& given, const std::set<std::string>& known) {
    // Near enough to be a typo: one edit in a short name, two in a longer one, never the whole name.
    const size_t limit = given.size() <= 4 ? 1 : 2;
    size_t best = limit + 1;
    std::string nearest;
    for (const auto& name : known) {
        const size_t d = edit_distance(dashes(given), dashes(name));
        if (d < best && d < name.size()) best = d, nearest = name;
    }
    return nearest;
}

std::string unknown_option_message(const std::string& given, const std::set<std::string>& known) {
    const std::string suggestion = nearest_name(given, known);
    // Spelt with dashes, as options are (parameters take either).
    return "unknown option --" + given + (suggestion.empty() ? "" : " (did you mean --" + dashes(suggestion) + "?)");
}

Args::Args(int argc, char** argv, int first, const std::set<std::string>& flags, const std::set<std::string>& options,
           const std::set<std::string>& parameters) {
    const auto unknown = [&](const std::string& name) {
        std::set<std::string> known = flags;
        known.insert(options.begin(), options.end());
        known.insert(parameters.begin(), parameters.end());
        return UsageError(unknown_option_message(name, known));
    };
    for (int i = first; i < argc; ++i) {
        std::string arg = argv[i];
        if (arg.size() < 3 || arg.compare(0, 2, "--") != 0) {
            if (arg == "-h") { flags_.insert("help"); continue; }
            if (arg == "-q") { flags_.insert("quiet"); continue; }
            if (arg == "-o" && options.count("output-file")) {  // a command's output file (plan -o PLAN)
                if (i + 1 >= argc) throw UsageError("-o needs a file");
                options_["output-file"] = argv[++i];
                continue;
            }
            if (arg.size() == 2 && arg[0] == '-' && arg != "-") throw UsageError("unknown option " + arg);
            positionals_.push_back(arg);
            continue;
        }
        std::string name = arg.substr(2), value;
        bool has_value = false;
        const size_t eq = name.find('=');
        if (eq != std::string::npos) {
            value = name.substr(eq + 1);
            name = name.substr(0, eq);
            has_value = true;
        }
        const bool is_option = options.count(name) > 0, is_parameter = !is_option && contains(parameters, name);
        if (flags.count(name)) {
            if (has_value) throw UsageError("--" + name + " takes no value");
            flags_.insert(name);
            continue;
        }
        if (!is_option && !is_parameter) throw unknown(name);
        if (!has_value) {
            if (i + 1 >= argc) throw UsageError("--" + name + " needs a value");
            value = argv[++i];
        }
        if (is_option) {
            options_[name] = value;
        } else {
            extras_.emplace_back(name, value);
        }
    }
}

std::string Args::option(const std::string& name, const std::string& fallback) const {
    auto it = options_.find(name);
    return it == options_.end() ? fallback : it->second;
}

}  // namespace statfilter_cli
