// sf_plan_*: a run written as a plan of tasks, and one task of it run (lib/distributed/).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "api_guard.hpp"
#include "distributed/detect_plan.hpp"
#include "distributed/plan_json.hpp"
#include "distributed/plan_run.hpp"
#include "distributed/tile_files.hpp"
#include "distributed/tile_plan.hpp"
#include "options.hpp"
#include "pipeline/guide_sources.hpp"
#include "statfilter/filter_registry.hpp"
#include "statfilter/json.hpp"

using namespace statfilter;
using namespace statfilter::capi;

namespace {

namespace fs = std::filesystem;

std::string text_member(const JsonValue& object, const char* key) {
    const JsonValue* v = object.find(key);
    return v && v->is(JsonValue::Type::String) ? v->string() : std::string();
}
double number_member(const JsonValue& object, const char* key) {
    const JsonValue* v = object.find(key);
    return v && v->is(JsonValue::Type::Number) ? v->number() : 0;
}

std::string absolute(const std::string& path) { return fs::absolute(path).lexically_normal().string(); }

// The front end's settings a task needs to do what sf_filter_run would: the filter by name and its
// parameters not at their defaults, its named inputs given as files (paths made absolute), the read
// and write options.
std::string front_end_json(const std::string& name, const Filter& f, const sf_read_options& r, const sf_write_options& w) {
    std::ostringstream o;
    o << "{\"filter\": " << json_quote(name) << ", \"parameters\": {";
    bool first = true;
    for (const ParamSpec& spec : f.params().specs()) {
        std::string value = f.params().get_string(spec.name);
        if (value == spec.default_value) continue;
        // A pass named by a parameter (the hybrid's "albedo", "normal") is files the tasks open, from
        // any working directory (a layer's name stays a name: the tasks read it from the plan's input).
        if (f.takes_input(spec.name) && pass_names_files(value)) value = absolute(value);
        o << (first ? "" : ", ") << json_quote(spec.name) << ": " << json_quote(value);
        first = false;
    }
    o << "}, \"inputs\": {";
    first = true;
    for (const std::string& input : f.input_names()) {
        if (f.input_files(input).empty()) continue;
        const std::string& files = f.input_files(input);
        o << (first ? "" : ", ") << json_quote(input) << ": " << json_quote(pass_names_files(files) ? absolute(files) : files);
        first = false;
    }
    auto text = [](const char* s) { return json_quote(text_or_empty(s)); };
    o << "}, \"read\": {\"channels\": " << text(r.channels) << ", \"frames\": " << text(r.frames)
      << ", \"ocio_config\": " << text(r.ocio_config) << ", \"colorspace_in\": " << text(r.colorspace_in)
      << ", \"colorspace_out\": " << text(r.colorspace_out) << "}";
    o << ", \"write\": {\"pixel_type\": " << static_cast<int>(w.pixel_type) << ", \"compression\": " << text(w.compression)
      << ", \"ocio_config\": " << text(w.ocio_config) << ", \"colorspace_in\": " << text(w.colorspace_in)
      << ", \"colorspace_out\": " << text(w.colorspace_out) << ", \"half_overflow\": " << w.half_overflow
      << ", \"tile_size\": " << w.tile_size << "}}";
    return o.str();
}

// The least plan format version that carries what front_end_json writes for this filter: any pass
// named (files or a layer, as a named input or through a parameter) needs a reader that knows them.
int plan_version(const Filter& f) {
    for (const std::string& input : f.input_names())
        if (!guide_pass_pattern(f, f.params(), input).empty()) return kPlanVersionInputs;
    return kPlanVersionFirst;
}

// The strings an sf_read_options / sf_write_options made from a plan point into.
struct FrontEnd {
    std::string filter, channels, frames, r_ocio, r_in, r_out, compression, w_ocio, w_in, w_out;
    sf_read_options read;
    sf_write_options write;
    std::vector<std::pair<std::string, std::string>> parameters;
    std::vector<std::pair<std::string, std::string>> inputs;  // named inputs given as files
};

const char* or_null(const std::string& s) { return s.empty() ? nullptr : s.c_str(); }

std::unique_ptr<FrontEnd> front_end_from(const JsonValue& plan) {
    const JsonValue* fe = plan.find("front_end");
    if (!fe || !fe->is(JsonValue::Type::Object)) throw Error(Status::InvalidArgument, "the plan has no front_end settings");
    auto out = std::make_unique<FrontEnd>();
    out->filter = text_member(*fe, "filter");
    if (const JsonValue* p = fe->find("parameters"))
        for (const auto& [name, value] : p->members()) out->parameters.emplace_back(name, value.string());
    if (const JsonValue* i = fe->find("inputs"))  // plans written before named inputs had none
        for (const auto& [name, value] : i->members()) out->inputs.emplace_back(name, value.string());
    sf_read_options_init(&out->read);
    sf_write_options_init(&out->write);
    if (const JsonValue* r = fe->find("read")) {
        out->channels = text_member(*r, "channels");
        out->frames = text_member(*r, "frames");
        out->r_ocio = text_member(*r, "ocio_config");
        out->r_in = text_member(*r, "colorspace_in");
        out->r_out = text_member(*r, "colorspace_out");
    }
    if (const JsonValue* w = fe->find("write")) {
        out->compression = text_member(*w, "compression");
        out->w_ocio = text_member(*w, "ocio_config");
        out->w_in = text_member(*w, "colorspace_in");
        out->w_out = text_member(*w, "colorspace_out");
        out->write.pixel_type = static_cast<sf_pixel_type>(number_member(*w, "pixel_type"));
        out->write.half_overflow = static_cast<int>(number_member(*w, "half_overflow"));
        out->write.tile_size = static_cast<int>(number_member(*w, "tile_size"));
    }
    out->read.channels = or_null(out->channels);
    out->read.frames = or_null(out->frames);
    out->read.ocio_config = or_null(out->r_ocio);
    out->read.colorspace_in = or_null(out->r_in);
    out->read.colorspace_out = or_null(out->r_out);
    out->write.compression = or_null(out->compression);
    out->write.ocio_config = or_null(out->w_ocio);
    out->write.colorspace_in = or_null(out->w_in);
    out->write.colorspace_out = or_null(out->w_out);
    return out;
}

JsonValue read_plan(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(Status::Io, "cannot open plan '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    try {
        JsonValue plan = parse_json(text.str());
        const JsonValue* format = plan.find("format");
        if (!format || !format->is(JsonValue::Type::String) || format->string() != "statfilter-plan")
            throw Error(Status::InvalidArgument, "not a statfilter plan");
        const JsonValue* version = plan.find("version");
        if (!version || !version->is(JsonValue::Type::Number) || version->number() != std::floor(version->number()) ||
            version->number() < kPlanVersionFirst)
            throw Error(Status::InvalidArgument, "the plan has no valid \"version\"");
        if (version->number() > kPlanVersionRead)
            throw Error(Status::Unsupported, "the plan's format is version " + json_number(version->number()) +
                                                 ", newer than this statfilter reads (up to " +
                                                 std::to_string(kPlanVersionRead) +
                                                 "): run its tasks with the statfilter release that wrote it");
        return plan;
    } catch (const Error& e) {
        throw Error(e.status(), "plan '" + path + "': " + e.what());
    }
}


// plan->images as (name, absolute path), refused when a path is the input or output pattern (make_plan
// checks the rest, as the tasks will write them).
std::vector<std::pair<std::string, std::string>> image_outputs(const sf_plan_options& p, const std::string& input,
                                                               const std::string& output) {
    if (p.image_count < 0) throw Error(Status::InvalidArgument, "plan->image_count must be >= 0");
    if (p.image_count > 0 && !p.images) throw Error(Status::InvalidArgument, "plan->images is NULL with image_count > 0");
    std::vector<std::pair<std::string, std::string>> images;
    for (int64_t i = 0; i < p.image_count; ++i) {
        const sf_image_output& o = p.images[i];
        const std::string what = "plan->images[" + std::to_string(i) + "]";
        if (!o.name || !*o.name) throw Error(Status::InvalidArgument, what + ".name is empty");
        if (!o.path || !*o.path) throw Error(Status::InvalidArgument, what + ".path (" + o.name + ") is empty");
        const std::string path = absolute(o.path);
        if (path == input || path == output)
            throw Error(Status::InvalidArgument, std::string("the image result '") + o.name + "' would be written to the plan's " +
                                                     (path == input ? "input" : "output") + " '" + path + "'");
        images.emplace_back(o.name, path);
    }
    return images;
}

// sf_plan_write_detect(_outputs): every output checked as the single-process detect would write it
// (tools/cmd_detect.cpp: the mask half float, the score and maps float), then the plan written.
void write_detect_plan(sf_filter filter, const char* denoised_pattern, const char* noisy_pattern,
                       const sf_read_options* read, const sf_detect_outputs& o, const sf_run_options* run,
                       const sf_plan_options* plan, const char* plan_path) {
    sf_filter_s& handle = require(filter, "filter");
    if (handle.name != "detect")
        throw Error(Status::InvalidArgument, "a detect plan takes the \"detect\" filter, not \"" + handle.name + "\"");
    const sf_run_options r = read_versioned(run, sf_run_options_init);
    const sf_plan_options p = read_versioned(plan, sf_plan_options_init);
    const sf_read_options ro_c = read_versioned(read, sf_read_options_init);
    check_run_options(r, "the default", "every core");
    if (r.overwrite) throw Error(Status::InvalidArgument, "a detect plan does not overwrite its inputs (run->overwrite is refused)");
    if (p.image_count != 0)
        throw Error(Status::InvalidArgument, "a detect plan names its outputs in sf_detect_outputs, not plan->images");
    auto given = [](const char* path) { return path && *path ? absolute(path) : std::string(); };
    DetectPlanRequest request;
    request.mask = given(o.mask);
    request.crops = given(o.crops);
    request.score = given(o.score);
    request.degree_map = given(o.degree_map);
    request.preview = given(o.preview);
    const std::vector<std::pair<const char*, std::string>> outputs = {
        {"mask", request.mask}, {"crops", request.crops}, {"score", request.score},
        {"degree_map", request.degree_map}, {"preview", request.preview}};
    if (std::all_of(outputs.begin(), outputs.end(), [](const auto& out) { return out.second.empty(); }))
        throw Error(Status::InvalidArgument, "a detect plan writes the mask, crops, score, degree_map or preview: give one");
    request.denoised = absolute(require_string(denoised_pattern, "denoised_pattern"));
    request.noisy = noisy_pattern && *noisy_pattern ? absolute(noisy_pattern) : std::string();
    for (size_t i = 0; i < outputs.size(); ++i) {
        const std::string& a = outputs[i].second;
        if (a.empty()) continue;
        if (a == request.denoised || a == request.noisy)
            throw Error(Status::InvalidArgument, std::string("the ") + outputs[i].first + " output '" + a + "' is an input");
        for (size_t j = i + 1; j < outputs.size(); ++j)
            if (a == outputs[j].second)
                throw Error(Status::InvalidArgument, std::string("the ") + outputs[i].first + " and " + outputs[j].first +
                                                         " outputs are both '" + a + "'");
    }
    const std::string path = require_string(plan_path, "plan_path");
    handle.filter->check();
    ReadOptions ro = read_options_from(&ro_c);
    ro.progress = Progress();
    auto source = open_frame_source(request.denoised, ro);
    std::unique_ptr<FrameSource> noisy_source;
    if (!request.noisy.empty()) noisy_source = open_frame_source(request.noisy, ro);
    // Each image output's checks, now (nothing is written): as the masks task writes it.
    sf_write_options wo_c;
    sf_write_options_init(&wo_c);
    wo_c.pixel_type = SF_PIXEL_HALF;
    auto check_output = [&](const std::string& pattern, int64_t frames, const char* channel, bool as_float) {
        if (pattern.empty()) return;
        WriteOptions wo = write_options_from(&wo_c);
        wo.progress = Progress();
        if (as_float) wo.half = false;
        Sequence attributes(Shape{frames, 1, 1, 1});
        attributes.channel_names()[0] = channel;
        attributes.frame_numbers() = source->attributes().frame_numbers();
        attributes.frame_numbers().resize(static_cast<size_t>(frames));
        for (const std::string& input : {request.denoised, request.noisy}) {
            if (input.empty()) continue;
            OutputChecks checks;
            checks.width = source->shape().width;
            checks.height = source->shape().height;
            checks.input_pattern = input;
            open_frame_sink(pattern, wo, attributes, checks);
        }
    };
    const int64_t frames = source->shape().frames;
    check_output(request.mask, frames, "mask", false);
    check_output(request.score, frames, "score", true);
    check_output(request.degree_map, 1, "degree", true);
    check_output(request.preview, 1, "R", true);
    if (!request.crops.empty()) fs::create_directories(fs::path(request.crops).parent_path());
    request.work_dir = absolute(p.work_dir && *p.work_dir ? std::string(p.work_dir) : path + ".work");
    request.tiles = p.tiles;
    request.tile_rows = p.tile_rows;
    request.budget_bytes = static_cast<double>(r.memory);
    request.threads = r.threads;
    request.front_end = front_end_json(handle.name, *handle.filter, ro_c, wo_c);
    request.version = plan_version(*handle.filter);
    std::string plan_run;
    const std::string stamp = input_files_stamp(request.denoised, source->attributes().frame_numbers()) +
                              (noisy_source ? input_files_stamp(request.noisy, noisy_source->attributes().frame_numbers()) : "");
    const std::string text =
        name_plan_run(make_detect_plan(*handle.filter, *source, noisy_source.get(), request), stamp, &plan_run);
    fs::create_directories(request.work_dir + "/" + plan_run);
    AtomicFile file(path);
    file.write_at(0, text.data(), text.size());
    file.commit();
}

}  // namespace

