/* A tiny single-frame plugin for the tests: out = factor * in + offset, written in plain C99 against
 * the plugin header only. By default it is a current-version plugin with a thread-safe per-frame
 * entry (execute_frame) and the whole-sequence one. Compile definitions turn it into the other
 * plugins the tests need:
 *   TEST_OLD_ABI       plugin ABI version 1: the first sf_plugin layout (no flags, no execute_frame)
 *                      and parameter entries smaller than today's sf_param_info (no choices)
 *   TEST_SERIAL        per-frame only, not thread-safe: fails if two calls ever overlap
 *   TEST_BAD_ABI       declares a plugin ABI version newer than statfilter's
 *   TEST_NO_ENTRY      exports no sf_plugin_entry
 *   TEST_WRONG_NAME    declares a name its file name does not carry
 *   TEST_CREATE_FAILS  create fails cleanly, as without a GPU
 *   TEST_UNTERMINATED  create fails and fills the host's whole message buffer without a NUL
 * Every variant exports test_plugin_calls, which the tests read to see which entry statfilter used. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <statfilter/statfilter_plugin.h>

typedef struct scale_state {
    double factor, offset;
    int fail;
} scale_state;

/* Calls of each entry so far, and calls in flight (gcc/clang atomics: frames may run on several threads). */
static long whole_calls, frame_calls;
static int in_flight;

SF_PLUGIN_EXPORT void test_plugin_calls(long* whole, long* frames) {
    *whole = __atomic_load_n(&whole_calls, __ATOMIC_SEQ_CST);
    *frames = __atomic_load_n(&frame_calls, __ATOMIC_SEQ_CST);
}

static sf_status create(void** instance, char* error, size_t size) {
#if defined(TEST_CREATE_FAILS)
    (void)instance;
    snprintf(error, size, "no GPU device available");
    return SF_ERROR_UNSUPPORTED;
#elif defined(TEST_UNTERMINATED)
    (void)instance;
    memset(error, 'x', size);
    return SF_ERROR_UNSUPPORTED;
#endif
    scale_state* s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(error, size, "out of memory");
        return SF_ERROR_OUT_OF_MEMORY;
    }
    *instance = s;
    return SF_OK;
}

static sf_status set_param(void* instance, const char* name, const char* value, char* error, size_t size) {
    scale_state* s = instance;
    if (!strcmp(name, "factor")) s->factor = atof(value);
    else if (!strcmp(name, "offset")) s->offset = atof(value);
    else if (!strcmp(name, "fail")) s->fail = !strcmp(value, "yes");
    else {
        snprintf(error, size, "unknown parameter '%s'", name);
        return SF_ERROR_NOT_FOUND;
    }
    return SF_OK;
}

static float* at(const float* base, const sf_strides* st, int64_t f, int64_t y, int64_t x, int64_t c) {
    return (float*)((const char*)base + f * st->frame + y * st->row + x * st->pixel + c * st->channel);
}

static void scale_frame(const scale_state* s, const sf_plugin_run* run, int64_t f) {
    for (int64_t y = 0; y < run->shape.height; ++y)
        for (int64_t x = 0; x < run->shape.width; ++x)
            for (int64_t c = 0; c < run->shape.channels; ++c)
                *at(run->output, &run->output_strides, f, y, x, c) =
                    (float)(s->factor * *at(run->input, &run->input_strides, f, y, x, c) + s->offset);
}

__attribute__((unused)) static sf_status execute(void* instance, const sf_plugin_run* run, char* error, size_t size) {
    const scale_state* s = instance;
    __atomic_add_fetch(&whole_calls, 1, __ATOMIC_SEQ_CST);
    if (s->fail) {
        snprintf(error, size, "asked to fail at frame %lld", (long long)run->frame_numbers[0]);
        return SF_ERROR_NUMERIC;
    }
    for (int64_t f = 0; f < run->shape.frames; ++f) {
        if (run->progress && run->progress(run->progress_user, (double)f / run->shape.frames, "scale")) {
            snprintf(error, size, "cancelled");
            return SF_ERROR_CANCELLED;
        }
        scale_frame(s, run, f);
    }
    return SF_OK;
}

