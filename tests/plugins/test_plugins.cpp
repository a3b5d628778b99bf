// Filter plugins through the C ABI: the tiny "scale" plugin, its older-ABI and serial variants and
// broken ones built next to this test (tests/plugins/CMakeLists.txt), found on STATFILTER_PLUGIN_PATH;
// and the prefilter stage.
#include <dlfcn.h>

#include <cmath>
#include <string>
#include <vector>

#include "capi_util.hpp"

using namespace statfilter_test;

namespace {

sf_filter_info info_of(const char* name, sf_status expected = SF_OK) {
    sf_filter_info info;
    sf_filter_info_init(&info);
    EXPECT_EQ(sf_filter_info_get(name, &info), expected) << name << ": " << sf_last_error();
    return info;
}

bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::vector<std::string> available_names() {
    std::vector<std::string> names;
    for (int i = 0; i < sf_filter_count(); ++i) names.push_back(sf_filter_name(i));
    return names;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}

Filt create(const char* name) {
    sf_filter f = nullptr;
    EXPECT_SF_OK(sf_filter_create(name, &f));
    return Filt(f);
}

// A noisy, slowly varying 3-channel sequence (positive, so transforms apply).
Seq test_sequence() {
    return filled_sequence(shape_of(12, 6, 7, 3), [](int64_t f, int64_t y, int64_t x, int64_t c) {
        const float noise = static_cast<float>(std::sin(12.9898 * (f * 131 + y * 17 + x * 7 + c) + 0.5) * 0.05);
        return 0.5f + 0.1f * c + 0.02f * f + 0.01f * x + noise;
    });
}

std::vector<float> run_filter(sf_filter f, sf_sequence in) {
    sf_shape shape{};
    EXPECT_SF_OK(sf_sequence_shape(in, &shape));
    Seq out = create_sequence(shape);
    EXPECT_EQ(sf_filter_execute(f, in, out.get()), SF_OK) << sf_filter_last_error(f);
    return samples_of(out.get());
}

// How often statfilter called the plugin's whole-sequence and per-frame entries, read from the
// plugin's own counters (test_plugin_calls in scale_plugin.c) in the copy statfilter loaded.
struct Calls {
    long whole = 0, frames = 0;
};

Calls calls_of(const char* name) {
    const sf_filter_info info = info_of(name);
    void* library = dlopen(info.origin, RTLD_NOW | RTLD_NOLOAD);
    EXPECT_NE(library, nullptr) << info.origin << " is not loaded";
    Calls c;
    if (!library) return c;
    auto read = reinterpret_cast<void (*)(long*, long*)>(dlsym(library, "test_plugin_calls"));
    EXPECT_NE(read, nullptr);
    if (read) read(&c.whole, &c.frames);
    dlclose(library);  // drops only the reference dlopen just took
    return c;
}

}  // namespace

TEST(Plugins, ListedWithKindOriginAndVersion) {
    const sf_filter_info scale = info_of("scale");
    EXPECT_STREQ(scale.name, "scale");
    EXPECT_EQ(scale.kind, SF_FILTER_SINGLE_FRAME);
    EXPECT_TRUE(ends_with(scale.origin, "/statfilter_scale.so")) << scale.origin;
    EXPECT_STREQ(scale.version, "2.5.0");
    EXPECT_EQ(scale.available, 1);
    EXPECT_STREQ(scale.problem, "");
    EXPECT_STREQ(sf_filter_description("scale"), "test plugin: factor x input + offset");

    const sf_filter_info pca = info_of("pca");
    EXPECT_EQ(pca.kind, SF_FILTER_TEMPORAL);
    EXPECT_STREQ(pca.origin, "built-in");
    EXPECT_STREQ(pca.version, sf_version_string());
    EXPECT_EQ(info_of("copy").kind, SF_FILTER_SINGLE_FRAME);

    // The full listing has the built-ins first, then every plugin file, usable or not.
    std::vector<std::string> all;
    for (int i = 0; i < sf_filter_info_count(); ++i) {
        sf_filter_info info;
        sf_filter_info_init(&info);
        ASSERT_SF_OK(sf_filter_info_at(i, &info));
        all.push_back(info.name);
        EXPECT_EQ(info.available == 0, *info.problem != '\0') << info.name;
    }
    for (const char* name : {"copy", "pca", "scale", "oldabi", "serial", "notlib", "nosymbol", "badabi", "misnamed"})
        EXPECT_TRUE(contains(all, name)) << name;
    EXPECT_EQ(all.front(), "copy");
    sf_filter_info info;
    sf_filter_info_init(&info);
    expect_failure(sf_filter_info_at(sf_filter_info_count(), &info), SF_ERROR_INVALID_ARGUMENT, {"out of range"});

    // The creatable list has the working plugin and none of the broken ones.
    const auto names = available_names();
    for (const char* usable : {"scale", "oldabi", "serial", "pca"}) EXPECT_TRUE(contains(names, usable)) << usable;
    for (const char* broken : {"notlib", "nosymbol", "badabi", "misnamed"}) EXPECT_FALSE(contains(names, broken)) << broken;
}

