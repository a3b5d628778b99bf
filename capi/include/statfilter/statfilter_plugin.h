/*
 * statfilter: the filter plugin interface (C99). A plugin is a shared library that includes this
 * header; it needs statfilter.h (and to link libstatfilter) only if it also calls the library, e.g.
 * sf_sequence_read to read guide passes. statfilter.h includes this header.
 *
 * statfilter finds a plugin named statfilter_NAME.so (NAME = the filter's name) in each directory
 * of $STATFILTER_PLUGIN_PATH (colon-separated, searched in order), then in the directory of
 * libstatfilter itself, loads it with dlopen the first time the filter is asked for (or the filters
 * are listed) and calls its one exported function SF_PLUGIN_ENTRY, of type sf_plugin_entry_fn. A
 * file that does not load, lacks that symbol or declares a plugin ABI version this statfilter does
 * not know (a newer one) is never used: asking for it fails with a message naming the file, and
 * sf_filter_info reports why. Plugins stay loaded until exit.
 *
 * Versions: a plugin declares the plugin ABI version of the header it was built against.
 * statfilter loads every version from SF_PLUGIN_ABI_VERSION_FIRST to its own SF_PLUGIN_ABI_VERSION;
 * what an older plugin's sf_plugin (or parameter table) lacks takes its default, as for every
 * struct of this ABI.
 *   1: the first: whole-sequence execute.
 *   2: flags and execute_frame, appended to sf_plugin.
 */
#ifndef STATFILTER_STATFILTER_PLUGIN_H
#define STATFILTER_STATFILTER_PLUGIN_H

#include "statfilter_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The plugin ABI version this header describes: put it in sf_plugin.abi_version. */
#define SF_PLUGIN_ABI_VERSION 2
/* The oldest plugin ABI version statfilter still loads. */
#define SF_PLUGIN_ABI_VERSION_FIRST 1
/* The name of the function every plugin exports. */
#define SF_PLUGIN_ENTRY "sf_plugin_entry"
/* Put before the entry function's definition in a plugin: exported with C linkage. */
#ifdef __cplusplus
#  define SF_PLUGIN_EXPORT extern "C" __attribute__((visibility("default")))
#else
#  define SF_PLUGIN_EXPORT __attribute__((visibility("default")))
#endif

/* What a plugin's execute gets: the whole sequence, input and output as strided float buffers
 * (byte strides, as sf_sequence_data), plus where the input came from so that a plugin can read
 * matching frames of other passes (e.g. albedo) with sf_sequence_read. execute_frame gets the same
 * struct for one frame: shape.frames is 1, frame_numbers holds that frame's number, and progress is
 * NULL (statfilter reports progress between frames). */
typedef struct sf_plugin_run {
    size_t struct_size;               /* sizeof(sf_plugin_run) of the host; fields past a plugin's
                                         own size are unknown to it, never missing to it */
    sf_shape shape;
    const float* input;
    sf_strides input_strides;
    float* output;                    /* may be the same memory as input (same strides) */
    sf_strides output_strides;
    const int64_t* frame_numbers;     /* shape.frames numbers, as on disk */
    const char* const* channel_names; /* shape.channels names */
    const char* source_pattern;       /* the pattern the input was read from; "" if not from files */
    const char* source_channels;      /* the channels or layer it was read with; "" = all */
    sf_progress_callback progress;    /* call per frame; non-zero back: stop, return SF_ERROR_CANCELLED */
    void* progress_user;
} sf_plugin_run;

/* The plugin's functions. Every one that can fail returns an sf_status and, on failure, writes a
 * NUL-terminated message of at most error_size bytes into error. None may throw or longjmp. */
/* Whether the plugin can run on this machine (e.g. its runtime library is present). */
typedef sf_status (*sf_plugin_probe_fn)(char* error, size_t error_size);
typedef sf_status (*sf_plugin_create_fn)(void** instance, char* error, size_t error_size);
/* Called before each run (an execute, or the execute_frame calls of one sequence) with every
 * parameter as text, already checked by statfilter against the plugin's parameter table (type,
 * range, choices). */
typedef sf_status (*sf_plugin_set_param_fn)(void* instance, const char* name, const char* value, char* error,
                                            size_t error_size);
/* The whole sequence in one call: the plugin loops over the frames and reports progress. */
typedef sf_status (*sf_plugin_execute_fn)(void* instance, const sf_plugin_run* run, char* error,
                                          size_t error_size);
/* One frame per call (since version 2): statfilter owns the loop over frames, so it can run them on
 * several threads (SF_PLUGIN_THREAD_SAFE) and report progress and cancel between them. */
typedef sf_status (*sf_plugin_execute_frame_fn)(void* instance, const sf_plugin_run* frame, char* error,
                                                size_t error_size);
typedef void (*sf_plugin_release_fn)(void* instance);

/* sf_plugin.flags. SF_PLUGIN_THREAD_SAFE: statfilter may call the plugin from several threads at
 * once: execute_frame on one instance for different frames, and any function of different
 * instances. Without it statfilter makes one call into the plugin at a time (all its instances
 * together) and runs the frames one after the other. */
#define SF_PLUGIN_THREAD_SAFE 1u

typedef struct sf_plugin {
    int abi_version;             /* SF_PLUGIN_ABI_VERSION; first, so that any version can be checked */
    const char* name;            /* the filter's name: must match the file name statfilter_NAME.so */
    const char* version;         /* the plugin's own version, e.g. "1.0.0" */
    const char* description;
    sf_filter_kind kind;
    int param_count;
    const sf_param_info* params; /* param_count entries, each of size params[0].struct_size; fields
                                    past that size take their defaults ("" texts, no range) */
    sf_plugin_probe_fn probe;    /* may be NULL: always usable */
    sf_plugin_create_fn create;
    sf_plugin_set_param_fn set_param;
    sf_plugin_execute_fn execute; /* may be NULL (version 2 on) when execute_frame is set */
    sf_plugin_release_fn release;
    /* ---- version 2; a version 1 plugin gets flags 0 and no execute_frame ---- */
    unsigned flags;              /* SF_PLUGIN_THREAD_SAFE or 0 */
    sf_plugin_execute_frame_fn execute_frame; /* single-frame plugins only; may be NULL; when set,
                                                 statfilter calls it instead of execute */
} sf_plugin;

/* A plugin exports:  SF_PLUGIN_EXPORT const sf_plugin* sf_plugin_entry(void);
 * returning a pointer that stays valid while the library is loaded. */
typedef const sf_plugin* (*sf_plugin_entry_fn)(void);

#ifdef __cplusplus
}
#endif

#endif /* STATFILTER_STATFILTER_PLUGIN_H */
