#include "cli_args.hpp"

namespace statfilter_cli {

Args::Args(int argc, char** argv, int first, const std::set<std::string>& flags, const std::set<std::string>& options) {
    for (int i = first; i < argc; ++i) {
        std::string arg = argv[i];
        if (arg.size() < 3 || arg.compare(0, 2, "--") != 0) {
            if (arg.size() == 2 && arg[0] == '-' && arg != "-" && arg[1] != 'h' && arg[1] != 'q')
                throw UsageError("unknown option '" + arg + "'");
            if (arg == "-h") { flags_.insert("help"); continue; }
            if (arg == "-q") { flags_.insert("quiet"); continue; }
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
        if (flags.count(name)) {
            if (has_value) throw UsageError("--" + name + " takes no value");
            flags_.insert(name);
            continue;
        }
        if (!has_value) {
            if (i + 1 >= argc) throw UsageError("--" + name + " needs a value");
            value = argv[++i];
        }
        if (options.count(name)) {
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
