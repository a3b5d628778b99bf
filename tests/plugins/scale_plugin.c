/* A tiny single-frame plugin for the tests: out = factor * in + offset, written in plain C99 against
 * the public header only. Compile definitions turn it into the broken plugins the loader must
 * reject: TEST_BAD_ABI (declares another plugin ABI version), TEST_NO_ENTRY (exports no
 * sf_plugin_entry), TEST_WRONG_NAME (declares a name its file name does not carry), TEST_CREATE_FAILS
 * (create fails cleanly, as without a GPU), TEST_UNTERMINATED (create fails and fills the host's
 * whole message buffer without a terminating NUL). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <statfilter/statfilter.h>

typedef struct scale_state {
    double factor, offset;
    int fail;
} scale_state;

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

static sf_status execute(void* instance, const sf_plugin_run* run, char* error, size_t size) {
    const scale_state* s = instance;
    if (s->fail) {
        snprintf(error, size, "asked to fail at frame %lld", (long long)run->frame_numbers[0]);
        return SF_ERROR_NUMERIC;
    }
    for (int64_t f = 0; f < run->shape.frames; ++f) {
        if (run->progress && run->progress(run->progress_user, (double)f / run->shape.frames, "scale")) {
            snprintf(error, size, "cancelled");
            return SF_ERROR_CANCELLED;
        }
        for (int64_t y = 0; y < run->shape.height; ++y)
            for (int64_t x = 0; x < run->shape.width; ++x)
                for (int64_t c = 0; c < run->shape.channels; ++c)
                    *at(run->output, &run->output_strides, f, y, x, c) =
                        (float)(s->factor * *at(run->input, &run->input_strides, f, y, x, c) + s->offset);
    }
    return SF_OK;
}

static void release(void* instance) { free(instance); }

static const sf_param_info params[] = {
    {sizeof(sf_param_info), "factor", SF_PARAM_FLOAT, "2", "multiplies every sample", -1000, 1000, ""},
    {sizeof(sf_param_info), "offset", SF_PARAM_FLOAT, "0", "added after the factor", -1000, 1000, ""},
    {sizeof(sf_param_info), "fail", SF_PARAM_STRING, "no", "yes: execute fails (tests the error path)", 0, 0, "no,yes"},
};

#if defined(TEST_BAD_ABI)
#  define ABI 999
#else
#  define ABI SF_PLUGIN_ABI_VERSION
#endif
#if defined(TEST_WRONG_NAME)
#  define NAME "another-name"
#elif defined(TEST_CREATE_FAILS)
#  define NAME "nodevice"
#elif defined(TEST_UNTERMINATED)
#  define NAME "unterminated"
#else
#  define NAME "scale"
#endif

static const sf_plugin plugin = {
    ABI, NAME, "2.5.0", "test plugin: factor x input + offset", SF_FILTER_SINGLE_FRAME,
    3, params, NULL, create, set_param, execute, release,
};

#if defined(TEST_NO_ENTRY)
SF_PLUGIN_EXPORT const sf_plugin* not_the_entry(void) { return &plugin; }
#else
SF_PLUGIN_EXPORT const sf_plugin* sf_plugin_entry(void) { return &plugin; }
#endif