TEST(Plugins, FileThatIsNotALibrary) {
    sf_filter f = nullptr;
    expect_failure(sf_filter_create("notlib", &f), SF_ERROR_IO, {"statfilter_notlib.so", "cannot load"});
    EXPECT_EQ(f, nullptr);
    const sf_filter_info info = info_of("notlib");
    EXPECT_EQ(info.available, 0);
    EXPECT_NE(std::string(info.problem).find("statfilter_notlib.so"), std::string::npos) << info.problem;
}

TEST(Plugins, LibraryWithoutTheEntrySymbol) {
    sf_filter f = nullptr;
    expect_failure(sf_filter_create("nosymbol", &f), SF_ERROR_UNSUPPORTED, {"statfilter_nosymbol.so", "sf_plugin_entry"});
}

TEST(Plugins, NewerAbiVersionIsRefusedNamingBothVersions) {
    sf_filter f = nullptr;
    const std::string versions = "loads versions " + std::to_string(SF_PLUGIN_ABI_VERSION_FIRST) + " to " +
                                 std::to_string(SF_PLUGIN_ABI_VERSION);
    expect_failure(sf_filter_create("badabi", &f), SF_ERROR_UNSUPPORTED,
                   {"statfilter_badabi.so", "plugin ABI version 999 is newer than this statfilter", versions});
    EXPECT_EQ(f, nullptr);
    EXPECT_NE(std::string(info_of("badabi").problem).find(versions), std::string::npos);
}

// A version 1 plugin (the first sf_plugin layout, parameter entries smaller than today's) loads, gets
// defaults for what it lacks, and runs through its whole-sequence execute.
TEST(Plugins, OlderAbiVersionLoadsAndRuns) {
    const sf_filter_info info = info_of("oldabi");
    EXPECT_EQ(info.available, 1) << info.problem;
    EXPECT_EQ(info.kind, SF_FILTER_SINGLE_FRAME);
    EXPECT_STREQ(info.version, "1.0.0");
    Filt f = create("oldabi");
    int count = 0;
    ASSERT_SF_OK(sf_filter_param_count(f.get(), &count));
    ASSERT_EQ(count, 3);
    sf_param_info p;
    p.struct_size = sizeof p;
    ASSERT_SF_OK(sf_filter_param_info(f.get(), 0, &p));
    EXPECT_STREQ(p.name, "factor");
    EXPECT_EQ(p.max, 1000);
    ASSERT_SF_OK(sf_filter_param_info(f.get(), 2, &p));
    EXPECT_STREQ(p.name, "fail");
    EXPECT_STREQ(p.choices, "");  // past the entry's size: the default, free text
    ASSERT_SF_OK(sf_filter_set_float(f.get(), "offset", 0.5));

    const Calls before = calls_of("oldabi");
    Seq in = test_sequence();
    const std::vector<float> samples = samples_of(in.get());
    const std::vector<float> out = run_filter(f.get(), in.get());
    ASSERT_EQ(out.size(), samples.size());
    for (size_t i = 0; i < out.size(); ++i) ASSERT_FLOAT_EQ(out[i], 2 * samples[i] + 0.5f) << i;
    const Calls after = calls_of("oldabi");
    EXPECT_EQ(after.whole - before.whole, 1);
    EXPECT_EQ(after.frames, before.frames);

    ASSERT_SF_OK(sf_filter_set_string(f.get(), "fail", "yes"));
    Seq o = create_sequence(shape_of(12, 6, 7, 3));
    expect_failure(sf_filter_execute(f.get(), in.get(), o.get()), SF_ERROR_NUMERIC, {"oldabi: asked to fail at frame 1"});
}