__attribute__((unused)) static sf_status execute_frame(void* instance, const sf_plugin_run* frame, char* error, size_t size) {
    const scale_state* s = instance;
    sf_status status = SF_OK;
    __atomic_add_fetch(&frame_calls, 1, __ATOMIC_SEQ_CST);
    const int overlapping = __atomic_add_fetch(&in_flight, 1, __ATOMIC_SEQ_CST) > 1;
#if defined(TEST_SERIAL)
    const struct timespec pause = {0, 2000000}; /* 2 ms: long enough for an overlap to show */
    nanosleep(&pause, NULL);
#endif
    if (frame->shape.frames != 1) {
        snprintf(error, size, "execute_frame got %lld frames", (long long)frame->shape.frames);
        status = SF_ERROR_INTERNAL;
    } else if (s->fail) {
        snprintf(error, size, "asked to fail at frame %lld", (long long)frame->frame_numbers[0]);
        status = SF_ERROR_NUMERIC;
    } else {
        scale_frame(s, frame, 0);
    }
#if defined(TEST_SERIAL)
    if (overlapping && status == SF_OK) {
        snprintf(error, size, "called while another call was running, but the plugin is not thread-safe");
        status = SF_ERROR_INTERNAL;
    }
#else
    (void)overlapping;
#endif
    __atomic_sub_fetch(&in_flight, 1, __ATOMIC_SEQ_CST);
    return status;
}

static void release(void* instance) { free(instance); }

#if defined(TEST_WRONG_NAME)
#  define NAME "another-name"
#elif defined(TEST_CREATE_FAILS)
#  define NAME "nodevice"
#elif defined(TEST_UNTERMINATED)
#  define NAME "unterminated"
#elif defined(TEST_OLD_ABI)
#  define NAME "oldabi"
#elif defined(TEST_SERIAL)
#  define NAME "serial"
#else
#  define NAME "scale"
#endif
#define DESCRIPTION "test plugin: factor x input + offset"

#if defined(TEST_OLD_ABI)
/* sf_plugin as plugin ABI version 1 declared it, and a parameter entry of an older, smaller
 * sf_param_info (no choices): what a plugin built against an older header hands over. */
typedef struct old_param_info {
    size_t struct_size;
    const char* name;
    sf_param_type type;
    const char* default_value;
    const char* description;
    double min;
    double max;
} old_param_info;

typedef struct old_plugin {
    int abi_version;
    const char* name;
    const char* version;
    const char* description;
    sf_filter_kind kind;
    int param_count;
    const old_param_info* params;
    sf_plugin_probe_fn probe;
    sf_plugin_create_fn create;
    sf_plugin_set_param_fn set_param;
    sf_plugin_execute_fn execute;
    sf_plugin_release_fn release;
} old_plugin;

static const old_param_info params[] = {
    {sizeof(old_param_info), "factor", SF_PARAM_FLOAT, "2", "multiplies every sample", -1000, 1000},
    {sizeof(old_param_info), "offset", SF_PARAM_FLOAT, "0", "added after the factor", -1000, 1000},
    {sizeof(old_param_info), "fail", SF_PARAM_STRING, "no", "yes: execute fails (tests the error path)", 0, 0},
};

static const old_plugin plugin = {
    1, NAME, "1.0.0", DESCRIPTION, SF_FILTER_SINGLE_FRAME, 3, params, NULL, create, set_param, execute, release,
};
#define PLUGIN ((const sf_plugin*)&plugin)
#else
static const sf_param_info params[] = {
    {sizeof(sf_param_info), "factor", SF_PARAM_FLOAT, "2", "multiplies every sample", -1000, 1000, ""},
    {sizeof(sf_param_info), "offset", SF_PARAM_FLOAT, "0", "added after the factor", -1000, 1000, ""},
    {sizeof(sf_param_info), "fail", SF_PARAM_STRING, "no", "yes: execute fails (tests the error path)", 0, 0, "no,yes"},
};

#  if defined(TEST_BAD_ABI)
#    define ABI 999 /* far newer than any statfilter */
#  else
#    define ABI SF_PLUGIN_ABI_VERSION
#  endif
#  if defined(TEST_SERIAL)
#    define FLAGS 0u
#    define WHOLE NULL
#  else
#    define FLAGS 0u
#    define WHOLE execute
#  endif

static const sf_plugin plugin = {
    ABI, NAME, "2.5.0", DESCRIPTION, SF_FILTER_SINGLE_FRAME, 3, params, NULL,
    create, set_param, WHOLE, release, FLAGS, execute_frame,
};
#define PLUGIN (&plugin)
#endif

#if defined(TEST_NO_ENTRY)
SF_PLUGIN_EXPORT const sf_plugin* not_the_entry(void) { return PLUGIN; }
#else
SF_PLUGIN_EXPORT const sf_plugin* sf_plugin_entry(void) { return PLUGIN; }
#endif
