// Named filter parameters: one table per filter serves the C ABI, Python and the CLI.
#pragma once
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace statfilter {

enum class ParamType { Int = 0, Float = 1, String = 2 };

struct ParamSpec {
    std::string name;
    ParamType type = ParamType::Int;
    std::string default_value;  // as text
    std::string description;
    double min = -std::numeric_limits<double>::infinity();
    double max = std::numeric_limits<double>::infinity();
    std::vector<std::string> choices;  // String: allowed words (empty = free text)
    bool accepts_integer = false;      // String: an integer in [min, max] is also allowed (e.g. rank)
    std::string choices_text;          // the choices as one comma list (filled by ParamSet)
};

// Table entries, for filters to declare their parameters in one line each.
ParamSpec int_param(const std::string& name, const std::string& default_value, double min, double max,
                    const std::string& description);
ParamSpec float_param(const std::string& name, const std::string& default_value, double min, double max,
                      const std::string& description);
ParamSpec choice_param(const std::string& name, const std::string& default_value, std::vector<std::string> choices,
                       const std::string& description);

// A value in every representation a caller may ask for.
struct ParamValue {
    ParamType type = ParamType::Int;
    int64_t i = 0;
    double f = 0;
    std::string s;
};

class ParamSet {
public:
    ParamSet() = default;
    explicit ParamSet(std::vector<ParamSpec> specs);

    // Setters validate against the spec and leave the old value on error.
    void set_int(const std::string& name, int64_t value);
    void set_float(const std::string& name, double value);
    // Parses text for numeric parameters, so text from a command line can set anything.
    void set_string(const std::string& name, const std::string& value);

    int64_t get_int(const std::string& name) const;
    double get_float(const std::string& name) const;
    const std::string& get_string(const std::string& name) const;
    // For a string parameter that accepts an integer: true and the number if it holds one.
    bool get_integer_choice(const std::string& name, int64_t& value) const;

    const std::vector<ParamSpec>& specs() const { return specs_; }
    bool has(const std::string& name) const;

private:
    const ParamSpec& spec(const std::string& name) const;
    std::vector<ParamSpec> specs_;
    std::map<std::string, ParamValue> values_;
};

class Sequence;

// Results a filter reports after running: numbers and text (e.g. the rank chosen by rank=auto) and
// images (e.g. a per-pixel rank map). An image result's text value describes it.
class Results {
public:
    void clear() { values_.clear(); names_.clear(); images_.clear(); }
    void set(const std::string& name, double value);
    void set(const std::string& name, const std::string& value);
    void set_image(const std::string& name, std::shared_ptr<const Sequence> image);
    // Throws Error(NotFound) unless name is an image result.
    std::shared_ptr<const Sequence> image(const std::string& name) const;
    double get_float(const std::string& name) const;
    const std::string& get_string(const std::string& name) const;
    const std::vector<std::string>& names() const { return names_; }
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    // Result `name` of `from` as `as`, its type (number, text, image) kept.
    void copy(const Results& from, const std::string& name, const std::string& as);

private:
    const ParamValue& find(const std::string& name) const;
    std::map<std::string, ParamValue> values_;
    std::vector<std::string> names_;
    std::map<std::string, std::shared_ptr<const Sequence>> images_;
};

std::string format_number(double value);

}  // namespace statfilter
