// A small command-line parser: --flag, --option VALUE (or --option=VALUE), positionals, and the
// --name VALUE pairs that are filter parameters. Any other --name is a usage error that names it and
// suggests the nearest known option.
#pragma once
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace statfilter_cli {

// Exit code 2: the command line is wrong (main prints the message).
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The parameter names of every filter the library offers, built-in or plugin (from the C ABI).
const std::set<std::string>& filter_parameter_names();
// The parameter names of one filter.
std::set<std::string> filter_parameter_names(const std::string& filter);

// The known name nearest to the given one (edit distance, '-' and '_' alike) when it is near enough
// to be a typo, else "".
std::string nearest_name(const std::string& given, const std::set<std::string>& known);
// "unknown option --rnak (did you mean --rank?)", the suggestion spelt with dashes.
std::string unknown_option_message(const std::string& given, const std::set<std::string>& known);

class Args {
public:
    // flags take no value; options take one. parameters are the names that may be given as --name VALUE
    // (with '-' or '_') and are kept as extras: by default those of every filter; {} for a command
    // that takes none.
    Args(int argc, char** argv, int first, const std::set<std::string>& flags, const std::set<std::string>& options,
         const std::set<std::string>& parameters = filter_parameter_names());

    bool flag(const std::string& name) const { return flags_.count(name) > 0; }
    std::string option(const std::string& name, const std::string& fallback = "") const;
    bool has(const std::string& name) const { return options_.count(name) > 0; }
    void set_option(const std::string& name, const std::string& value) { options_[name] = value; }
    const std::vector<std::string>& positionals() const { return positionals_; }
    // --name VALUE pairs that were parameters, in order given, names as given.
    const std::vector<std::pair<std::string, std::string>>& extras() const { return extras_; }

private:
    std::set<std::string> flags_;
    std::map<std::string, std::string> options_;
    std::vector<std::string> positionals_;
    std::vector<std::pair<std::string, std::string>> extras_;
};

}  // namespace statfilter_cli
