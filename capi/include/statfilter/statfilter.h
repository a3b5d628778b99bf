/*
 * statfilter: statistical temporal filtering of rendered indirect illumination.
 *
 * The stable C ABI (C99). Everything crosses as opaque handles, status codes, plain C structs
 * and strided float buffers; no C++ type or exception crosses it. Only symbols prefixed sf_
 * are exported.
 *
 * Conventions
 *  - Every function returns an sf_status (or a value documented otherwise). On failure the
 *    message is available from sf_last_error() on the calling thread, and for filters also
 *    from sf_filter_last_error().
 *  - A sequence holds F frames of H x W pixels with C float32 channels. Its memory is either
 *    owned by statfilter (sf_sequence_create, sf_sequence_read) or borrowed from the caller
 *    (sf_sequence_wrap) with byte strides for channel, pixel (x), row (y) and frame, so a
 *    NumPy array passes in and out without a copy.
 *  - Filters are created by name and configured by named parameters, so new filters and
 *    parameters never change this ABI.
 *  - Structs passed in carry their own size in their first member (struct_size); initialise
 *    them with the matching *_init function, which fills defaults for the version you built
 *    against.
 *  - Strings returned as const char* stay valid until the owning handle is released (or, for
 *    sf_last_error, until the next statfilter call on that thread).
 */
#ifndef STATFILTER_STATFILTER_H
#define STATFILTER_STATFILTER_H

#include <stddef.h>
#include <stdint.h>

/* The types shared with plugins (sf_status, sf_shape, sf_strides, sf_param_info, ...), and the
 * plugin interface itself: included here so that every consumer of this header keeps seeing them. */
#include "statfilter_types.h"
#include "statfilter_plugin.h"

#if defined(_WIN32)
#  if defined(STATFILTER_BUILDING)
#    define SF_API __declspec(dllexport)
#  else
#    define SF_API __declspec(dllimport)
#  endif
#else
#  define SF_API __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- version ------------------------------------------------------------------------------ */

#define SF_VERSION_MAJOR 0
#define SF_VERSION_MINOR 1
#define SF_VERSION_PATCH 0
/* MAJOR * 10000 + MINOR * 100 + PATCH of the header you compiled against. */
#define SF_VERSION (SF_VERSION_MAJOR * 10000 + SF_VERSION_MINOR * 100 + SF_VERSION_PATCH)

/* The version of the library actually loaded, in the same encoding as SF_VERSION. */
SF_API int sf_version(void);
/* The same as text, e.g. "0.1.0". */
SF_API const char* sf_version_string(void);

/* ---- status and errors -------------------------------------------------------------------- */

/* A short constant name for a status, e.g. "SF_ERROR_IO". */
SF_API const char* sf_status_name(sf_status status);
/* The message of the last failed call on this thread ("" if none). */
SF_API const char* sf_last_error(void);

/* Called on every failure (any thread) with the status and message; NULL removes it. */
typedef void (*sf_error_callback)(void* user, sf_status status, const char* message);
SF_API void sf_set_error_callback(sf_error_callback callback, void* user);

/* ---- sequences ---------------------------------------------------------------------------- */

typedef struct sf_sequence_s* sf_sequence;

/* A new sequence owning zero-filled, contiguous (frame, row, pixel, channel) memory.
 * Channels are named "C0", "C1", ... until renamed; frames are numbered 1..F. Dimensions are
 * checked before any allocation: each must be >= 1 and H * W must fit in 2^31 - 1 pixels. */
SF_API sf_status sf_sequence_create(sf_shape shape, sf_sequence* out);

/* A sequence over caller memory (not copied). The caller keeps the memory alive and unchanged
 * in size until sf_sequence_release. Strides are in bytes and must be multiples of 4 and
 * non-negative; the layout may be any order (e.g. a NumPy array's strides). */
SF_API sf_status sf_sequence_wrap(float* data, sf_shape shape, sf_strides strides, sf_sequence* out);

SF_API sf_status sf_sequence_release(sf_sequence sequence);

