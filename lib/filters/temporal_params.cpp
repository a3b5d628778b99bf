#include "filters/temporal_params.hpp"

namespace statfilter {

std::vector<ParamSpec> temporal_common_params() {
    std::vector<ParamSpec> p;
    {
        ParamSpec s;
        s.name = "transform";
        s.type = ParamType::String;
        s.default_value = "log";  // measured best on every scene and level: docs/methods.md
        s.choices = {"none", "sqrt", "log"};
        s.description = "variance-stabilising transform (signed) applied before the temporal basis and undone after";
        p.push_back(s);
    }
    {
        ParamSpec s;
        s.name = "nonfinite";
        s.type = ParamType::String;
        s.default_value = "error";
        s.choices = {"error", "repair"};
        s.description = "NaN/Inf input: fail naming the sample, or replace by the series' finite mean and count";
        p.push_back(s);
    }
    {
        ParamSpec s;
        s.name = "shared_basis";
        s.type = ParamType::Int;
        s.default_value = "1";
        s.min = 0;
        s.max = 1;
        s.description = "1: all channels share one temporal basis; 0: one basis per channel";
        p.push_back(s);
    }
    {
        ParamSpec s;
        s.name = "memory_mb";
        s.type = ParamType::Float;
        s.default_value = "512";
        s.min = 1;
        s.max = 1e7;
        s.description = "working memory budget for pixel tiles, in MiB (results do not depend on it)";
        p.push_back(s);
    }
    return p;
}

ParamSpec rank_param(const char* default_value) {
    ParamSpec s;
    s.name = "rank";
    s.type = ParamType::String;
    s.default_value = default_value;
    s.choices = {"auto", "energy"};
    s.accepts_integer = true;
    s.min = 0;
    s.max = 1000000;
    s.description = "temporal components kept: a count (0 = temporal mean), auto (Gavish-Donoho optimal hard "
                    "threshold), or energy (see 'energy')";
    return s;
}

TemporalSetup temporal_setup(const ParamSet& params) {
    TemporalSetup t;
    t.prep.transform = parse_value_transform(params.get_string("transform"));
    t.nonfinite = parse_nonfinite_policy(params.get_string("nonfinite"));
    t.prep.repair_nonfinite = t.nonfinite == NonFinitePolicy::Repair;
    t.shared_basis = params.get_int("shared_basis") != 0;
    t.budget_bytes = params.get_float("memory_mb") * 1024.0 * 1024.0;
    return t;
}

std::vector<ChannelSelection> basis_groups(const Shape& shape, bool shared_basis) {
    if (shared_basis) return {ChannelSelection::all(shape)};
    std::vector<ChannelSelection> groups;
    for (int64_t c = 0; c < shape.channels; ++c) groups.push_back(ChannelSelection::one(c));
    return groups;
}

}  // namespace statfilter

namespace statfilter {

ParamSpec energy_param() {
    ParamSpec s;
    s.name = "energy";
    s.type = ParamType::Float;
    s.default_value = "0.99";
    s.min = 0;
    s.max = 1;
    s.description = "with rank=energy: keep the fewest components holding this fraction of the variance";
    return s;
}

RankChoice choose_rank(const ParamSet& params, const std::vector<double>& eigenvalues, int64_t series, int64_t frames) {
    RankChoice choice;
    const std::string& rank = params.get_string("rank");
    int64_t fixed = 0;
    if (rank == "auto") {
        choice = gavish_donoho_rank(eigenvalues, series, frames);
    } else if (rank == "energy") {
        choice.rank = energy_rank(eigenvalues, params.get_float("energy"));
    } else if (params.get_integer_choice("rank", fixed)) {
        choice.rank = fixed;
    }
    choice.rank = std::min(choice.rank, max_useful_rank(series, frames));
    return choice;
}

}  // namespace statfilter
