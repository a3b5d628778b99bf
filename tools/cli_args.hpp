// A small command-line parser: --flag, --option VALUE (or --option=VALUE), positionals, and the
// leftover --name VALUE pairs that become filter parameters.
#pragma once
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace statfilter_cli {

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class Args {
public:
    // flags take no value; options take one. Anything else given as --name VALUE is kept as extra.
    Args(int argc, char** argv, int first, const std::set<std::string>& flags, const std::set<std::string>& options);

    bool flag(const std::string& name) const { return flags_.count(name) > 0; }
    std::string option(const std::string& name, const std::string& fallback = "") const;
    bool has(const std::string& name) const { return options_.count(name) > 0; }
    void set_option(const std::string& name, const std::string& value) { options_[name] = value; }
    const std::vector<std::string>& positionals() const { return positionals_; }
    // --name VALUE pairs that were neither flags nor options, in order given.
    const std::vector<std::pair<std::string, std::string>>& extras() const { return extras_; }

private:
    std::set<std::string> flags_;
    std::map<std::string, std::string> options_;
    std::vector<std::string> positionals_;
    std::vector<std::pair<std::string, std::string>> extras_;
};

}  // namespace statfilter_cli