SF_API sf_status sf_sequence_shape(sf_sequence sequence, sf_shape* out);
/* The data pointer and byte strides (owned or borrowed memory). */
SF_API sf_status sf_sequence_data(sf_sequence sequence, float** data, sf_strides* strides);
/* Copy all samples into caller memory laid out with the given byte strides. */
SF_API sf_status sf_sequence_copy_to(sf_sequence sequence, float* dst, sf_strides dst_strides);

SF_API sf_status sf_sequence_channel_name(sf_sequence sequence, int64_t channel, const char** name);
SF_API sf_status sf_sequence_set_channel_name(sf_sequence sequence, int64_t channel, const char* name);
/* The frame number (as on disk) of frame index i. */
SF_API sf_status sf_sequence_frame_number(sf_sequence sequence, int64_t index, int64_t* number);
SF_API sf_status sf_sequence_set_frame_number(sf_sequence sequence, int64_t index, int64_t number);

typedef struct sf_channel_stats {
    double min;       /* over finite samples; 0 if there are none */
    double max;
    double mean;
    int64_t nan_count;
    int64_t inf_count;
} sf_channel_stats;

SF_API sf_status sf_sequence_channel_stats(sf_sequence sequence, int64_t channel, sf_channel_stats* out);

/* Error of a sequence against a reference of the same shape (the project's metrics). */
typedef struct sf_comparison {
    size_t struct_size;     /* set by the caller (sf_comparison_init); fields past it are not written */
    double rel_mse;         /* mean((x - ref)^2 / (ref^2 + 0.01)) over every sample */
    double rel_mse_moving;  /* the same inside the moving region: reference temporal std > 3x median */
    double rel_mse_static;  /* ... and outside it */
    double moving_fraction; /* share of pixels in the moving region */
    double psnr;            /* dB on tonemapped values x / (1 + x) */
    double flicker;         /* mean |(x_t - x_t-1) - (ref_t - ref_t-1)| on tonemapped values */
    double jitter;          /* mean |x_t+1 - 2 x_t + x_t-1| of tonemapped luminance where the reference
                               varies least (temporal std <= 1.5x median) */
} sf_comparison;

SF_API void sf_comparison_init(sf_comparison* comparison);
SF_API sf_status sf_sequence_compare(sf_sequence test, sf_sequence reference, sf_comparison* out);

/* An image result as a picture: each frame's first channel, clamped to [0, 1] (not a number: 0),
 * through one ramp, dark blue (0) through teal to yellow (1). *preview receives a new sequence of
 * the same frames with channels R, G, B, for sf_sequence_write (a PNG path converts it to 8 bits);
 * release it with sf_sequence_release. What `statfilter denoise --save NAME=x.png` and a plan's
 * image outputs write. */
SF_API sf_status sf_sequence_false_colour(sf_sequence image, sf_sequence* preview);

/* ---- frame patterns and files ------------------------------------------------------------- */

/* Frame numbers found on disk for a pattern (name.####.exr, name.%04d.exr, name.#.exr,
 * name.@@@.exr), ascending. Two-call idiom: with numbers == NULL, *count gets how many there
 * are; otherwise up to capacity numbers are written and *count gets how many were written.
 * No file found is SF_ERROR_NOT_FOUND. */
SF_API sf_status sf_pattern_frames(const char* pattern, int64_t* numbers, size_t capacity, size_t* count);

/* The file name of one frame of a pattern, written into buffer (two-call idiom with *needed,
 * which counts the terminating NUL). */
SF_API sf_status sf_pattern_format(const char* pattern, int64_t frame, char* buffer, size_t capacity,
                                   size_t* needed);

/* ---- reading and writing sequences -------------------------------------------------------- */

typedef struct sf_read_options {
    size_t struct_size;        /* sizeof(sf_read_options), set by sf_read_options_init */
    const char* channels;      /* NULL/"" = the default: every channel of a file without layers
                                  (R,G,B,A...); of a file with layers its light passes only, never
                                  Normal, Albedo, *Color, Depth/Z, Vector, Alpha/A, Denoising*,
                                  Mist, Index*, UV, Position, Crypto* (see sf_channel_selection).
                                  "*" = every channel of every part. Else a comma list of channel
                                  and/or layer names, e.g. "R,G,B" or "ViewLayer.Diffuse Indirect":
                                  one layer alone is named by its channels' suffixes (R, G, B);
                                  several names keep the file's full channel names. */
    const char* frames;        /* NULL/"" = every frame found on disk; else "1-48", "1-10,12" */
    const char* ocio_config;   /* NULL = $OCIO; used only when colour spaces are given */
    const char* colorspace_in; /* convert from this OCIO colour space ... */
    const char* colorspace_out;/* ... to this one after reading; both or neither */
    sf_progress_callback progress;
    void* progress_user;
} sf_read_options;