extern "C" {

void sf_plan_options_init(sf_plan_options* options) {
    if (!options) return;
    std::memset(options, 0, sizeof *options);
    options->struct_size = sizeof *options;
}

sf_status sf_plan_write(sf_filter filter, const char* input_pattern, const sf_read_options* read,
                        const char* output_pattern, const sf_write_options* write, const sf_run_options* run,
                        const sf_plan_options* plan, const char* plan_path) {
    std::string* handle_error = filter ? &filter->last_error : nullptr;
    return guarded([&] {
        sf_filter_s& handle = require(filter, "filter");
        const sf_run_options r = read_versioned(run, sf_run_options_init);
        const sf_plan_options p = read_versioned(plan, sf_plan_options_init);
        const sf_read_options ro_c = read_versioned(read, sf_read_options_init);
        const sf_write_options wo_c = read_versioned(write, sf_write_options_init);
        check_run_options(r, "the default", "every core");
        if (r.overwrite)
            throw Error(Status::InvalidArgument, "a plan cannot overwrite its input: its tasks read the input while others write");
        const std::string in = absolute(require_string(input_pattern, "input_pattern"));
        const std::string out = absolute(require_string(output_pattern, "output_pattern"));
        const std::string path = require_string(plan_path, "plan_path");
        handle.filter->check();
        ReadOptions ro = read_options_from(&ro_c);
        WriteOptions wo = write_options_from(&wo_c);
        ro.progress = Progress();
        wo.progress = Progress();
        auto source = open_frame_source(in, ro);
        OutputChecks checks;
        checks.width = source->shape().width;
        checks.height = source->shape().height;
        checks.input_pattern = in;
        // The tasks read every input from files: a pass in the caller's memory cannot reach them.
        for (const std::string& input : handle.filter->input_names())
            if (handle.filter->input(input))
                throw Error(Status::InvalidArgument, "the filter's input '" + input + "' is in memory, which a plan's tasks "
                                                     "cannot read: give it as files (sf_filter_set_input_files)");
        open_guide_sources(*handle.filter, *source);  // the renderer's passes checked against the input, now
        open_frame_sink(out, wo, source->attributes(), checks);  // the output's checks, now; nothing written
        std::string stamp = input_files_stamp(in, source->attributes().frame_numbers());
        for (const std::string& input : handle.filter->input_names()) {  // passes rendered again: another run
            const std::string pattern = guide_pass_pattern(*handle.filter, handle.filter->params(), input);
            // (A layer of the input's files is stamped with them.)
            if (!pattern.empty() && pass_names_files(pattern))
                stamp += input_files_stamp(absolute(pattern), source->attributes().frame_numbers());
        }
        PlanRequest request;
        request.images = image_outputs(p, in, out);
        request.input = in;
        request.output = out;
        request.work_dir = absolute(p.work_dir && *p.work_dir ? std::string(p.work_dir) : path + ".work");
        request.tiles = p.tiles;
        request.tile_rows = p.tile_rows;
        request.frames_per_task = p.frames_per_task;
        request.half_tiles = wo.half && !wo.color.active() && !wo.into;
        request.budget_bytes = static_cast<double>(r.memory);
        request.threads = r.threads;
        request.front_end = front_end_json(handle.name, *handle.filter, ro_c, wo_c);
        request.version = plan_version(*handle.filter);
        std::string plan_run;
        const std::string text = name_plan_run(make_plan(*handle.filter, *source, request), stamp, &plan_run);
        fs::create_directories(request.work_dir + "/" + plan_run);
        AtomicFile file(path);
        file.write_at(0, text.data(), text.size());
        file.commit();
    }, handle_error);
}

void sf_detect_outputs_init(sf_detect_outputs* outputs) {
    if (!outputs) return;
    std::memset(outputs, 0, sizeof *outputs);
    outputs->struct_size = sizeof *outputs;
}

sf_status sf_plan_write_detect(sf_filter filter, const char* denoised_pattern, const char* noisy_pattern,
                               const sf_read_options* read, const char* mask_pattern, const char* crops_path,
                               const sf_run_options* run, const sf_plan_options* plan, const char* plan_path) {
    std::string* handle_error = filter ? &filter->last_error : nullptr;
    return guarded([&] {
        if (!(mask_pattern && *mask_pattern) && !(crops_path && *crops_path))
            throw Error(Status::InvalidArgument, "a detect plan writes the mask (mask_pattern), the crop windows (crops_path) or both: give one");
        sf_detect_outputs outputs;
        sf_detect_outputs_init(&outputs);
        outputs.mask = mask_pattern;
        outputs.crops = crops_path;
        write_detect_plan(filter, denoised_pattern, noisy_pattern, read, outputs, run, plan, plan_path);
    }, handle_error);
}

sf_status sf_plan_write_detect_outputs(sf_filter filter, const char* denoised_pattern, const char* noisy_pattern,
                                       const sf_read_options* read, const sf_detect_outputs* outputs,
                                       const sf_run_options* run, const sf_plan_options* plan, const char* plan_path) {
    std::string* handle_error = filter ? &filter->last_error : nullptr;
    return guarded([&] {
        write_detect_plan(filter, denoised_pattern, noisy_pattern, read,
                          read_versioned(&require(outputs, "outputs"), sf_detect_outputs_init), run, plan, plan_path);
    }, handle_error);
}

sf_status sf_plan_task_count(const char* plan_path, int64_t* count) {
    return guarded([&] { require(count, "count") = plan_task_count(read_plan(require_string(plan_path, "plan_path"))); });
}

sf_status sf_plan_run_task(const char* plan_path, int64_t task, const sf_run_options* run) {
    return guarded([&] {
        const JsonValue plan = read_plan(require_string(plan_path, "plan_path"));
        const sf_run_options r = read_versioned(run, sf_run_options_init);
        check_run_options(r, "the plan's", "the plan's");
        const auto fe = front_end_from(plan);
        auto filter = create_filter(fe->filter);
        for (const auto& [name, value] : fe->parameters) filter->params().set_string(name, value);
        for (const auto& [name, pattern] : fe->inputs) filter->set_input_files(name, pattern);
        filter->check();
        ReadOptions ro = read_options_from(&fe->read);
        WriteOptions wo = write_options_from(&fe->write);
        ro.progress = Progress();
        wo.progress = Progress();
        const JsonValue* input = plan.find("input");
        if (!input || !input->is(JsonValue::Type::String)) throw Error(Status::InvalidArgument, "the plan has no input");
        auto source = open_frame_source(input->string(), ro);
        std::unique_ptr<FrameSource> noisy;  // a detect plan's second input
        const std::string noisy_pattern = text_member(plan, "noisy");
        if (!noisy_pattern.empty()) noisy = open_frame_source(noisy_pattern, ro);
        TaskContext context;
        context.filter = filter.get();
        context.source = source.get();
        context.noisy = noisy.get();
        context.open_sink = [&](const std::string& pattern, const Sequence& attributes, bool as_float) {
            OutputChecks checks;
            checks.width = source->shape().width;
            checks.height = source->shape().height;
            checks.input_pattern = input->string();
            WriteOptions options = wo;
            if (as_float) options.half = false;
            return open_frame_sink(pattern, options, attributes, checks);
        };
        std::string changed;
        for (const auto& [name, value] : fe->parameters) changed += (changed.empty() ? "" : " ") + name + "=" + value;
        context.attributes = {{"statfilter:version", sf_version_string()},
                              {"statfilter:filter", fe->filter},
                              {"statfilter:parameters", changed}};
        context.budget_bytes = static_cast<double>(r.memory);
        context.threads = r.threads;
        context.clamp_half = wo.clamp_half;
        context.progress = make_progress(r.progress, r.progress_user);
        run_plan_task(plan, task, context);
    });
}

}  // extern "C"
