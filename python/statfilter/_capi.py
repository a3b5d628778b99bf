"""ctypes mirror of capi/include/statfilter/statfilter.h (and the headers it includes,
statfilter_types.h and statfilter_plugin.h).

Every ``sf_`` function of the header is declared in ``FUNCTIONS`` with its ``restype`` and
``argtypes``; ``lib`` is the loaded library with all of them applied. Structures mirror the C
structs member for member (a test parses the header and compares).
"""

import os
from ctypes import (CFUNCTYPE, POINTER, Structure, c_char_p, c_double, c_float, c_int, c_int64,
                    c_size_t, c_uint, c_void_p)

from ._library import load_library

# ---- enums (C enums are int) -----------------------------------------------------------------

sf_status = c_int
SF_OK = 0
SF_ERROR_INVALID_ARGUMENT = 1
SF_ERROR_OUT_OF_MEMORY = 2
SF_ERROR_IO = 3
SF_ERROR_NOT_FOUND = 4
SF_ERROR_UNSUPPORTED = 5
SF_ERROR_CANCELLED = 6
SF_ERROR_NUMERIC = 7
SF_ERROR_INTERNAL = 8

sf_pixel_type = c_int
SF_PIXEL_HALF = 0
SF_PIXEL_FLOAT = 1

sf_param_type = c_int
SF_PARAM_INT = 0
SF_PARAM_FLOAT = 1
SF_PARAM_STRING = 2

sf_filter_kind = c_int
SF_FILTER_TEMPORAL = 0
SF_FILTER_SINGLE_FRAME = 1

SF_PLUGIN_ABI_VERSION = 2
SF_PLUGIN_ABI_VERSION_FIRST = 1
SF_PLUGIN_ENTRY = "sf_plugin_entry"
SF_PLUGIN_THREAD_SAFE = 1

# ---- opaque handles --------------------------------------------------------------------------


class sf_sequence(c_void_p):
    """Opaque sf_sequence handle (struct sf_sequence_s*)."""


class sf_filter(c_void_p):
    """Opaque sf_filter handle (struct sf_filter_s*)."""


# ---- callbacks -------------------------------------------------------------------------------

# typedef void (*sf_error_callback)(void* user, sf_status status, const char* message);
sf_error_callback = CFUNCTYPE(None, c_void_p, sf_status, c_char_p)
# typedef int (*sf_progress_callback)(void* user, double fraction, const char* stage);
sf_progress_callback = CFUNCTYPE(c_int, c_void_p, c_double, c_char_p)

# ---- structs ---------------------------------------------------------------------------------


class sf_shape(Structure):
    _fields_ = [("frames", c_int64), ("height", c_int64), ("width", c_int64), ("channels", c_int64)]


class sf_strides(Structure):
    _fields_ = [("channel", c_int64), ("pixel", c_int64), ("row", c_int64), ("frame", c_int64)]


class sf_window(Structure):
    _fields_ = [("x", c_int64), ("y", c_int64), ("width", c_int64), ("height", c_int64)]


class sf_channel_stats(Structure):
    _fields_ = [("min", c_double), ("max", c_double), ("mean", c_double),
                ("nan_count", c_int64), ("inf_count", c_int64)]


class sf_read_options(Structure):
    _fields_ = [("struct_size", c_size_t),
                ("channels", c_char_p),
                ("frames", c_char_p),
                ("ocio_config", c_char_p),
                ("colorspace_in", c_char_p),
                ("colorspace_out", c_char_p),
                ("progress", sf_progress_callback),
                ("progress_user", c_void_p)]


class sf_write_options(Structure):
    _fields_ = [("struct_size", c_size_t),
                ("pixel_type", sf_pixel_type),
                ("compression", c_char_p),
                ("ocio_config", c_char_p),
                ("colorspace_in", c_char_p),
                ("colorspace_out", c_char_p),
                ("half_overflow", c_int),
                ("progress", sf_progress_callback),
                ("progress_user", c_void_p),
                ("tile_size", c_int),
                ("into", c_int)]


class sf_param_info(Structure):
    _fields_ = [("struct_size", c_size_t),
                ("name", c_char_p),
                ("type", sf_param_type),
                ("default_value", c_char_p),
                ("description", c_char_p),
                ("min", c_double),
                ("max", c_double),
                ("choices", c_char_p)]