// A plugin with execute_frame is called once per frame by statfilter, never with the whole sequence.
TEST(Plugins, PerFrameEntryRunsEveryFrame) {
    Filt f = create("scale");
    const Calls before = calls_of("scale");
    Seq in = test_sequence();
    const std::vector<float> samples = samples_of(in.get());
    const std::vector<float> out = run_filter(f.get(), in.get());
    for (size_t i = 0; i < out.size(); ++i) ASSERT_FLOAT_EQ(out[i], 2 * samples[i]) << i;
    const Calls after = calls_of("scale");
    EXPECT_EQ(after.frames - before.frames, 12);
    EXPECT_EQ(after.whole, before.whole);
}

// Without SF_PLUGIN_THREAD_SAFE no two calls overlap (the plugin fails if they do): in memory, and
// streamed as a prefilter with several threads, where each thread has an instance of its own.
TEST(Plugins, NotThreadSafeMeansOneCallAtATime) {
    Seq in = test_sequence();
    Filt serial = create("serial");
    const std::vector<float> samples = samples_of(in.get());
    const std::vector<float> out = run_filter(serial.get(), in.get());
    for (size_t i = 0; i < out.size(); ++i) ASSERT_FLOAT_EQ(out[i], 2 * samples[i]) << i;

    TempDir dir;
    const std::string input = dir.file("in.####.exr"), output = dir.file("out.####.exr");
    const sf_write_options w = write_options(SF_PIXEL_FLOAT);
    ASSERT_SF_OK(sf_sequence_write(in.get(), input.c_str(), &w));
    Filt pca = create("pca");
    ASSERT_SF_OK(sf_filter_set_string(pca.get(), "prefilter", "serial"));
    sf_run_options run;
    sf_run_options_init(&run);
    run.threads = 4;
    const Calls before = calls_of("serial");
    ASSERT_EQ(sf_filter_run(pca.get(), input.c_str(), nullptr, output.c_str(), &w, &run), SF_OK)
        << sf_filter_last_error(pca.get());
    double streamed = 0;
    ASSERT_SF_OK(sf_filter_result_float(pca.get(), "run.streamed", &streamed));
    EXPECT_EQ(streamed, 1);
    // Each frame twice, one call at a time: filtered, then probed once more for the trust blend
    // (prefilter_trust, on by default).
    EXPECT_EQ(calls_of("serial").frames - before.frames, 24);
}