SF_API void sf_read_options_init(sf_read_options* options);

/* Read a frame sequence. All frames must exist, hold the channels chosen in the first frame,
 * flat (a deep file is SF_ERROR_UNSUPPORTED) and share one display window. The frames are read on
 * their common data window (a region render stays a region); when their data windows differ
 * (auto-cropped renders, or channels of parts of different windows) on the box of the display
 * window and all data windows, pixels outside a frame's own data window being 0. Writing puts
 * every frame back in its windows (sf_sequence_frame_windows). */
SF_API sf_status sf_sequence_read(const char* pattern, const sf_read_options* options, sf_sequence* out);

/* The channels of one file (names as in the file, comma-separated) that a channel selection
 * (sf_read_options.channels: NULL/"" for the default, "*", or a list) takes, written into buffer
 * (two-call idiom with *needed, which counts the terminating NUL). */
SF_API sf_status sf_channel_selection(const char* path, const char* channels, char* buffer, size_t capacity,
                                      size_t* needed);

/* A rectangle of pixels in a file's coordinates. */
typedef struct sf_window {
    int64_t x;
    int64_t y;
    int64_t width;
    int64_t height;
} sf_window;

/* Where frame index `frame` came from. data: the window its pixels fill (the sequence's width x
 * height), the output's data window; display: its display window; file_data: the frame's own
 * data window in its file, smaller than data when its pixels outside were read as 0. A sequence
 * not read from files has all three at (0, 0) of its own size. Any pointer may be NULL. */
SF_API sf_status sf_sequence_frame_windows(sf_sequence sequence, int64_t frame, sf_window* data, sf_window* display,
                                           sf_window* file_data);
/* Places frame index `frame` (-1: every frame) for writing: its pixels fill `data` (which must be
 * the sequence's width x height) inside the display window `display` (NULL: the same as data), as a
 * region render is written. Pixels then keep the sequence's own values (nothing is read). */
SF_API sf_status sf_sequence_set_frame_windows(sf_sequence sequence, int64_t frame, const sf_window* data,
                                               const sf_window* display);

typedef enum sf_pixel_type { SF_PIXEL_HALF = 0, SF_PIXEL_FLOAT = 1 } sf_pixel_type;

typedef struct sf_write_options {
    size_t struct_size;          /* sizeof(sf_write_options), set by sf_write_options_init */
    sf_pixel_type pixel_type;    /* default SF_PIXEL_HALF */
    const char* compression;     /* EXR compression: "zip" (default), "none", "piz", "dwaa", ... */
    const char* ocio_config;     /* NULL = $OCIO */
    const char* colorspace_in;   /* convert from this colour space ... */
    const char* colorspace_out;  /* ... to this one before writing; both or neither */
    int half_overflow;           /* 0 = error if a finite value exceeds half's range (65504);
                                    1 = clamp to +-65504 */
    sf_progress_callback progress;
    void* progress_user;
    int tile_size;               /* 0 = scanline EXR (default); N = N x N tiles (1..65536) */
    int into;                    /* 1: each output frame is a copy of the EXR file it was read from
                                    (every part, header and other channel as it was, untouched parts
                                    copied bit for bit) with the sequence's channels written back in
                                    place, each in its file's own pixel type, compression and tiling
                                    (pixel_type, compression and tile_size do not apply; tile_size must
                                    be 0). Only for sequences read from files. 0 (default): new files */
} sf_write_options;

SF_API void sf_write_options_init(sf_write_options* options);

/* Write every frame to the pattern, numbered by the sequence's frame numbers. Each frame goes
 * to a temporary file in the same directory and is renamed into place when complete, so a
 * failure never leaves a half-written frame. The metadata read with the sequence is kept. */
