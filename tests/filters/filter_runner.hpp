// Runs a registered filter with text parameters, as the C ABI and the CLI would.
#pragma once
#include <map>
#include <string>

#include "statfilter/filter_registry.hpp"

namespace statfilter::test {

struct FilterRun {
    std::unique_ptr<Sequence> output;
    std::unique_ptr<Filter> filter;
    double result(const std::string& name) const { return filter->results().get_float(name); }
};

inline FilterRun run_filter(const std::string& name, const Sequence& input,
                      const std::map<std::string, std::string>& params = {}) {
    FilterRun r;
    r.filter = create_filter(name);
    for (const auto& [k, v] : params) r.filter->params().set_string(k, v);
    r.output = std::make_unique<Sequence>(input.shape());
    r.filter->execute(input, *r.output, Progress());
    return r;
}

// The filter on the raw values (transform=none unless given), with the plain inverse and no firefly
// replacement: the linear algebra the references check.
inline FilterRun run_linear(const std::string& name, const Sequence& input,
                            std::map<std::string, std::string> params = {}) {
    params.emplace("transform", "none");
    params.emplace("keep_mean", "0");
    params.emplace("firefly_z", "0");
    return run_filter(name, input, params);
}

}  // namespace statfilter::test