// A prefilter that changes the light (this one doubles it) is scaled back to the noisy shot's light,
// channel by channel, in memory and streamed (keep_mean); with keep_mean=0 its light stays.
TEST(Plugins, APrefiltersLightIsScaledBackToTheInputs) {
    Seq in = test_sequence();
    const std::vector<float> samples = samples_of(in.get());
    auto mean_of = [](const std::vector<float>& v) {
        double sum = 0;
        for (float x : v) sum += x;
        return sum / static_cast<double>(v.size());
    };
    const double input_mean = mean_of(samples);
    for (const char* keep : {"1", "0"}) {
        Filt pca = create("pca");
        ASSERT_SF_OK(sf_filter_set_string(pca.get(), "prefilter", "serial"));
        ASSERT_SF_OK(sf_filter_set_string(pca.get(), "keep_mean", keep));
        const double ratio = mean_of(run_filter(pca.get(), in.get())) / input_mean;
        if (keep[0] == '1')
            EXPECT_NEAR(ratio, 1.0, 1e-3);
        else
            EXPECT_NEAR(ratio, 2.0, 2e-3);
    }
    TempDir dir;
    const std::string input = dir.file("in.####.exr"), output = dir.file("out.####.exr");
    const sf_write_options w = write_options(SF_PIXEL_FLOAT);
    ASSERT_SF_OK(sf_sequence_write(in.get(), input.c_str(), &w));
    Filt pca = create("pca");
    ASSERT_SF_OK(sf_filter_set_string(pca.get(), "prefilter", "serial"));
    ASSERT_EQ(sf_filter_run(pca.get(), input.c_str(), nullptr, output.c_str(), &w, nullptr), SF_OK)
        << sf_filter_last_error(pca.get());
    sf_sequence raw = nullptr;
    ASSERT_SF_OK(sf_sequence_read(output.c_str(), nullptr, &raw));
    Seq out(raw);
    EXPECT_NEAR(mean_of(samples_of(out.get())) / input_mean, 1.0, 1e-3);
}

TEST(Plugins, NameMustMatchTheFile) {
    sf_filter f = nullptr;
    expect_failure(sf_filter_create("misnamed", &f), SF_ERROR_UNSUPPORTED,
                   {"statfilter_misnamed.so", "declares filter 'another-name'"});
}

TEST(Plugins, CreateThatFailsCleanlyIsListedUnavailable) {
    const sf_filter_info info = info_of("nodevice");
    EXPECT_EQ(info.available, 0);
    EXPECT_NE(std::string(info.problem).find("no GPU device available"), std::string::npos) << info.problem;
    EXPECT_NE(std::string(info.problem).find("statfilter_nodevice.so"), std::string::npos) << info.problem;
    EXPECT_FALSE(contains(available_names(), "nodevice"));
    sf_filter f = nullptr;
    expect_failure(sf_filter_create("nodevice", &f), SF_ERROR_UNSUPPORTED, {"no GPU device available"});
    EXPECT_EQ(f, nullptr);
}

// The message is read no further than the host's buffer (ASan: no stack-buffer-overflow).
TEST(Plugins, UnterminatedMessageIsCutAtTheBuffer) {
    const sf_filter_info info = info_of("unterminated");
    EXPECT_EQ(info.available, 0);
    const std::string problem = info.problem;
    EXPECT_NE(problem.find(std::string(100, 'x')), std::string::npos);
    EXPECT_LT(problem.size(), 4096u + 300u) << "read past the plugin's buffer";
    sf_filter f = nullptr;
    expect_failure(sf_filter_create("unterminated", &f), SF_ERROR_UNSUPPORTED, {"xxxx"});
}

TEST(Plugins, UnknownNameSaysWhereItLooked) {
    sf_filter f = nullptr;
    expect_failure(sf_filter_create("no-such-plugin", &f), SF_ERROR_NOT_FOUND,
                   {"unknown filter 'no-such-plugin'", "statfilter_no-such-plugin.so", "STATFILTER_PLUGIN_PATH"});
    expect_failure(sf_filter_create("../evil", &f), SF_ERROR_NOT_FOUND, {"unknown filter"});
    sf_filter_info info;
    sf_filter_info_init(&info);
    expect_failure(sf_filter_info_get("no-such-plugin", &info), SF_ERROR_NOT_FOUND, {"no-such-plugin"});
}