class sf_comparison(Structure):
    _fields_ = [("struct_size", c_size_t),
                ("rel_mse", c_double),
                ("rel_mse_moving", c_double),
                ("rel_mse_static", c_double),
                ("moving_fraction", c_double),
                ("psnr", c_double),
                ("flicker", c_double),
                ("jitter", c_double)]


class sf_filter_info(Structure):
    _fields_ = [("struct_size", c_size_t),
                ("name", c_char_p),
                ("description", c_char_p),
                ("kind", sf_filter_kind),
                ("origin", c_char_p),
                ("version", c_char_p),
                ("available", c_int),
                ("problem", c_char_p)]


# ---- the plugin interface (what a plugin library exports; mirrored for completeness) ----------

class sf_plugin_run(Structure):
    _fields_ = [("struct_size", c_size_t),
                ("shape", sf_shape),
                ("input", POINTER(c_float)),
                ("input_strides", sf_strides),
                ("output", POINTER(c_float)),
                ("output_strides", sf_strides),
                ("frame_numbers", POINTER(c_int64)),
                ("channel_names", POINTER(c_char_p)),
                ("source_pattern", c_char_p),
                ("source_channels", c_char_p),
                ("progress", sf_progress_callback),
                ("progress_user", c_void_p)]


sf_plugin_probe_fn = CFUNCTYPE(sf_status, c_char_p, c_size_t)
sf_plugin_create_fn = CFUNCTYPE(sf_status, POINTER(c_void_p), c_char_p, c_size_t)
sf_plugin_set_param_fn = CFUNCTYPE(sf_status, c_void_p, c_char_p, c_char_p, c_char_p, c_size_t)
sf_plugin_execute_fn = CFUNCTYPE(sf_status, c_void_p, POINTER(sf_plugin_run), c_char_p, c_size_t)
sf_plugin_execute_frame_fn = CFUNCTYPE(sf_status, c_void_p, POINTER(sf_plugin_run), c_char_p, c_size_t)
sf_plugin_release_fn = CFUNCTYPE(None, c_void_p)


class sf_plugin(Structure):
    _fields_ = [("abi_version", c_int),
                ("name", c_char_p),
                ("version", c_char_p),
                ("description", c_char_p),
                ("kind", sf_filter_kind),
                ("param_count", c_int),
                ("params", POINTER(sf_param_info)),
                ("probe", sf_plugin_probe_fn),
                ("create", sf_plugin_create_fn),
                ("set_param", sf_plugin_set_param_fn),
                ("execute", sf_plugin_execute_fn),
                ("release", sf_plugin_release_fn),
                ("flags", c_uint),  # plugin ABI version 2
                ("execute_frame", sf_plugin_execute_frame_fn)]


sf_plugin_entry_fn = CFUNCTYPE(POINTER(sf_plugin))


class sf_crop_window(Structure):
    _fields_ = [("frame", c_int64), ("index", c_int64), ("x", c_int64), ("y", c_int64), ("width", c_int64),
                ("height", c_int64)]


class sf_run_options(Structure):
    _fields_ = [("struct_size", c_size_t),
                ("memory", c_int64),
                ("threads", c_int),
                ("overwrite", c_int),
                ("progress", sf_progress_callback),
                ("progress_user", c_void_p)]


class sf_merge_options(Structure):
    _fields_ = [("struct_size", c_size_t),
                ("crops", c_char_p),
                ("mask", sf_sequence),
                ("feather", c_int64),
                ("progress", sf_progress_callback),
                ("progress_user", c_void_p)]


class sf_image_output(Structure):
    _fields_ = [("name", c_char_p),
                ("path", c_char_p)]


class sf_plan_options(Structure):
    _fields_ = [("struct_size", c_size_t),
                ("tiles", c_int64),
                ("tile_rows", c_int64),
                ("frames_per_task", c_int64),
                ("work_dir", c_char_p),
                ("images", POINTER(sf_image_output)),
                ("image_count", c_int64)]


class sf_detect_outputs(Structure):
    _fields_ = [("struct_size", c_size_t),
                ("mask", c_char_p),
                ("crops", c_char_p),
                ("score", c_char_p),
                ("degree_map", c_char_p),
                ("preview", c_char_p)]


STRUCTS = {cls.__name__: cls for cls in (sf_shape, sf_strides, sf_channel_stats, sf_comparison, sf_read_options,
                                         sf_write_options, sf_param_info, sf_filter_info, sf_plugin_run,
                                         sf_plugin)}
STRUCTS.update({cls.__name__: cls for cls in (sf_crop_window, sf_merge_options, sf_run_options, sf_window,
                                              sf_image_output, sf_plan_options, sf_detect_outputs)})

