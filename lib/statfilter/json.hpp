// A small JSON reader and writer helpers for the files statfilter exchanges (crop windows).
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace statfilter {

class JsonValue {
public:
    enum class Type { Null, Bool, Number, String, Array, Object };

    Type type() const { return type_; }
    bool is(Type t) const { return type_ == t; }
    double number() const { return number_; }
    bool boolean() const { return boolean_; }
    const std::string& string() const { return string_; }
    const std::vector<JsonValue>& array() const { return array_; }
    // Object members in file order; find returns nullptr when the key is absent.
    const std::vector<std::pair<std::string, JsonValue>>& members() const { return members_; }
    const JsonValue* find(const std::string& key) const;

    static const char* type_name(Type t);

private:
    friend class JsonParser;
    Type type_ = Type::Null;
    double number_ = 0;
    bool boolean_ = false;
    std::string string_;
    std::vector<JsonValue> array_;
    std::vector<std::pair<std::string, JsonValue>> members_;
};

// Parses a whole document; throws Error(InvalidArgument) naming the line and column of the problem.
JsonValue parse_json(const std::string& text);

// A JSON string literal (quotes and escapes) and a number (null for NaN/Inf).
std::string json_quote(const std::string& text);
std::string json_number(double value);

}  // namespace statfilter