TEST(Plugins, ParametersThroughTheCAbi) {
    Filt f = create("scale");
    int count = 0;
    ASSERT_SF_OK(sf_filter_param_count(f.get(), &count));
    ASSERT_EQ(count, 3);
    sf_param_info p;
    p.struct_size = sizeof p;
    ASSERT_SF_OK(sf_filter_param_info(f.get(), 0, &p));
    EXPECT_STREQ(p.name, "factor");
    EXPECT_EQ(p.type, SF_PARAM_FLOAT);
    EXPECT_STREQ(p.default_value, "2");
    EXPECT_EQ(p.min, -1000);
    EXPECT_EQ(p.max, 1000);
    ASSERT_SF_OK(sf_filter_param_info(f.get(), 2, &p));
    EXPECT_STREQ(p.choices, "no,yes");

    double factor = 0;
    ASSERT_SF_OK(sf_filter_get_float(f.get(), "factor", &factor));
    EXPECT_EQ(factor, 2);
    EXPECT_SF_OK(sf_filter_set_float(f.get(), "factor", 3));
    EXPECT_SF_OK(sf_filter_set_int(f.get(), "offset", 1));
    // The plugin's table is enforced by statfilter: range, choices, unknown names.
    expect_failure(sf_filter_set_float(f.get(), "factor", 1e9), SF_ERROR_INVALID_ARGUMENT, {"'factor'", "outside"});
    expect_failure(sf_filter_set_string(f.get(), "fail", "maybe"), SF_ERROR_INVALID_ARGUMENT, {"no, yes"});
    expect_failure(sf_filter_set_int(f.get(), "gain", 1), SF_ERROR_NOT_FOUND, {"'gain'"});
    ASSERT_SF_OK(sf_filter_get_float(f.get(), "factor", &factor));
    EXPECT_EQ(factor, 3);

    Seq in = test_sequence();
    const std::vector<float> before = samples_of(in.get());
    const std::vector<float> out = run_filter(f.get(), in.get());
    ASSERT_EQ(out.size(), before.size());
    for (size_t i = 0; i < out.size(); ++i) ASSERT_FLOAT_EQ(out[i], 3 * before[i] + 1) << i;
}

TEST(Plugins, StridedCallerMemoryInAndOut) {
    // Planar (channel-major) caller memory: the plugin sees the byte strides, not a copy.
    const sf_shape shape = shape_of(3, 4, 5, 2);
    const int64_t n = sample_count(shape);
    std::vector<float> in_data(n), out_data(n, -1);
    const sf_strides planar{4 * 3 * 4 * 5, 4, 4 * 5, 4 * 4 * 5};
    for (int64_t i = 0; i < n; ++i) in_data[i] = static_cast<float>(i);
    sf_sequence in = nullptr, out = nullptr;
    ASSERT_SF_OK(sf_sequence_wrap(in_data.data(), shape, planar, &in));
    ASSERT_SF_OK(sf_sequence_wrap(out_data.data(), shape, planar, &out));
    Seq in_h(in), out_h(out);
    Filt f = create("scale");
    ASSERT_SF_OK(sf_filter_execute(f.get(), in, out));
    for (int64_t i = 0; i < n; ++i) ASSERT_EQ(out_data[i], 2 * in_data[i]) << i;
}

TEST(Plugins, PluginErrorsAndCancellationReachTheCaller) {
    Filt f = create("scale");
    ASSERT_SF_OK(sf_filter_set_string(f.get(), "fail", "yes"));
    Seq in = test_sequence();
    Seq out = create_sequence(shape_of(12, 6, 7, 3));
    expect_failure(sf_filter_execute(f.get(), in.get(), out.get()), SF_ERROR_NUMERIC, {"scale: asked to fail at frame"});
    EXPECT_NE(std::string(sf_filter_last_error(f.get())).find("asked to fail"), std::string::npos);

    ASSERT_SF_OK(sf_filter_set_string(f.get(), "fail", "no"));
    int calls = 0;
    auto cancel_at_third = [](void* user, double, const char*) -> int { return ++*static_cast<int*>(user) >= 3; };
    ASSERT_SF_OK(sf_filter_set_progress(f.get(), cancel_at_third, &calls));
    expect_failure(sf_filter_execute(f.get(), in.get(), out.get()), SF_ERROR_CANCELLED, {"cancelled"});
    EXPECT_EQ(calls, 3);
}