# ---- functions: name -> (restype, [argtypes]) -------------------------------------------------

_P = POINTER
FUNCTIONS = {
    # version
    "sf_version": (c_int, []),
    "sf_version_string": (c_char_p, []),
    # status and errors
    "sf_status_name": (c_char_p, [sf_status]),
    "sf_last_error": (c_char_p, []),
    "sf_set_error_callback": (None, [sf_error_callback, c_void_p]),
    # sequences
    "sf_sequence_create": (sf_status, [sf_shape, _P(sf_sequence)]),
    "sf_sequence_wrap": (sf_status, [_P(c_float), sf_shape, sf_strides, _P(sf_sequence)]),
    "sf_sequence_release": (sf_status, [sf_sequence]),
    "sf_sequence_shape": (sf_status, [sf_sequence, _P(sf_shape)]),
    "sf_sequence_data": (sf_status, [sf_sequence, _P(_P(c_float)), _P(sf_strides)]),
    "sf_sequence_copy_to": (sf_status, [sf_sequence, _P(c_float), sf_strides]),
    "sf_sequence_channel_name": (sf_status, [sf_sequence, c_int64, _P(c_char_p)]),
    "sf_sequence_set_channel_name": (sf_status, [sf_sequence, c_int64, c_char_p]),
    "sf_sequence_frame_number": (sf_status, [sf_sequence, c_int64, _P(c_int64)]),
    "sf_sequence_set_frame_number": (sf_status, [sf_sequence, c_int64, c_int64]),
    "sf_sequence_channel_stats": (sf_status, [sf_sequence, c_int64, _P(sf_channel_stats)]),
    "sf_comparison_init": (None, [_P(sf_comparison)]),
    "sf_sequence_compare": (sf_status, [sf_sequence, sf_sequence, _P(sf_comparison)]),
    "sf_sequence_false_colour": (sf_status, [sf_sequence, _P(sf_sequence)]),
    # frame patterns
    "sf_pattern_frames": (sf_status, [c_char_p, _P(c_int64), c_size_t, _P(c_size_t)]),
    "sf_pattern_format": (sf_status, [c_char_p, c_int64, c_char_p, c_size_t, _P(c_size_t)]),
    # reading and writing
    "sf_read_options_init": (None, [_P(sf_read_options)]),
    "sf_sequence_read": (sf_status, [c_char_p, _P(sf_read_options), _P(sf_sequence)]),
    "sf_channel_selection": (sf_status, [c_char_p, c_char_p, c_char_p, c_size_t, _P(c_size_t)]),
    "sf_sequence_frame_windows": (sf_status, [sf_sequence, c_int64, _P(sf_window), _P(sf_window), _P(sf_window)]),
    "sf_sequence_set_frame_windows": (sf_status, [sf_sequence, c_int64, _P(sf_window), _P(sf_window)]),
    "sf_write_options_init": (None, [_P(sf_write_options)]),
    "sf_sequence_write": (sf_status, [sf_sequence, c_char_p, _P(sf_write_options)]),
    # filters
    "sf_filter_count": (c_int, []),
    "sf_filter_name": (c_char_p, [c_int]),
    "sf_filter_description": (c_char_p, [c_char_p]),
    "sf_filter_create": (sf_status, [c_char_p, _P(sf_filter)]),
    "sf_filter_release": (sf_status, [sf_filter]),
    "sf_filter_last_error": (c_char_p, [sf_filter]),
    "sf_filter_set_int": (sf_status, [sf_filter, c_char_p, c_int64]),
    "sf_filter_set_float": (sf_status, [sf_filter, c_char_p, c_double]),
    "sf_filter_set_string": (sf_status, [sf_filter, c_char_p, c_char_p]),
    "sf_filter_get_int": (sf_status, [sf_filter, c_char_p, _P(c_int64)]),
    "sf_filter_get_float": (sf_status, [sf_filter, c_char_p, _P(c_double)]),
    "sf_filter_get_string": (sf_status, [sf_filter, c_char_p, _P(c_char_p)]),
    "sf_filter_param_count": (sf_status, [sf_filter, _P(c_int)]),
    "sf_filter_param_info": (sf_status, [sf_filter, c_int, _P(sf_param_info)]),
    "sf_filter_result_count": (sf_status, [sf_filter, _P(c_int)]),
    "sf_filter_result_name": (sf_status, [sf_filter, c_int, _P(c_char_p)]),
    "sf_filter_result_float": (sf_status, [sf_filter, c_char_p, _P(c_double)]),
    "sf_filter_result_string": (sf_status, [sf_filter, c_char_p, _P(c_char_p)]),
    "sf_filter_result_sequence": (sf_status, [sf_filter, c_char_p, _P(sf_sequence)]),
    "sf_filter_set_progress": (sf_status, [sf_filter, sf_progress_callback, c_void_p]),
    "sf_filter_execute": (sf_status, [sf_filter, sf_sequence, sf_sequence]),
    "sf_filter_image_result_count": (sf_status, [sf_filter, _P(c_int)]),
    "sf_filter_image_result_name": (sf_status, [sf_filter, c_int, _P(c_char_p)]),
    "sf_filter_check_image_output": (sf_status, [sf_filter, c_char_p, c_char_p, c_char_p, c_char_p, c_char_p]),
    "sf_run_options_init": (None, [_P(sf_run_options)]),
    "sf_memory_size_parse": (sf_status, [c_char_p, _P(c_int64)]),
    "sf_filter_run": (sf_status, [sf_filter, c_char_p, _P(sf_read_options), c_char_p, _P(sf_write_options),
                                  _P(sf_run_options)]),
    # a run as tasks for a distributed engine or a render farm
    "sf_plan_options_init": (None, [_P(sf_plan_options)]),
    "sf_plan_write": (sf_status, [sf_filter, c_char_p, _P(sf_read_options), c_char_p, _P(sf_write_options),
                                  _P(sf_run_options), _P(sf_plan_options), c_char_p]),
    "sf_plan_write_detect": (sf_status, [sf_filter, c_char_p, c_char_p, _P(sf_read_options), c_char_p, c_char_p,
                                         _P(sf_run_options), _P(sf_plan_options), c_char_p]),
    "sf_detect_outputs_init": (None, [_P(sf_detect_outputs)]),
    "sf_plan_write_detect_outputs": (sf_status, [sf_filter, c_char_p, c_char_p, _P(sf_read_options),
                                                 _P(sf_detect_outputs), _P(sf_run_options), _P(sf_plan_options),
                                                 c_char_p]),
    "sf_plan_task_count": (sf_status, [c_char_p, _P(c_int64)]),
    "sf_plan_run_task": (sf_status, [c_char_p, c_int64, _P(sf_run_options)]),
    # artifact detection, re-render list and merge
    "sf_filter_set_input": (sf_status, [sf_filter, c_char_p, sf_sequence]),
    "sf_filter_set_input_files": (sf_status, [sf_filter, c_char_p, c_char_p]),
    "sf_detect_degree_preview": (sf_status, [sf_sequence, c_int64, _P(sf_sequence)]),
    "sf_crops_windows": (sf_status, [c_char_p, _P(sf_crop_window), c_size_t, _P(c_size_t), _P(c_int64), _P(c_int64)]),
    "sf_merge_options_init": (None, [_P(sf_merge_options)]),
    "sf_merge": (sf_status, [sf_sequence, sf_sequence, _P(sf_merge_options), sf_sequence, _P(c_int64)]),
    # filter plugins and the filter listing
    "sf_filter_info_init": (None, [_P(sf_filter_info)]),
    "sf_filter_info_count": (c_int, []),
    "sf_filter_info_at": (sf_status, [c_int, _P(sf_filter_info)]),
    "sf_filter_info_get": (sf_status, [c_char_p, _P(sf_filter_info)]),
}

lib, library_path = load_library()


#: Functions of the header that the loaded library does not export (an older library). They
#: are not declared; the Python calls that need them raise UnsupportedError.
MISSING = []


def _declare(library):
    for name, (restype, argtypes) in FUNCTIONS.items():
        try:
            fn = getattr(library, name)
        except AttributeError:
            MISSING.append(name)
            continue
        fn.restype = restype
        fn.argtypes = list(argtypes)


_declare(lib)


def has(name):
    """True when the loaded library exports the function."""
    return name not in MISSING


def text(value):
    """Decode a C string (bytes or None) to str ("" for NULL)."""
    if value is None:
        return ""
    return value.decode("utf-8", errors="replace")


def encode(value):
    """Encode a str for the C side (UTF-8); None stays NULL."""
    if value is None:
        return None
    if isinstance(value, bytes):
        return value
    return str(value).encode("utf-8")


def encode_path(value):
    """Encode a path (str, bytes or os.PathLike) with the file system encoding."""
    return os.fsencode(value)
