"""Filters: created by name, configured by named parameters, run on NumPy arrays.

Nothing here knows any particular filter: parameters are listed and set through the C ABI's
named-parameter calls, so new filters and parameters need no Python change.
"""

from __future__ import annotations

import contextlib
import ctypes
import numbers
import re
import warnings
from typing import TYPE_CHECKING, Any, Callable, Dict, List, Mapping, Optional, Union

import numpy as np

from . import _arrays, _capi
from ._handle import OwnsHandle
from ._progress import ProgressAdapter, ProgressCallback
from .errors import InvalidArgumentError, NotFoundError, StatfilterWarning, UnsupportedError, check, error_for

if TYPE_CHECKING:  # the argument types of run_files, defined with the file functions
    from .sequence import Channels, Frames, Pattern

#: A parameter value: int, float or str by the parameter's type.
ParamValue = Union[int, float, str]
#: A result value: a number, a text, or an image (float32 array shaped (frames, height, width, channels)).
ResultValue = Union[float, str, np.ndarray]

# Results kept as text by the library that are numbers ("3", "0.25") come back as numbers too.
_NUMBER_TEXT = re.compile(r"-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?")

_TYPE_NAMES = {_capi.SF_PARAM_INT: "int", _capi.SF_PARAM_FLOAT: "float", _capi.SF_PARAM_STRING: "string"}


def filters() -> Dict[str, str]:
    """The available filters as an ordered dict {name: description}."""
    out = {}
    for i in range(_capi.lib.sf_filter_count()):
        name = _capi.lib.sf_filter_name(i)
        if name is None:
            continue
        out[_capi.text(name)] = _capi.text(_capi.lib.sf_filter_description(name))
    return out


_KIND_NAMES = {_capi.SF_FILTER_TEMPORAL: "temporal", _capi.SF_FILTER_SINGLE_FRAME: "single-frame"}


def plugins() -> List[Dict[str, Any]]:
    """Every filter the library finds, built-in or plugin, as a list of dicts with keys name,
    kind ("temporal", or "single-frame": usable as a temporal filter's ``prefilter``), version,
    origin ("built-in" or the plugin file's path), available (bool), problem (why not, "" if
    available) and description. Plugins are found on $STATFILTER_PLUGIN_PATH and next to the
    library; the ones that cannot be used are listed too."""
    out = []
    for i in range(_capi.lib.sf_filter_info_count()):
        info = _capi.sf_filter_info()
        _capi.lib.sf_filter_info_init(ctypes.byref(info))
        check(_capi.lib.sf_filter_info_at(i, ctypes.byref(info)))
        out.append({
            "name": _capi.text(info.name),
            "kind": _KIND_NAMES.get(info.kind, str(info.kind)),
            "version": _capi.text(info.version),
            "origin": _capi.text(info.origin),
            "available": bool(info.available),
            "problem": _capi.text(info.problem),
            "description": _capi.text(info.description),
        })
    return out


def version() -> str:
    """The version of the loaded C library, e.g. "0.1.0"."""
    return _capi.text(_capi.lib.sf_version_string())


def _same_memory(a: np.ndarray, b: np.ndarray) -> bool:
    return (a.ctypes.data == b.ctypes.data and a.shape == b.shape and a.strides == b.strides)


def _require_input_files(inputs: Dict[str, str]) -> None:
    if inputs and not _capi.has("sf_filter_set_input_files"):
        raise UnsupportedError("this statfilter library cannot read named inputs from files: update it")


def _set_input_files(handle: Any, inputs: Dict[str, str], check: Callable[[int], None]) -> None:
    """The filter's named inputs as file patterns (sf_filter_set_input_files; _require_input_files first)."""
    for name, pattern in inputs.items():
        check(_capi.lib.sf_filter_set_input_files(handle, _capi.encode(str(name)), _capi.encode_path(pattern)))


