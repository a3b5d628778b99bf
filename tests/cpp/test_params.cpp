// Named parameters: defaults, validation that leaves the old value on error, type promotion,
// parsing text from a command line, choices and string parameters that also take an integer.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "statfilter/error.hpp"
#include "statfilter/params.hpp"

using namespace statfilter;

namespace {

ParamSpec int_spec(const std::string& name, const std::string& def, double min, double max) {
    ParamSpec s;
    s.name = name;
    s.type = ParamType::Int;
    s.default_value = def;
    s.min = min;
    s.max = max;
    return s;
}

ParamSpec float_spec(const std::string& name, const std::string& def, double min, double max) {
    ParamSpec s = int_spec(name, def, min, max);
    s.type = ParamType::Float;
    return s;
}

ParamSpec string_spec(const std::string& name, const std::string& def, std::vector<std::string> choices) {
    ParamSpec s;
    s.name = name;
    s.type = ParamType::String;
    s.default_value = def;
    s.choices = std::move(choices);
    return s;
}

// "rank": "auto" or an integer 1..64, the way a PCA filter declares it.
ParamSpec rank_spec() {
    ParamSpec s = string_spec("rank", "auto", {"auto"});
    s.accepts_integer = true;
    s.min = 1;
    s.max = 64;
    return s;
}

ParamSet make_params() {
    return ParamSet({int_spec("window", "8", 1, 100), float_spec("sigma", "0.5", 0, 10),
                     string_spec("mode", "fast", {"fast", "exact"}), string_spec("label", "", {}), rank_spec()});
}

// Expects body to throw Error with this status, and the message to name the parameter.
template <class Body>
void expect_error(Body&& body, Status status, const std::string& name) {
    try {
        body();
        ADD_FAILURE() << "no error for '" << name << "'";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), status) << e.what();
        EXPECT_NE(std::string(e.what()).find("'" + name + "'"), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(ParamSet, Defaults) {
    const ParamSet p = make_params();
    EXPECT_EQ(p.get_int("window"), 8);
    EXPECT_DOUBLE_EQ(p.get_float("window"), 8.0);
    EXPECT_EQ(p.get_string("window"), "8");
    EXPECT_DOUBLE_EQ(p.get_float("sigma"), 0.5);
    EXPECT_EQ(p.get_string("mode"), "fast");
    EXPECT_EQ(p.get_string("label"), "");
    EXPECT_EQ(p.get_string("rank"), "auto");
    int64_t rank = -1;
    EXPECT_FALSE(p.get_integer_choice("rank", rank));
    EXPECT_EQ(p.specs().size(), 5u);
}

TEST(ParamSet, RangeChecksLeaveTheValueUnchanged) {
    ParamSet p = make_params();
    p.set_int("window", 12);
    expect_error([&] { p.set_int("window", 0); }, Status::InvalidArgument, "window");
    expect_error([&] { p.set_int("window", 101); }, Status::InvalidArgument, "window");
    expect_error([&] { p.set_string("window", "1000"); }, Status::InvalidArgument, "window");
    EXPECT_EQ(p.get_int("window"), 12);
    EXPECT_EQ(p.get_string("window"), "12");

    p.set_float("sigma", 2.5);
    expect_error([&] { p.set_float("sigma", -0.1); }, Status::InvalidArgument, "sigma");
    expect_error([&] { p.set_float("sigma", 10.5); }, Status::InvalidArgument, "sigma");
    expect_error([&] { p.set_float("sigma", std::nan("")); }, Status::InvalidArgument, "sigma");
    expect_error([&] { p.set_float("sigma", std::numeric_limits<double>::infinity()); }, Status::InvalidArgument, "sigma");
    EXPECT_DOUBLE_EQ(p.get_float("sigma"), 2.5);

    // Bounds are inclusive.
    p.set_int("window", 1);
    p.set_int("window", 100);
    p.set_float("sigma", 0);
    p.set_float("sigma", 10);
    EXPECT_EQ(p.get_int("window"), 100);
    EXPECT_DOUBLE_EQ(p.get_float("sigma"), 10);
}

TEST(ParamSet, UnknownNamesAreNotFoundAndListTheKnownOnes) {
    ParamSet p = make_params();
    expect_error([&] { p.set_int("windw", 3); }, Status::NotFound, "windw");
    expect_error([&] { p.get_int("windw"); }, Status::NotFound, "windw");
    try {
        p.set_float("sgma", 1);
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("sigma"), std::string::npos) << e.what();
    }
}

TEST(ParamSet, IntPromotesToFloatButNotTheOtherWay) {
    ParamSet p = make_params();
    p.set_int("sigma", 3);
    EXPECT_DOUBLE_EQ(p.get_float("sigma"), 3.0);
    expect_error([&] { p.set_int("sigma", 11); }, Status::InvalidArgument, "sigma");
    EXPECT_DOUBLE_EQ(p.get_float("sigma"), 3.0);

    // A float holding an integer may set an int parameter; a fraction may not.
    p.set_float("window", 20.0);
    EXPECT_EQ(p.get_int("window"), 20);
    expect_error([&] { p.set_float("window", 20.5); }, Status::InvalidArgument, "window");
    expect_error([&] { p.set_float("window", std::nan("")); }, Status::InvalidArgument, "window");
    EXPECT_EQ(p.get_int("window"), 20);
}

TEST(ParamSet, ParsesNumbersFromText) {
    ParamSet p = make_params();
    p.set_string("window", "42");
    EXPECT_EQ(p.get_int("window"), 42);
    p.set_string("sigma", "1.25");
    EXPECT_DOUBLE_EQ(p.get_float("sigma"), 1.25);
    p.set_string("sigma", "7e-1");
    EXPECT_DOUBLE_EQ(p.get_float("sigma"), 0.7);
    p.set_string("sigma", "3");
    EXPECT_DOUBLE_EQ(p.get_float("sigma"), 3.0);
    for (const char* bad : {"", "4x", "4.0", " ", "1e2", "0x10", "99999999999999999999"})
        expect_error([&] { p.set_string("window", bad); }, Status::InvalidArgument, "window");
    for (const char* bad : {"", "abc", "1.5.2", "2,5", "1e999"})
        expect_error([&] { p.set_string("sigma", bad); }, Status::InvalidArgument, "sigma");
    EXPECT_EQ(p.get_int("window"), 42);
    EXPECT_DOUBLE_EQ(p.get_float("sigma"), 3.0);
}

TEST(ParamSet, Choices) {
    ParamSet p = make_params();
    p.set_string("mode", "exact");
    EXPECT_EQ(p.get_string("mode"), "exact");
    try {
        p.set_string("mode", "slow");
        ADD_FAILURE() << "'slow' accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        const std::string msg = e.what();
        EXPECT_NE(msg.find("fast"), std::string::npos) << msg;  // the allowed words are listed
        EXPECT_NE(msg.find("exact"), std::string::npos) << msg;
    }
    EXPECT_EQ(p.get_string("mode"), "exact");
    expect_error([&] { p.set_int("mode", 1); }, Status::InvalidArgument, "mode");
    expect_error([&] { p.get_int("mode"); }, Status::InvalidArgument, "mode");
    // Free text takes anything.
    p.set_string("label", "shot 10, take 2");
    EXPECT_EQ(p.get_string("label"), "shot 10, take 2");
}

TEST(ParamSet, StringParameterAcceptingIntegers) {
    ParamSet p = make_params();
    int64_t rank = 0;

    p.set_int("rank", 3);
    EXPECT_EQ(p.get_string("rank"), "3");
    EXPECT_EQ(p.get_int("rank"), 3);
    ASSERT_TRUE(p.get_integer_choice("rank", rank));
    EXPECT_EQ(rank, 3);

    p.set_string("rank", "64");
    ASSERT_TRUE(p.get_integer_choice("rank", rank));
    EXPECT_EQ(rank, 64);

    p.set_string("rank", "auto");
    EXPECT_EQ(p.get_string("rank"), "auto");
    EXPECT_FALSE(p.get_integer_choice("rank", rank));

    p.set_float("rank", 5.0);
    EXPECT_EQ(p.get_int("rank"), 5);

    // Out of range, fractional or unknown words: rejected, value unchanged, message helpful.
    expect_error([&] { p.set_int("rank", 0); }, Status::InvalidArgument, "rank");
    expect_error([&] { p.set_int("rank", 65); }, Status::InvalidArgument, "rank");
    expect_error([&] { p.set_string("rank", "0"); }, Status::InvalidArgument, "rank");
    expect_error([&] { p.set_string("rank", "2.5"); }, Status::InvalidArgument, "rank");
    expect_error([&] { p.set_float("rank", 2.5); }, Status::InvalidArgument, "rank");
    try {
        p.set_string("rank", "best");
        ADD_FAILURE() << "'best' accepted";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("auto"), std::string::npos) << msg;
        EXPECT_NE(msg.find("[1, 64]"), std::string::npos) << msg;
    }
    EXPECT_EQ(p.get_int("rank"), 5);
    EXPECT_EQ(p.get_string("rank"), "5");
}