SF_API sf_status sf_sequence_write(sf_sequence sequence, const char* pattern, const sf_write_options* options);

/* ---- filters ------------------------------------------------------------------------------ */

typedef struct sf_filter_s* sf_filter;

/* Names of the filters that can be created here: the built-ins and every plugin that loaded
 * (see "filter plugins" below), index 0 .. sf_filter_count() - 1. */
SF_API int sf_filter_count(void);
SF_API const char* sf_filter_name(int index);
SF_API const char* sf_filter_description(const char* name);

SF_API sf_status sf_filter_create(const char* name, sf_filter* out);
SF_API sf_status sf_filter_release(sf_filter filter);
SF_API const char* sf_filter_last_error(sf_filter filter);

/* Parameters by name. An int may set a float parameter; a string parameter that accepts numbers
 * (e.g. rank = "auto" or a count) may be set with set_int. Unknown names and out-of-range values
 * fail with SF_ERROR_NOT_FOUND / SF_ERROR_INVALID_ARGUMENT and leave the value unchanged. */
SF_API sf_status sf_filter_set_int(sf_filter filter, const char* name, int64_t value);
SF_API sf_status sf_filter_set_float(sf_filter filter, const char* name, double value);
SF_API sf_status sf_filter_set_string(sf_filter filter, const char* name, const char* value);
SF_API sf_status sf_filter_get_int(sf_filter filter, const char* name, int64_t* value);
SF_API sf_status sf_filter_get_float(sf_filter filter, const char* name, double* value);
SF_API sf_status sf_filter_get_string(sf_filter filter, const char* name, const char** value);

SF_API sf_status sf_filter_param_count(sf_filter filter, int* count);
SF_API sf_status sf_filter_param_info(sf_filter filter, int index, sf_param_info* info);

/* Results of the last execute, by name (e.g. "rank" chosen by rank=auto), read with
 * sf_filter_result_*; the names are listed like parameters. */
SF_API sf_status sf_filter_result_count(sf_filter filter, int* count);
SF_API sf_status sf_filter_result_name(sf_filter filter, int index, const char** name);
SF_API sf_status sf_filter_result_float(sf_filter filter, const char* name, double* value);
SF_API sf_status sf_filter_result_string(sf_filter filter, const char* name, const char** value);
/* An image result (e.g. "rank_map") as a new sequence the caller releases; its text value
 * (sf_filter_result_string) reads "image" and its shape. */
SF_API sf_status sf_filter_result_sequence(sf_filter filter, const char* name, sf_sequence* out);

/* The names of the image results the filter can produce (e.g. "rank_map"), known before it runs, so
 * a request for one can be checked before any work; index 0 .. count - 1. */
SF_API sf_status sf_filter_image_result_count(sf_filter filter, int* count);
SF_API sf_status sf_filter_image_result_name(sf_filter filter, int index, const char** name);

/* Checks, before any work and writing nothing, that the image result `name` can be written to
 * `pattern` with sf_sequence_write (float; a .png path as its false-colour picture) after a run over
 * input_pattern's frames `frames` (as sf_read_options.frames: NULL or "" = every frame on disk): a
 * name the filter has, a frame token in the pattern when the result has a frame per frame (beta,
 * detect's mask and score) and the run more than one, a file format the library writes, and the
 * directory (created when missing, as sf_filter_run creates its output's); and that no file it would
 * write is a frame of the input on disk, or of other_pattern at the run's frame numbers (e.g. the
 * run's output; NULL: not checked). What `statfilter denoise --save`, `statfilter detect` and
 * `statfilter motion` check before the work. */
SF_API sf_status sf_filter_check_image_output(sf_filter filter, const char* name, const char* pattern,
                                              const char* input_pattern, const char* frames,
                                              const char* other_pattern);

SF_API sf_status sf_filter_set_progress(sf_filter filter, sf_progress_callback callback, void* user);

/* Run the filter: read input, write output. The output must have the input's shape (it may
 * wrap caller memory) and must not overlap the input unless it is the same memory with the
 * same strides. The input's channel names, frame numbers and metadata are copied to output. */