// prefilter=scale inside each temporal filter gives exactly scale, then the filter.
TEST(Prefilter, EqualsRunningTheTwoFiltersOneAfterTheOther) {
    Seq in = test_sequence();
    for (const char* method : {"pca", "error-threshold", "moving-basis"}) {
        Filt scale = create("scale");
        ASSERT_SF_OK(sf_filter_set_float(scale.get(), "factor", 3));
        ASSERT_SF_OK(sf_filter_set_float(scale.get(), "offset", 0.25));
        const std::vector<float> scaled = run_filter(scale.get(), in.get());
        Seq scaled_seq = create_sequence(shape_of(12, 6, 7, 3));
        float* data = nullptr;
        sf_strides st{};
        ASSERT_SF_OK(sf_sequence_data(scaled_seq.get(), &data, &st));
        std::copy(scaled.begin(), scaled.end(), data);
        // The plain chain: the prefilter's light as it is (keep_mean=0), no trust blend.
        Filt plain = create(method);
        ASSERT_SF_OK(sf_filter_set_string(plain.get(), "keep_mean", "0"));
        const std::vector<float> two_steps = run_filter(plain.get(), scaled_seq.get());

        Filt combined = create(method);
        ASSERT_SF_OK(sf_filter_set_string(combined.get(), "keep_mean", "0"));
        ASSERT_SF_OK(sf_filter_set_string(combined.get(), "prefilter_trust", "0"));
        ASSERT_SF_OK(sf_filter_set_string(combined.get(), "prefilter", "scale"));
        ASSERT_SF_OK(sf_filter_set_string(combined.get(), "prefilter_params", "factor=3,offset=0.25"));
        const std::vector<float> one_step = run_filter(combined.get(), in.get());
        ASSERT_EQ(one_step.size(), two_steps.size());
        for (size_t i = 0; i < one_step.size(); ++i) ASSERT_EQ(one_step[i], two_steps[i]) << method << " sample " << i;

        // And the prefilter did something: without it the output differs.
        Filt unprefiltered = create(method);
        EXPECT_NE(run_filter(unprefiltered.get(), in.get()), one_step) << method;
    }
}

TEST(Prefilter, BuiltinSingleFrameFilterWorksToo) {
    Seq in = test_sequence();
    Filt plain = create("pca");
    Filt with_copy = create("pca");
    ASSERT_SF_OK(sf_filter_set_string(with_copy.get(), "prefilter", "copy"));
    EXPECT_EQ(run_filter(with_copy.get(), in.get()), run_filter(plain.get(), in.get()));
}

TEST(Prefilter, ClearErrors) {
    Seq in = test_sequence();
    Seq out = create_sequence(shape_of(12, 6, 7, 3));
    auto fails = [&](const char* prefilter, const char* params, sf_status status, std::vector<std::string> fragments) {
        Filt f = create("pca");
        ASSERT_SF_OK(sf_filter_set_string(f.get(), "prefilter", prefilter));
        ASSERT_SF_OK(sf_filter_set_string(f.get(), "prefilter_params", params));
        expect_failure(sf_filter_execute(f.get(), in.get(), out.get()), status, fragments, prefilter);
    };
    fails("moving-basis", "", SF_ERROR_INVALID_ARGUMENT, {"prefilter 'moving-basis' is a temporal filter"});
    fails("no-such-filter", "", SF_ERROR_NOT_FOUND, {"unknown filter 'no-such-filter'"});
    fails("badabi", "", SF_ERROR_UNSUPPORTED, {"statfilter_badabi.so"});
    fails("scale", "gain=2", SF_ERROR_NOT_FOUND, {"prefilter_params", "'gain'"});
    fails("scale", "factor=1e9", SF_ERROR_INVALID_ARGUMENT, {"prefilter_params", "'factor'"});
    fails("scale", "factor", SF_ERROR_INVALID_ARGUMENT, {"prefilter_params", "expected name=value"});
    fails("scale", "fail=yes", SF_ERROR_NUMERIC, {"scale: asked to fail"});
}