class Filter(OwnsHandle):
    """A statfilter filter.

    ``Filter(name, **params)`` creates the filter and sets each parameter with the setter that
    matches the Python type: int (and bool, numpy integers) -> sf_filter_set_int, float ->
    sf_filter_set_float, str -> sf_filter_set_string. Unknown filters and parameters raise
    NotFoundError; values out of range or of the wrong kind raise InvalidArgumentError, leaving
    the old value.

    ``filter(array, out=None, progress=None)`` runs it on a (frames, height, width, channels)
    array and returns ``out`` (a new float32 array when None). Input and output are passed to the
    library without copies (see ``write_sequence`` for when a copy is made); ``out`` must be a
    writeable float32 array of the input's shape and may be the input itself. After a run,
    ``filter.results`` holds the filter's results: {name: float (every result that is a number,
    also those the library keeps as text), str, or for image results (e.g. a per-pixel rank map) a
    float32 array shaped (frames, height, width, channels)}.
    """

    def __init__(self, name: str, **params: ParamValue) -> None:
        self._handle = _capi.sf_filter()
        self.name = str(name)
        self.results: Dict[str, ResultValue] = {}
        check(_capi.lib.sf_filter_create(_capi.encode(self.name), ctypes.byref(self._handle)))
        try:
            self.set(**params)
        except BaseException:
            self.close()
            raise

    # ---- lifetime ----------------------------------------------------------------------------

    def close(self) -> None:
        """Release the C filter (also done when the object is garbage collected)."""
        handle, self._handle = getattr(self, "_handle", None), _capi.sf_filter()
        if handle:
            _capi.lib.sf_filter_release(handle)

    def _live(self):
        if not self._handle:
            raise InvalidArgumentError("filter '%s' is closed" % self.name)
        return self._handle

    def _check(self, status):
        check(status, self._handle)

    # ---- parameters --------------------------------------------------------------------------

    def set(self, **params: ParamValue) -> "Filter":
        """Set parameters by keyword; returns self."""
        for key, value in params.items():
            self[key] = value
        return self

    def __setitem__(self, name: str, value: ParamValue) -> None:
        handle = self._live()
        key = _capi.encode(name)
        if isinstance(value, str):
            self._check(_capi.lib.sf_filter_set_string(handle, key, _capi.encode(value)))
        elif isinstance(value, (bool, numbers.Integral)):
            self._check(_capi.lib.sf_filter_set_int(handle, key, int(value)))
        elif isinstance(value, numbers.Real):
            self._check(_capi.lib.sf_filter_set_float(handle, key, float(value)))
        else:
            raise TypeError("parameter '%s' takes an int, float or str, got %s" % (name, type(value).__name__))

    def __getitem__(self, name: str) -> ParamValue:
        return self.get(name)

    def get(self, name: str) -> ParamValue:
        """The current value of a parameter: int, float or str according to its type."""
        self._live()
        info = {p["name"]: p for p in self._param_infos()}.get(name)
        if info is None:
            # Let the library word the error (it lists the known parameters).
            self._check(_capi.lib.sf_filter_get_string(self._handle, _capi.encode(name), ctypes.byref(ctypes.c_char_p())))
            raise NotFoundError("unknown parameter '%s'" % name)
        return self._get_typed(name, info["type"])

    def _get_typed(self, name: str, type_name: str) -> ParamValue:
        handle, key = self._live(), _capi.encode(name)
        if type_name == "int":
            value = ctypes.c_int64()
            self._check(_capi.lib.sf_filter_get_int(handle, key, ctypes.byref(value)))
            return value.value
        if type_name == "float":
            value = ctypes.c_double()
            self._check(_capi.lib.sf_filter_get_float(handle, key, ctypes.byref(value)))
            return value.value
        value = ctypes.c_char_p()
        self._check(_capi.lib.sf_filter_get_string(handle, key, ctypes.byref(value)))
        return _capi.text(value.value)

    def params(self) -> List[Dict[str, Any]]:
        """The filter's parameters as a list of dicts with keys name, type ("int", "float" or
        "string"), default (text), description, min, max, choices (list of str) and value
        (the current value)."""
        out = self._param_infos()
        for p in out:
            p["value"] = self._get_typed(p["name"], p["type"])
        return out

    def _param_infos(self) -> List[Dict[str, Any]]:
        handle = self._live()
        count = ctypes.c_int()
        self._check(_capi.lib.sf_filter_param_count(handle, ctypes.byref(count)))
        out = []
        for i in range(count.value):
            info = _capi.sf_param_info()
            info.struct_size = ctypes.sizeof(_capi.sf_param_info)
            self._check(_capi.lib.sf_filter_param_info(handle, i, ctypes.byref(info)))
            choices = _capi.text(info.choices)
            out.append({
                "name": _capi.text(info.name),
                "type": _TYPE_NAMES.get(info.type, str(info.type)),
                "default": _capi.text(info.default_value),
                "description": _capi.text(info.description),
                "min": info.min,
                "max": info.max,
                "choices": [c for c in choices.split(",") if c],
            })
        return out

    def _read_results(self) -> Dict[str, ResultValue]:
        handle = self._live()
        count = ctypes.c_int()
        self._check(_capi.lib.sf_filter_result_count(handle, ctypes.byref(count)))
        results: Dict[str, ResultValue] = {}
        for i in range(count.value):
            name = ctypes.c_char_p()
            self._check(_capi.lib.sf_filter_result_name(handle, i, ctypes.byref(name)))
            key = name.value
            number = ctypes.c_double()
            if _capi.lib.sf_filter_result_float(handle, key, ctypes.byref(number)) == _capi.SF_OK:
                results[_capi.text(key)] = number.value
                continue
            text = ctypes.c_char_p()
            self._check(_capi.lib.sf_filter_result_string(handle, key, ctypes.byref(text)))
            value = _capi.text(text.value)
            if _NUMBER_TEXT.fullmatch(value):
                results[_capi.text(key)] = float(value)
                continue
            results[_capi.text(key)] = value
            # An image result's text reads "image <shape>": fetch the image itself as an array.
            if value.startswith("image") and _capi.has("sf_filter_result_sequence"):
                image = _capi.sf_sequence()
                if _capi.lib.sf_filter_result_sequence(handle, key, ctypes.byref(image)) == _capi.SF_OK:
                    results[_capi.text(key)] = _arrays.adopt(image)
        return results

    # ---- running -----------------------------------------------------------------------------

    def __call__(self, array: np.ndarray, out: Optional[np.ndarray] = None,
                 progress: Optional[ProgressCallback] = None,
                 inputs: Optional[Mapping[str, np.ndarray]] = None) -> np.ndarray:
        """Run the filter on ``array``. ``inputs`` maps the names of the filter's extra inputs to
        arrays of the input's shape, e.g. ``{"noisy": noisy}`` for the detect filter."""
        handle = self._live()
        source = _arrays.as_input(array, "input")
        extra = {}
        for name, value in (inputs or {}).items():
            extra[str(name)] = _arrays.as_input(value, "input '%s'" % name)
        if out is None:
            out = np.empty(source.shape, dtype=np.float32)
        if not isinstance(out, np.ndarray):
            raise InvalidArgumentError("out must be a numpy array, got %s" % type(out).__name__)
        if out.dtype != _arrays.FLOAT32:
            raise InvalidArgumentError("out must be float32, got %s" % out.dtype)
        if out.shape != source.shape:
            raise InvalidArgumentError("out has shape %s, the input %s" % (out.shape, source.shape))
        if not out.flags.writeable:
            raise InvalidArgumentError("out is read-only")
        # Write straight into out when the C ABI can (non-negative strides, no self-overlap);
        # otherwise into a temporary copied into out afterwards.
        direct = _arrays.wrappable(out) and all(s > 0 or n == 1 for s, n in zip(out.strides, out.shape))
        target = out if direct else np.empty(out.shape, dtype=np.float32)
        # The C ABI forbids partial overlap of input and output: copy the input then.
        if np.may_share_memory(source, target) and not _same_memory(source, target):
            source = source.copy()

        adapter = ProgressAdapter(progress)
        self.results = {}
        with _arrays.WrappedSequence(source) as seq_in, _arrays.WrappedSequence(target) as seq_out, \
                contextlib.ExitStack() as stack:
            wrapped = {name: stack.enter_context(_arrays.WrappedSequence(a)) for name, a in extra.items()}
            for name, seq in wrapped.items():
                # Cleared again before the wrapped memory goes away (callbacks run last in, first out).
                stack.callback(_capi.lib.sf_filter_set_input, handle, _capi.encode(name), _capi.sf_sequence())
                self._check(_capi.lib.sf_filter_set_input(handle, _capi.encode(name), seq.handle))
            if progress is not None:
                self._check(_capi.lib.sf_filter_set_progress(handle, adapter.c_function, None))
            try:
                status = _capi.lib.sf_filter_execute(handle, seq_in.handle, seq_out.handle)
                error = None
                if status != _capi.SF_OK:
                    message = _capi.text(_capi.lib.sf_filter_last_error(handle)) or \
                        _capi.text(_capi.lib.sf_last_error())
                    error = error_for(status, message)
            finally:
                if progress is not None:
                    _capi.lib.sf_filter_set_progress(handle, _capi.sf_progress_callback(), None)
        adapter.reraise()
        if error is not None:
            raise error
        self.results = self._read_results()
        self._warn()
        if target is not out:
            np.copyto(out, target)
        return out

    def run_files(self, input_pattern: Pattern, output_pattern: Pattern, memory: Union[int, str, None] = None,
                  threads: int = 0, overwrite: bool = False, channels: Optional[Channels] = None,
                  frames: Optional[Frames] = None, pixel_type: str = "half", compression: str = "zip",
                  progress: Optional[ProgressCallback] = None, into: bool = False,
                  inputs: Optional[Mapping[str, Pattern]] = None) -> Dict[str, Any]:
        """Run the filter from one EXR frame sequence to another without holding the shot in memory
        where the filter allows it (pca, error-threshold, moving-basis, the hybrid, the presets, copy and
        diffusion stream; see docs/architecture.md).

        memory:    the budget, bytes or a size such as "2G" (default: half of physical memory); a run
                   that cannot fit raises OutOfMemoryError naming the smallest budget, before any work.
        threads:   0 (default) = every core.
        overwrite: allow the output to replace frames of the input (refused otherwise).
        channels, frames: as read_sequence; pixel_type, compression: as write_sequence.
        into:      write each frame into a copy of its input file instead: the filtered channels in
                   place (in the file's own pixel types, compression and tiling), every other part,
                   channel and header kept as it was.
        inputs:    the filter's named inputs as file patterns with the input's frames, e.g. the
                   renderer's passes {"vectors": "vector.####.exr"} for the hybrid and the presets
                   ("albedo", "normal" too); read a band or a frame at a time beside the input.
        Everything is checked before the first pixel is read; frames appear together at the end.
        """
        from . import sequence as _sequence
        handle = self._live()
        run = _capi.sf_run_options()
        _capi.lib.sf_run_options_init(ctypes.byref(run))
        if memory is not None:
            if isinstance(memory, str):
                size = ctypes.c_int64()
                check(_capi.lib.sf_memory_size_parse(_capi.encode(memory), ctypes.byref(size)))
                memory = size.value
            run.memory = int(memory)
        run.threads = int(threads)
        run.overwrite = 1 if overwrite else 0
        adapter = ProgressAdapter(progress)
        if progress is not None:
            run.progress = adapter.c_function
        read, keep_read = _sequence._read_options(channels, frames)
        write, keep_write = _sequence._write_options(pixel_type, compression)
        write.into = 1 if into else 0
        self.results = {}
        named = dict(inputs or {})
        _require_input_files(named)
        try:
            _set_input_files(handle, named, self._check)
            status = _capi.lib.sf_filter_run(handle, _capi.encode_path(input_pattern), ctypes.byref(read),
                                             _capi.encode_path(output_pattern), ctypes.byref(write), ctypes.byref(run))
        finally:
            for name in named:  # the filter keeps no file input past this run
                _capi.lib.sf_filter_set_input_files(handle, _capi.encode(str(name)), None)
        del keep_read, keep_write
        adapter.reraise()
        if status != _capi.SF_OK:
            message = _capi.text(_capi.lib.sf_filter_last_error(handle)) or _capi.text(_capi.lib.sf_last_error())
            raise error_for(status, message)
        self.results = self._read_results()
        self._warn()
        return self.results

    def _warn(self) -> None:
        """The run's warning (result "warning"), as a StatfilterWarning."""
        if "warning" in self.results:
            warnings.warn(str(self.results["warning"]), StatfilterWarning, stacklevel=3)

    def __repr__(self) -> str:
        if not self._handle:
            return "<statfilter.Filter %r (closed)>" % self.name
        args = "".join(", %s=%r" % (p["name"], p["value"]) for p in self.params())
        return "statfilter.Filter(%r%s)" % (self.name, args)