SF_API sf_status sf_filter_execute(sf_filter filter, sf_sequence input, sf_sequence output);

/* ---- running a filter over files, streamed ------------------------------------------------ */

typedef struct sf_run_options {
    size_t struct_size;            /* sizeof(sf_run_options), set by sf_run_options_init */
    int64_t memory;                /* bytes the run may hold (see sf_memory_size_parse); 0 = the default,
                                      half of physical memory */
    int threads;                   /* 0 = every core; the libraries' own pools (OpenEXR's coders,
                                      OpenBLAS) are held to at most it while the run runs */
    int overwrite;                 /* 1: the output may replace frames of the input (they are replaced
                                      only once every new frame is written); 0 (default): refused */
    sf_progress_callback progress; /* the whole run: reading, every pass, writing */
    void* progress_user;
} sf_run_options;

SF_API void sf_run_options_init(sf_run_options* options);

/* A memory size as users write it ("512M", "6G", "1.5G", "800K", or bytes) in bytes. */
SF_API sf_status sf_memory_size_parse(const char* text, int64_t* bytes);

/* Runs the filter from the frame sequence input_pattern to output_pattern without holding the shot
 * in memory where the filter allows it: global temporal filters (pca, error-threshold, moving-basis)
 * read bands of scanlines of every frame in a statistics pass and a second pass, then rebuild and
 * write each frame (the moving basis parks its rebuilt rows in a scratch file in $TMPDIR when the
 * shot is more than one band); the hybrid and the auto presets add a sliding window of frames;
 * per-frame filters run frame by frame; a prefilter and postfilter run frame by frame around them.
 * The renderer's passes (named inputs, in memory or sf_filter_set_input_files) are read beside the
 * input the same way. Other runs hold the whole shot in memory and read their passes whole: motion,
 * detect, and the hybrid (or a preset) with motion_compensation=off, shared_basis=0 or a repair
 * prefilter. Everything that can be checked is checked before the first pixel is read:
 * the filter's parameters and its pre/postfilter, every input frame's header, the output pattern,
 * compression and directory (created when missing), that the output is not the input (unless
 * run->overwrite), that no other run writes the same output, and that the run fits run->memory
 * (SF_ERROR_OUT_OF_MEMORY naming the smallest budget that would do). Frames are written to temporary
 * files and renamed into place together at the end: a failed or cancelled run leaves the previous
 * frames as they were. The read and write options' own progress fields are not used (run->progress
 * reports the whole run). Results are read as after sf_filter_execute. */
SF_API sf_status sf_filter_run(sf_filter filter, const char* input_pattern, const sf_read_options* read,
                               const char* output_pattern, const sf_write_options* write, const sf_run_options* run);

/* ---- a run as tasks for a distributed engine or a render farm ----------------------------- */

/* An image result of a filter (sf_filter_image_result_name) and the file to write it to. */
typedef struct sf_image_output {
    const char* name;  /* e.g. "rank_map", "alpha" */
    const char* path;  /* a float EXR; a path ending in .png gets the false-colour picture of its
                          first channel (sf_sequence_false_colour) */
} sf_image_output;

typedef struct sf_plan_options {
    size_t struct_size;        /* sizeof(sf_plan_options), set by sf_plan_options_init */
    int64_t tiles;             /* bands of full-width rows to cut the shot into; 0 = from tile_rows */
    int64_t tile_rows;         /* rows per band; both 0 = 256 rows */
    int64_t frames_per_task;   /* frames per assembly or per-frame task; 0 = 8 */
    const char* work_dir;      /* where the tasks exchange files (shared storage), in a directory
                                  named by the plan's "run" (a hash of the plan's text and of the
                                  input files' sizes and times: another plan, or the same one on
                                  frames rendered again, never reads these); NULL/"" =
                                  "<plan_path>.work" */
    /* fields are only ever added at the end: a caller built before them leaves them unread */
    const sf_image_output* images;  /* image results to write, image_count of them (sf_plan_write) */
    int64_t image_count;
} sf_plan_options;

SF_API void sf_plan_options_init(sf_plan_options* options);

