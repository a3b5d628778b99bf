#include "statfilter/json.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "statfilter/error.hpp"

namespace statfilter {

const JsonValue* JsonValue::find(const std::string& key) const {
    for (const auto& [k, v] : members_)
        if (k == key) return &v;
    return nullptr;
}

const char* JsonValue::type_name(Type t) {
    switch (t) {
    case Type::Null: return "null";
    case Type::Bool: return "a boolean";
    case Type::Number: return "a number";
    case Type::String: return "a string";
    case Type::Array: return "an array";
    case Type::Object: return "an object";
    }
    return "?";
}

class JsonParser {
public:
    explicit JsonParser(const std::string& text) : s_(text) {}

    JsonValue document() {
        JsonValue v = value(0);
        skip_space();
        if (i_ != s_.size()) fail("unexpected text after the end of the document");
        return v;
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        size_t line = 1, column = 1;
        for (size_t k = 0; k < i_ && k < s_.size(); ++k) {
            if (s_[k] == '\n') {
                ++line;
                column = 1;
            } else {
                ++column;
            }
        }
        throw Error(Status::InvalidArgument, "malformed JSON at line " + std::to_string(line) + ", column " +
                                                 std::to_string(column) + ": " + what);
    }

    void skip_space() {
        while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
    }

    bool consume(char c) {
        skip_space();
        if (i_ < s_.size() && s_[i_] == c) {
            ++i_;
            return true;
        }
        return false;
    }

    void expect(char c) {
        if (!consume(c)) fail(std::string("expected '") + c + "'");
    }

    bool literal(const char* word) {
        size_t n = 0;
        while (word[n]) ++n;
        if (s_.compare(i_, n, word) != 0) return false;
        i_ += n;
        return true;
    }

    JsonValue value(int depth) {
        if (depth > 64) fail("nesting deeper than 64 levels");
        skip_space();
        if (i_ >= s_.size()) fail("unexpected end of the document");
        JsonValue v;
        const char c = s_[i_];
        if (c == '{') {
            ++i_;
            v.type_ = JsonValue::Type::Object;
            if (consume('}')) return v;
            do {
                skip_space();
                if (i_ >= s_.size() || s_[i_] != '"') fail("expected a member name in quotes");
                std::string key = string_literal();
                expect(':');
                v.members_.emplace_back(std::move(key), value(depth + 1));
            } while (consume(','));
            expect('}');
        } else if (c == '[') {
            ++i_;
            v.type_ = JsonValue::Type::Array;
            if (consume(']')) return v;
            do v.array_.push_back(value(depth + 1));
            while (consume(','));
            expect(']');
        } else if (c == '"') {
            v.type_ = JsonValue::Type::String;
            v.string_ = string_literal();
        } else if (literal("true")) {
            v.type_ = JsonValue::Type::Bool;
            v.boolean_ = true;
        } else if (literal("false")) {
            v.type_ = JsonValue::Type::Bool;
        } else if (literal("null")) {
            v.type_ = JsonValue::Type::Null;
        } else if (c == '-' || (c >= '0' && c <= '9')) {
            const char* begin = s_.c_str() + i_;
            char* end = nullptr;
            v.number_ = std::strtod(begin, &end);
            if (end == begin) fail("bad number");
            i_ += static_cast<size_t>(end - begin);
            v.type_ = JsonValue::Type::Number;
        } else {
            fail(std::string("unexpected character '") + c + "'");
        }
        return v;
    }

    std::string string_literal() {
        ++i_;  // opening quote
        std::string out;
        while (true) {
            if (i_ >= s_.size()) fail("unterminated string");
            const char c = s_[i_++];
            if (c == '"') return out;
            if (static_cast<unsigned char>(c) < 0x20) fail("control character in a string");
            if (c != '\\') {
                out += c;
                continue;
            }
            if (i_ >= s_.size()) fail("unterminated string");
            const char e = s_[i_++];
            switch (e) {
            case '"': out += '"'; break;
            case '\\': out += '\\'; break;
            case '/': out += '/'; break;
            case 'b': out += '\b'; break;
            case 'f': out += '\f'; break;
            case 'n': out += '\n'; break;
            case 'r': out += '\r'; break;
            case 't': out += '\t'; break;
            case 'u': {
                if (i_ + 4 > s_.size()) fail("bad \\u escape");
                const unsigned long code = std::strtoul(s_.substr(i_, 4).c_str(), nullptr, 16);
                i_ += 4;
                // Enough for file names: ASCII and the rest of the basic plane as UTF-8.
                if (code < 0x80) {
                    out += static_cast<char>(code);
                } else if (code < 0x800) {
                    out += static_cast<char>(0xC0 | (code >> 6));
                    out += static_cast<char>(0x80 | (code & 0x3F));
                } else {
                    out += static_cast<char>(0xE0 | (code >> 12));
                    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
                    out += static_cast<char>(0x80 | (code & 0x3F));
                }
                break;
            }
            default: fail(std::string("bad escape '\\") + e + "'");
            }
        }
    }

    const std::string& s_;
    size_t i_ = 0;
};

JsonValue parse_json(const std::string& text) { return JsonParser(text).document(); }

// The same escapes as json_string in tools/cli_json.hpp (the CLI cannot link lib/).
std::string json_quote(const std::string& text) {
    std::string out = "\"";
    for (unsigned char c : text) {
        switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\t': out += "\\t"; break;
        case '\r': out += "\\r"; break;
        default:
            if (c < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\u%04x", c);
                out += buf;
            } else {
                out += static_cast<char>(c);
            }
        }
    }
    return out + "\"";
}

// The same format as json_number in tools/cli_json.hpp (the CLI's copy): the shortest of 15, 16 or
// 17 significant digits that reads back as the same double.
std::string json_number(double value) {
    if (!std::isfinite(value)) return "null";
    char buf[64];
    for (int digits = 15; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, value);
        if (std::strtod(buf, nullptr) == value) break;
    }
    return buf;
}

}  // namespace statfilter
