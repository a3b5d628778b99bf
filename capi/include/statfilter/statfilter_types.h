/*
 * statfilter: the plain C types that the library's API (statfilter.h) and the plugin interface
 * (statfilter_plugin.h) both use. Included by both; nothing here is a function, so a plugin that
 * includes only statfilter_plugin.h links against nothing.
 */
#ifndef STATFILTER_STATFILTER_TYPES_H
#define STATFILTER_STATFILTER_TYPES_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sf_status {
    SF_OK = 0,
    SF_ERROR_INVALID_ARGUMENT = 1, /* NULL pointer, bad value, wrong size, unknown name */
    SF_ERROR_OUT_OF_MEMORY = 2,
    SF_ERROR_IO = 3,               /* a file could not be read or written */
    SF_ERROR_NOT_FOUND = 4,        /* no such frame, channel, layer, filter or parameter */
    SF_ERROR_UNSUPPORTED = 5,
    SF_ERROR_CANCELLED = 6,        /* the progress callback asked to stop */
    SF_ERROR_NUMERIC = 7,          /* NaN/Inf or other values the chosen policy rejects */
    SF_ERROR_INTERNAL = 8
} sf_status;

/* Progress: fraction in [0, 1] and a short stage name. Return non-zero to cancel the work, which
 * then fails with SF_ERROR_CANCELLED and leaves no partial output file behind. */
typedef int (*sf_progress_callback)(void* user, double fraction, const char* stage);

typedef struct sf_shape {
    int64_t frames;
    int64_t height;
    int64_t width;
    int64_t channels;
} sf_shape;

/* Byte distances between neighbouring channels, pixels (x), rows (y) and frames. */
typedef struct sf_strides {
    int64_t channel;
    int64_t pixel;
    int64_t row;
    int64_t frame;
} sf_strides;

typedef enum sf_param_type { SF_PARAM_INT = 0, SF_PARAM_FLOAT = 1, SF_PARAM_STRING = 2 } sf_param_type;

typedef struct sf_param_info {
    size_t struct_size;        /* set by the caller to sizeof(sf_param_info) */
    const char* name;
    sf_param_type type;
    const char* default_value; /* as text */
    const char* description;
    double min;                /* for int and float parameters */
    double max;
    const char* choices;       /* for string parameters with fixed values: comma list, else "" */
} sf_param_info;

typedef enum sf_filter_kind {
    SF_FILTER_TEMPORAL = 0,    /* needs the whole sequence (pca, error-threshold, ...) */
    SF_FILTER_SINGLE_FRAME = 1 /* works frame by frame: usable as a temporal filter's prefilter */
} sf_filter_kind;

#ifdef __cplusplus
}
#endif

#endif /* STATFILTER_STATFILTER_TYPES_H */