/* Writes a plan (JSON, atomically) of the tasks that run the filter from input_pattern to
 * output_pattern as sf_filter_run would, for any scheduler to run with sf_plan_run_task. A filter
 * whose stage is the global low-rank one (pca, error-threshold, moving-basis, auto with quality=fast,
 * no prefilter or postfilter) is cut into bands of rows of every frame: "statistics" tasks (one per band: its
 * partial Gram), one "reduce" task after them all (sums the partials in band order, makes the basis;
 * past 32 bands "sum" tasks first sum contiguous runs of them, and the reduction waits for those),
 * "reconstruct" tasks after it (one per band, reading its halo rows too), then "assemble" tasks (each
 * writes its chunk of output frames from the bands). A per-frame filter is cut into chunks of frames
 * ("frames" tasks, independent). The hybrid and auto with quality=balanced (motion compensation) run
 * as an "analysis" task, then chunks of frames (docs/distributed.md); their renderer's passes must be
 * files (sf_filter_set_input_files: the tasks open them; a pass in memory is refused). Any other
 * filter is one "shot" task. Each task lists the tasks it
 * must run "after". run->memory and run->threads are each task's defaults. Checked before the plan is
 * written, as sf_filter_run checks before work: the filter, every input frame's header, the output
 * (pattern, compression, directory), and that a band task fits the memory; a plan cannot overwrite
 * its input (run->overwrite is refused: tasks read the input while others write).
 * plan->images: image results written as sf_filter_result_sequence + sf_sequence_write (float)
 * write them after sf_filter_run, bit-identical, each once by the task that makes it: error-threshold's
 * "rank_map" by an "images" task after the reconstructions (from each band's rows), the "alpha" of
 * --quality balanced and the hybrid by the analysis task, any image result of a "shot" task by that
 * task. Refused before the plan is written: a name the filter does not have, one the plan's tasks do
 * not make (alpha of a tiled pca run, any image of a per-frame plan), a path that is an input, the
 * output or another image's, or that cannot be written (format, directory). */
SF_API sf_status sf_plan_write(sf_filter filter, const char* input_pattern, const sf_read_options* read,
                               const char* output_pattern, const sf_write_options* write, const sf_run_options* run,
                               const sf_plan_options* plan, const char* plan_path);

/* Writes a plan (JSON, atomically) of the tasks that run the "detect" filter (configured by its
 * parameters) on the denoised sequence denoised_pattern with the noisy render noisy_pattern (its
 * named input "noisy"; NULL = without it), writing the mask frames to mask_pattern (half float, one
 * channel "mask", as `statfilter detect --mask` writes them) and the crop windows to crops_path
 * (NULL = not written; at least one of the two is given). The detection is cut into bands of rows
 * of every frame (plan->tiles or plan->tile_rows; plan->frames_per_task is not used): "noise" tasks
 * (one per band), one "tolerance" task after them (the automatic tolerance from every pixel's
 * noise), "detect" tasks after it (one per band, reading its halo rows: the band's mask), then one
 * "masks" task that writes every mask frame once and the crop windows. The mask and the crop windows
 * are bit-identical to sf_filter_execute's on the whole sequences. Checked before the plan is
 * written: the filter and its parameters against every frame's header of both sequences (shapes,
 * degree against the frame count), the mask pattern and directory, and that a band task fits
 * run->memory; the crops file's directory is created. Run the tasks with sf_plan_run_task. */
SF_API sf_status sf_plan_write_detect(sf_filter filter, const char* denoised_pattern, const char* noisy_pattern,
                                      const sf_read_options* read, const char* mask_pattern, const char* crops_path,
                                      const sf_run_options* run, const sf_plan_options* plan, const char* plan_path);

/* What a detect plan writes (sf_plan_write_detect_outputs): each NULL or "" = not written, at least
 * one given. Fields are only ever added at the end: set struct_size with sf_detect_outputs_init. */
typedef struct sf_detect_outputs {
    size_t struct_size;      /* sizeof(sf_detect_outputs), set by sf_detect_outputs_init */
    const char* mask;        /* the mask frames' pattern: half float, one channel "mask" */
    const char* crops;       /* the crop windows' JSON file */
    const char* score;       /* the estimated relMSE of each pixel-frame: a float EXR per frame, channel "score" */
    const char* degree_map;  /* the degree map: one float image, channel "degree" (the highest degree + 1
                                where no degree explains the pixel) */
    const char* preview;     /* the degree map as a picture (sf_detect_degree_preview), e.g. a PNG */
} sf_detect_outputs;