TEST(ParamSet, InvalidDefaultIsRejected) {
    EXPECT_THROW(ParamSet({int_spec("n", "0", 1, 10)}), Error);
    EXPECT_THROW(ParamSet({string_spec("m", "c", {"a", "b"})}), Error);
}

TEST(Results, StoresNumbersAndText) {
    Results r;
    r.set("rank", 3.0);
    r.set("method", std::string("auto"));
    r.set("rank", 4.0);  // overwriting keeps one name
    EXPECT_EQ(r.names(), (std::vector<std::string>{"rank", "method"}));
    EXPECT_DOUBLE_EQ(r.get_float("rank"), 4.0);
    EXPECT_EQ(r.get_string("rank"), "4");
    EXPECT_EQ(r.get_string("method"), "auto");
    EXPECT_THROW(r.get_float("method"), Error);
    try {
        r.get_float("energy");
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::NotFound);
    }
    r.clear();
    EXPECT_TRUE(r.names().empty());
}

TEST(FormatNumber, ShortAndExact) {
    EXPECT_EQ(format_number(3), "3");
    EXPECT_EQ(format_number(0.5), "0.5");
    EXPECT_EQ(format_number(std::numeric_limits<double>::infinity()), "inf");
    EXPECT_EQ(format_number(-std::numeric_limits<double>::infinity()), "-inf");
}
