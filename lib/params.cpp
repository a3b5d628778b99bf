#include "statfilter/params.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "statfilter/error.hpp"
#include "statfilter/sequence.hpp"

namespace statfilter {
namespace {

bool parse_int(const std::string& text, int64_t& out) {
    if (text.empty()) return false;
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (errno != 0 || *end != '\0') return false;
    out = v;
    return true;
}

bool parse_float(const std::string& text, double& out) {
    if (text.empty()) return false;
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (errno == ERANGE || *end != '\0') return false;
    out = v;
    return true;
}

std::string range_text(const ParamSpec& s) {
    return "[" + format_number(s.min) + ", " + format_number(s.max) + "]";
}

void check_range(const ParamSpec& s, double v) {
    if (!(v >= s.min && v <= s.max))  // also rejects NaN
        throw Error(Status::InvalidArgument,
                    "parameter '" + s.name + "' = " + format_number(v) + " is outside " + range_text(s));
}

}  // namespace

namespace {

ParamSpec numeric_param(ParamType type, const std::string& name, const std::string& default_value, double min,
                        double max, const std::string& description) {
    ParamSpec s;
    s.name = name;
    s.type = type;
    s.default_value = default_value;
    s.min = min;
    s.max = max;
    s.description = description;
    return s;
}

}  // namespace

ParamSpec int_param(const std::string& name, const std::string& default_value, double min, double max,
                    const std::string& description) {
    return numeric_param(ParamType::Int, name, default_value, min, max, description);
}

ParamSpec float_param(const std::string& name, const std::string& default_value, double min, double max,
                      const std::string& description) {
    return numeric_param(ParamType::Float, name, default_value, min, max, description);
}

ParamSpec choice_param(const std::string& name, const std::string& default_value, std::vector<std::string> choices,
                       const std::string& description) {
    ParamSpec s;
    s.name = name;
    s.type = ParamType::String;
    s.default_value = default_value;
    s.choices = std::move(choices);
    s.description = description;
    return s;
}

std::string format_number(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

ParamSet::ParamSet(std::vector<ParamSpec> specs) : specs_(std::move(specs)) {
    for (auto& s : specs_) {
        s.choices_text.clear();
        for (const auto& c : s.choices) s.choices_text += (s.choices_text.empty() ? "" : ",") + c;
        values_[s.name].type = s.type;
        set_string(s.name, s.default_value);
    }
}

const ParamSpec& ParamSet::spec(const std::string& name) const {
    for (const auto& s : specs_)
        if (s.name == name) return s;
    std::string known;
    for (const auto& s : specs_) known += (known.empty() ? "" : ", ") + s.name;
    throw Error(Status::NotFound, "unknown parameter '" + name + "'" + (known.empty() ? "" : " (parameters: " + known + ")"));
}

bool ParamSet::has(const std::string& name) const { return values_.count(name) != 0; }

void ParamSet::set_int(const std::string& name, int64_t value) {
    const ParamSpec& s = spec(name);
    ParamValue& v = values_[name];
    switch (s.type) {
    case ParamType::Int:
        check_range(s, static_cast<double>(value));
        v.i = value;
        v.f = static_cast<double>(value);
        v.s = std::to_string(value);
        return;
    case ParamType::Float:
        set_float(name, static_cast<double>(value));
        return;
    case ParamType::String:
        if (!s.accepts_integer) throw Error(Status::InvalidArgument, "parameter '" + name + "' takes text, not a number");
        check_range(s, static_cast<double>(value));
        v.i = value;
        v.f = static_cast<double>(value);
        v.s = std::to_string(value);
        return;
    }
}

void ParamSet::set_float(const std::string& name, double value) {
    const ParamSpec& s = spec(name);
    ParamValue& v = values_[name];
    if (s.type == ParamType::Float) {
        check_range(s, value);
        v.f = value;
        v.i = static_cast<int64_t>(value);
        v.s = format_number(value);
        return;
    }
    if (std::isfinite(value) && value == std::floor(value) && std::fabs(value) < 9.2e18) {
        set_int(name, static_cast<int64_t>(value));
        return;
    }
    throw Error(Status::InvalidArgument, "parameter '" + name + "' takes an integer, got " + format_number(value));
}

void ParamSet::set_string(const std::string& name, const std::string& text) {
    const ParamSpec& s = spec(name);
    int64_t i = 0;
    double f = 0;
    switch (s.type) {
    case ParamType::Int:
        if (!parse_int(text, i)) throw Error(Status::InvalidArgument, "parameter '" + name + "' takes an integer, got '" + text + "'");
        set_int(name, i);
        return;
    case ParamType::Float:
        if (!parse_float(text, f)) throw Error(Status::InvalidArgument, "parameter '" + name + "' takes a number, got '" + text + "'");
        set_float(name, f);
        return;
    case ParamType::String:
        if (s.accepts_integer && parse_int(text, i)) {
            set_int(name, i);
            return;
        }
        if (!s.choices.empty()) {
            bool ok = false;
            for (const auto& c : s.choices) ok = ok || c == text;
            if (!ok) {
                std::string list;
                for (const auto& c : s.choices) list += (list.empty() ? "" : ", ") + c;
                throw Error(Status::InvalidArgument, "parameter '" + name + "' = '" + text + "' is not one of: " + list +
                                                         (s.accepts_integer ? ", or an integer in " + range_text(s) : ""));
            }
        }
        ParamValue& v = values_[name];
        v.s = text;
        v.i = 0;
        v.f = 0;
        return;
    }
}

int64_t ParamSet::get_int(const std::string& name) const {
    const ParamSpec& s = spec(name);
    if (s.type == ParamType::String && !s.accepts_integer)
        throw Error(Status::InvalidArgument, "parameter '" + name + "' is text");
    return values_.at(name).i;
}

double ParamSet::get_float(const std::string& name) const {
    const ParamSpec& s = spec(name);
    if (s.type == ParamType::String && !s.accepts_integer)
        throw Error(Status::InvalidArgument, "parameter '" + name + "' is text");
    return values_.at(name).f;
}

const std::string& ParamSet::get_string(const std::string& name) const {
    spec(name);
    return values_.at(name).s;
}

bool ParamSet::get_integer_choice(const std::string& name, int64_t& value) const {
    int64_t i = 0;
    if (!parse_int(get_string(name), i)) return false;
    value = i;
    return true;
}

void Results::set(const std::string& name, double value) {
    if (!values_.count(name)) names_.push_back(name);
    ParamValue& v = values_[name];
    v.type = ParamType::Float;
    v.f = value;
    v.i = static_cast<int64_t>(value);
    v.s = format_number(value);
}

void Results::set(const std::string& name, const std::string& value) {
    if (!values_.count(name)) names_.push_back(name);
    ParamValue& v = values_[name];
    v.type = ParamType::String;
    v.s = value;
}

void Results::set_image(const std::string& name, std::shared_ptr<const Sequence> image) {
    set(name, "image " + to_string(image->shape()));
    images_[name] = std::move(image);
}

std::shared_ptr<const Sequence> Results::image(const std::string& name) const {
    auto it = images_.find(name);
    if (it == images_.end()) throw Error(Status::NotFound, "no image result '" + name + "'");
    return it->second;
}

const ParamValue& Results::find(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) throw Error(Status::NotFound, "no result '" + name + "' (has the filter run?)");
    return it->second;
}

double Results::get_float(const std::string& name) const {
    const ParamValue& v = find(name);
    if (v.type != ParamType::Float) throw Error(Status::InvalidArgument, "result '" + name + "' is text");
    return v.f;
}

const std::string& Results::get_string(const std::string& name) const { return find(name).s; }

void Results::copy(const Results& from, const std::string& name, const std::string& as) {
    const ParamValue& v = from.find(name);
    if (!values_.count(as)) names_.push_back(as);
    values_[as] = v;
    auto image = from.images_.find(name);
    if (image != from.images_.end()) images_[as] = image->second;
}

}  // namespace statfilter