SF_API void sf_detect_outputs_init(sf_detect_outputs* outputs);

/* sf_plan_write_detect with any of the outputs `statfilter detect` writes: the mask and score
 * frames, the crop windows, the degree map and its preview, each written once by the "masks" task
 * from the bands' rows and bit-identical to the detect filter's results written with
 * sf_sequence_write (float for the score and the maps). Each output is checked before the plan is
 * written (pattern, format, directory; none may be an input). */
SF_API sf_status sf_plan_write_detect_outputs(sf_filter filter, const char* denoised_pattern, const char* noisy_pattern,
                                              const sf_read_options* read, const sf_detect_outputs* outputs,
                                              const sf_run_options* run, const sf_plan_options* plan,
                                              const char* plan_path);

/* The number of tasks in a plan file. */
SF_API sf_status sf_plan_task_count(const char* plan_path, int64_t* count);

/* Runs task `task` (0-based) of a plan file, on any node that sees the plan's input, output and work
 * directory. A task's outputs are written to temporaries and renamed into place, so a task that dies
 * can be run again, and a finished task run again rewrites the same outputs. Output frames appear
 * only in "assemble", "frames" and "shot" tasks, each frame by one rename. When the task has finished,
 * its report (JSON: seconds, CPU seconds, bytes read and written, results) is in
 * "<work_dir>/<run>/task-<task>.json" (<run>: the plan's "run" member). run->memory and run->threads override the plan's when not 0;
 * run->progress reports the task. */
SF_API sf_status sf_plan_run_task(const char* plan_path, int64_t task, const sf_run_options* run);

/* ---- filter plugins ----------------------------------------------------------------------- */

/* A filter can live in its own shared library, a plugin: statfilter_plugin.h (included above)
 * describes how one is written, found and loaded. The functions below list every filter found,
 * built-in or plugin. */

/* What statfilter knows about one filter, built-in or plugin. */
typedef struct sf_filter_info {
    size_t struct_size;      /* set by the caller (sf_filter_info_init); fields past it are not written */
    const char* name;
    const char* description;
    sf_filter_kind kind;
    const char* origin;      /* "built-in", or the plugin file's path */
    const char* version;     /* the library's version for built-ins, the plugin's own for plugins */
    int available;           /* 1: sf_filter_create works; 0: see problem */
    const char* problem;     /* why not, naming the file (e.g. a missing runtime library); "" if available */
} sf_filter_info;

SF_API void sf_filter_info_init(sf_filter_info* info);
/* Every filter found: the built-ins, then every plugin file on the search path, including those that
 * cannot be used (available = 0). Index 0 .. sf_filter_info_count() - 1. Strings stay valid until exit. */
SF_API int sf_filter_info_count(void);
SF_API sf_status sf_filter_info_at(int index, sf_filter_info* info);
/* The same for one name: loads the plugin if needed. SF_ERROR_NOT_FOUND if no such filter. */
SF_API sf_status sf_filter_info_get(const char* name, sf_filter_info* info);

/* ---- artifact detection, re-render list and merge ----------------------------------------- */

/* Named extra inputs of a filter, besides the main one passed to sf_filter_execute: e.g. the
 * "detect" filter checks a denoised sequence (its main input) against the noisy render it was made
 * from, set as its input "noisy". The filter does not copy or own the sequence: it must stay alive
 * (not released) until the input is cleared (sequence NULL), replaced, or the filter released.
 * A name the filter does not take fails with SF_ERROR_NOT_FOUND listing the names it takes.
 *
 * The "detect" filter writes its input unchanged to its output; its results are the images "mask"
 * (F x H x W x 1, 1 = re-render this pixel-frame), "score" (the estimated relMSE of each
 * pixel-frame) and "degree_map" (1 x H x W x 1, the polynomial degree each pixel needed), the text
 * "crops" (the crop windows as JSON, see docs/methods.md) and counts such as "flagged_fraction". */
SF_API sf_status sf_filter_set_input(sf_filter filter, const char* name, sf_sequence sequence);

/* A named input given as a frame sequence on disk: a file pattern (as sf_sequence_read's) holding
 * the same frames as the main input, every channel read. sf_filter_run reads it a band of rows or a
 * frame at a time beside the input, so a run given the renderer's passes (the hybrid's and the
 * presets' "albedo", "normal", "vectors") streams within its memory budget too; sf_filter_execute
 * reads it whole. The files are opened and checked against the input (frames, width, height; the
 * vectors' four channels X, Y, Z, W) when the run starts, before any work. It replaces a sequence set
 * under that name with sf_filter_set_input (and is replaced by one; sf_filter_set_input with NULL
 * clears both); pattern NULL or "" clears it. A plan (sf_plan_write) takes passes only this way.
 * The filter keeps a copy of the pattern. A name the filter does not take fails with
 * SF_ERROR_NOT_FOUND listing the names it takes. */
SF_API sf_status sf_filter_set_input_files(sf_filter filter, const char* name, const char* pattern);

/* The "detect" filter's "degree_map" result (1 x H x W x 1) as a picture for people, given the
 * filter's "degree" parameter: degree 0 dark blue through yellow at the highest degree, pixels that no
 * degree explains in red. *preview receives a new 1 x H x W x 3 sequence (channels R, G, B) for
 * sf_sequence_write (a PNG path converts it to 8 bits); release it with sf_sequence_release. */
SF_API sf_status sf_detect_degree_preview(sf_sequence degree_map, int64_t degree, sf_sequence* preview);

/* One crop window of a crop-window JSON document: a pixel rectangle of one frame, row 0 at the top. */
typedef struct sf_crop_window {
    int64_t frame;  /* frame number, as on disk */
    int64_t index;  /* the window's position within its frame, 0, 1, ... */
    int64_t x;
    int64_t y;
    int64_t width;
    int64_t height;
} sf_crop_window;

/* The windows of a crop-window JSON document (as the detect filter's "crops" result), by frame then
 * position. Two-call idiom: with windows == NULL, *count gets how many there are; otherwise up to
 * capacity are written and *count gets how many were written. A malformed document, or a window
 * outside the frame size it declares, fails with SF_ERROR_INVALID_ARGUMENT naming the frame and
 * window. width and height (may be NULL) get the frame size the document declares. */
SF_API sf_status sf_crops_windows(const char* crops_json, sf_crop_window* windows, size_t capacity, size_t* count,
                                  int64_t* width, int64_t* height);

typedef struct sf_merge_options {
    size_t struct_size;         /* sizeof(sf_merge_options), set by sf_merge_options_init */
    const char* crops;          /* crop-window JSON text; NULL = none */
    sf_sequence mask;           /* per-frame mask, non-zero = flagged; NULL = none */
    int64_t feather;            /* the re-render's weight rises over this many pixels inside the edge
                                   of the replaced region; 0 (default) = hard edge */
    sf_progress_callback progress;
    void* progress_user;
} sf_merge_options;

SF_API void sf_merge_options_init(sf_merge_options* options);

/* output = denoised with re-rendered pixels spliced in. The replaced region of each frame is the
 * union of its crop windows, or the mask's flagged pixels, or with both the mask's pixels (which must
 * lie inside the windows); at least one must be given. rerender holds full-size frames matched to
 * the denoised frames by frame number; it needs each frame that has a region (other pixels are not
 * read, so crop-window renders can be pasted into blank frames). output has the denoised shape and
 * may be the denoised sequence itself. Mismatched sizes or channels, a frame missing from the
 * re-render, windows outside the frame, an empty region: SF_ERROR_INVALID_ARGUMENT, output untouched.
 * replaced (may be NULL) gets how many pixel-frames took re-rendered values. */
SF_API sf_status sf_merge(sf_sequence denoised, sf_sequence rerender, const sf_merge_options* options,
                          sf_sequence output, int64_t* replaced);

#ifdef __cplusplus
}
#endif

#endif /* STATFILTER_STATFILTER_H */
