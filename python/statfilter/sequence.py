"""Reading and writing frame sequences (EXR) as NumPy arrays.

Patterns: one ``#`` or ``@`` per digit as in Nuke and Houdini (``beauty.####.exr`` is
``beauty.0001.exr``; a lone ``#`` is 4 digits; not oiiotool's convention, where each ``#`` is 4
digits), or ``beauty.%04d.exr``. Arrays are float32, shaped (frames, height, width, channels).
"""

from __future__ import annotations

import ctypes
import numbers
import os
from typing import Any, List, Literal, NamedTuple, Optional, Sequence, Tuple, Union, overload

import numpy as np

from . import _arrays, _capi
from ._progress import ProgressAdapter, ProgressCallback
from .errors import InvalidArgumentError, check

#: What ``read_sequence(..., return_info=True)`` returns beside the array.
class Window(NamedTuple):
    """A rectangle of pixels in a file's coordinates (an EXR data or display window)."""
    x: int
    y: int
    width: int
    height: int


class SequenceInfo(NamedTuple):
    """channel_names: list of str, one per channel (a layer's channels are named by their suffix,
    e.g. R, G, B); frame_numbers: list of int, the number on disk of each frame, ascending;
    data_window: where the array's pixels sit in the files (a region render: not at the origin);
    display_window: the frame they belong to. Give both to write_sequence to write the region back
    where it was."""
    channel_names: List[str]
    frame_numbers: List[int]
    data_window: Optional[Window] = None
    display_window: Optional[Window] = None


#: A file pattern or name (str, bytes or a path).
Pattern = Union[str, bytes, "os.PathLike[str]"]
#: Frames to read: "1-48", "1-10,12", an int, a range or a list of ints.
Frames = Union[str, bytes, int, range, Sequence[int]]
#: Channels to read: "R,G,B", a layer name, or a list of names.
Channels = Union[str, bytes, Sequence[str]]

_PIXEL_TYPES = {"half": _capi.SF_PIXEL_HALF, "float": _capi.SF_PIXEL_FLOAT}
_HALF_OVERFLOW = {"error": 0, "clamp": 1}
_DEFAULT_CHANNEL_NAMES = {1: ["Y"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}


def _channels_text(channels: Optional[Channels]) -> Optional[bytes]:
    if channels is None:
        return None
    if isinstance(channels, (str, bytes)):
        return _capi.encode(channels)
    names = list(channels)
    if not all(isinstance(n, str) for n in names):
        raise TypeError("channels must be a string or a list of strings, got %r" % (channels,))
    return ",".join(names).encode("utf-8")


def _frames_text(frames: Optional[Frames]) -> Optional[bytes]:
    if frames is None:
        return None
    if isinstance(frames, (str, bytes)):
        return _capi.encode(frames)
    if isinstance(frames, bool):
        raise TypeError("frames must be a frame range string, an int or a list of ints")
    if isinstance(frames, numbers.Integral):
        return str(int(frames)).encode()
    if isinstance(frames, range) and len(frames) > 0 and frames.step > 0:
        last = frames[-1]
        text = "%d-%d" % (frames.start, last) if frames.step == 1 else "%d-%dx%d" % (frames.start, last, frames.step)
        return text.encode()
    items = list(frames)
    if not items or not all(isinstance(f, numbers.Integral) and not isinstance(f, bool) for f in items):
        raise TypeError("frames must be a frame range string ('1-48', '1-10,12'), an int, or a non-empty "
                        "list of ints, got %r" % (frames,))
    return ",".join(str(int(f)) for f in items).encode()


def _choice(value, table, what):
    try:
        return table[value]
    except (KeyError, TypeError):
        raise InvalidArgumentError("%s must be one of %s, got %r" % (what, ", ".join(map(repr, table)), value)) from None


def _set_colour_and_progress(options, ocio_config, colorspace_in, colorspace_out, progress):
    """The fields sf_read_options and sf_write_options share (the structure keeps the encoded
    strings alive). Returns the progress adapter, to keep until the call returns."""
    options.ocio_config = _capi.encode(ocio_config)
    options.colorspace_in = _capi.encode(colorspace_in)
    options.colorspace_out = _capi.encode(colorspace_out)
    adapter = ProgressAdapter(progress)
    if progress is not None:
        options.progress = adapter.c_function
    return adapter


def _read_options(channels: Optional[Channels], frames: Optional[Frames]) -> Tuple[Any, Any]:
    """sf_read_options for a channel and frame selection, and the encoded strings it points to."""
    options = _capi.sf_read_options()
    _capi.lib.sf_read_options_init(ctypes.byref(options))
    keep = (_channels_text(channels), _frames_text(frames))
    options.channels, options.frames = keep
    return options, keep


def _write_options(pixel_type: str, compression: str) -> Tuple[Any, Any]:
    """sf_write_options for a pixel type and compression, and the encoded string it points to."""
    options = _capi.sf_write_options()
    _capi.lib.sf_write_options_init(ctypes.byref(options))
    options.pixel_type = _choice(pixel_type, _PIXEL_TYPES, "pixel_type")
    keep = _capi.encode(compression)
    options.compression = keep
    return options, keep


@overload
def read_sequence(pattern: Pattern, channels: Optional[Channels] = ..., frames: Optional[Frames] = ...,
                  ocio_config: Optional[str] = ..., colorspace_in: Optional[str] = ...,
                  colorspace_out: Optional[str] = ..., progress: Optional[ProgressCallback] = ...,
                  return_info: Literal[False] = ...) -> np.ndarray: ...
@overload
def read_sequence(pattern: Pattern, channels: Optional[Channels] = ..., frames: Optional[Frames] = ...,
                  ocio_config: Optional[str] = ..., colorspace_in: Optional[str] = ...,
                  colorspace_out: Optional[str] = ..., progress: Optional[ProgressCallback] = ...,
                  *, return_info: Literal[True]) -> Tuple[np.ndarray, SequenceInfo]: ...
def read_sequence(pattern: Pattern, channels: Optional[Channels] = None, frames: Optional[Frames] = None,
                  ocio_config: Optional[str] = None, colorspace_in: Optional[str] = None,
                  colorspace_out: Optional[str] = None, progress: Optional[ProgressCallback] = None,
                  return_info: bool = False) -> Union[np.ndarray, Tuple[np.ndarray, SequenceInfo]]:
    """Read a frame sequence into a float32 array shaped (frames, height, width, channels).

    pattern:   ``dir/beauty.####.exr`` (or ``%04d``, ``#``, ``@@@``); a name without a frame token
               reads that one file as a single frame.
    channels:  None for the default: every channel of a file without layers (R, G, B, A), the
               light passes of a file with layers (no Normal, Albedo, *Color, Depth/Z, Vector,
               Alpha/A, Denoising*, ...); ``"*"`` for every channel of every part; else channel
               and/or layer names, as a list or a comma-separated string, e.g. ``"R,G,B"`` or
               ``"ViewLayer.Diffuse Indirect"`` (one layer alone is named by its suffixes R, G, B;
               several names keep the file's full channel names).
    frames:    None for every frame found on disk (a gap in the numbering is an error); else a
               range string ``"1-48"``, ``"1-10,12"``, ``"1-20x2"``, an int, a range or a list of
               ints. Frames are always returned in ascending order.
    ocio_config, colorspace_in, colorspace_out: convert colours with OpenColorIO after reading
               (both colour spaces or neither; ocio_config None means ``$OCIO``).
    progress:  optional ``progress(fraction, stage)``; return False to cancel (CancelledError).
    return_info: if true, return ``(array, SequenceInfo(channel_names, frame_numbers))``.

    The array uses the memory the library read the files into (no copy); that memory is freed
    when the array and every view of it are gone.

    Raises NotFoundError (missing frame, gap, unknown channel or layer), FileError (unreadable or
    non-image file), InvalidArgumentError (bad range, frames of different sizes), CancelledError.
    """
    options = _capi.sf_read_options()
    _capi.lib.sf_read_options_init(ctypes.byref(options))
    options.channels = _channels_text(channels)
    options.frames = _frames_text(frames)
    adapter = _set_colour_and_progress(options, ocio_config, colorspace_in, colorspace_out, progress)

    handle = _capi.sf_sequence()
    status = _capi.lib.sf_sequence_read(_capi.encode_path(pattern), ctypes.byref(options), ctypes.byref(handle))
    adapter.reraise()
    check(status)
    try:
        shape = _capi.sf_shape()
        check(_capi.lib.sf_sequence_shape(handle, ctypes.byref(shape)))
        data, display = _capi.sf_window(), _capi.sf_window()
        check(_capi.lib.sf_sequence_frame_windows(handle, 0, ctypes.byref(data), ctypes.byref(display), None))
        info = SequenceInfo(_arrays.channel_names(handle, shape.channels),
                            _arrays.frame_numbers(handle, shape.frames), _window(data), _window(display))
    except BaseException:
        _capi.lib.sf_sequence_release(handle)
        raise
    array = _arrays.adopt(handle)
    return (array, info) if return_info else array


def _window(w: Any) -> Window:
    return Window(int(w.x), int(w.y), int(w.width), int(w.height))


def _sf_window(w: Sequence[int], what: str) -> Any:
    try:
        x, y, width, height = (int(v) for v in w)
    except (TypeError, ValueError):
        raise InvalidArgumentError("%s must be (x, y, width, height), got %r" % (what, w)) from None
    return _capi.sf_window(x, y, width, height)


def write_sequence(pattern: Pattern, array: np.ndarray, pixel_type: str = "half", compression: str = "zip",
                   frame_numbers: Optional[Sequence[int]] = None, channel_names: Optional[Union[str, Sequence[str]]] = None,
                   half_overflow: str = "error", ocio_config: Optional[str] = None, colorspace_in: Optional[str] = None,
                   colorspace_out: Optional[str] = None, progress: Optional[ProgressCallback] = None,
                   data_window: Optional[Sequence[int]] = None,
                   display_window: Optional[Sequence[int]] = None) -> List[Union[str, bytes]]:
    """Write an array shaped (frames, height, width, channels) as one EXR file per frame.

    The array is passed to the library without a copy when it is float32 with non-negative
    strides (any view, including non-contiguous ones); other dtypes, negative strides and
    misaligned data are converted to a contiguous float32 copy first.

    pattern:       ``dir/out.####.exr``; a pattern without a frame token takes one frame only.
    pixel_type:    "half" (default) or "float".
    compression:   EXR compression: "zip" (default), "none", "rle", "zips", "piz", "pxr24",
                   "b44", "b44a", "dwaa", "dwab" (optionally with a level, "dwaa:45").
    frame_numbers: the number of each frame on disk; default 1..frames. Must be distinct.
    channel_names: one name per channel; default R,G,B (3 channels), R,G,B,A (4), Y (1), else
                   C0, C1, ...
    half_overflow: "error" (default): a finite value beyond half's range (65504) raises
                   NumericError before any file is written; "clamp": clamp to +-65504.
    ocio_config, colorspace_in, colorspace_out: convert colours before writing (both or neither).
    progress:      optional ``progress(fraction, stage)``; return False to cancel.
    data_window, display_window: (x, y, width, height) where the pixels go (the data window,
                   the array's width x height) inside which frame (the display window; default the
                   data window), e.g. a region read with ``return_info=True`` written back in place.
                   Default: at the origin of a frame of the array's size.

    Every frame goes to a temporary file renamed into place, so a failure leaves no partial
    frame. Returns the list of file names written.
    """
    a = _arrays.as_input(array, "array")
    frames, _, _, nchannels = a.shape
    if channel_names is None:
        channel_names = _DEFAULT_CHANNEL_NAMES.get(nchannels)
    elif isinstance(channel_names, str):
        channel_names = [n.strip() for n in channel_names.split(",")]
    if channel_names is not None:
        channel_names = [str(n) for n in channel_names]
        if len(channel_names) != nchannels:
            raise InvalidArgumentError("%d channel names given for %d channels" % (len(channel_names), nchannels))
    if frame_numbers is not None:
        frame_numbers = [int(n) for n in np.asarray(frame_numbers).reshape(-1)]
        if len(frame_numbers) != frames:
            raise InvalidArgumentError("%d frame numbers given for %d frames" % (len(frame_numbers), frames))
        if len(set(frame_numbers)) != frames:
            raise InvalidArgumentError("frame numbers must be distinct, got %s" % frame_numbers)

    options = _capi.sf_write_options()
    _capi.lib.sf_write_options_init(ctypes.byref(options))
    options.pixel_type = _choice(pixel_type, _PIXEL_TYPES, "pixel_type")
    options.half_overflow = _choice(half_overflow, _HALF_OVERFLOW, "half_overflow")
    compression_bytes = _capi.encode(compression)  # kept alive by this frame until the call returns
    options.compression = compression_bytes
    adapter = _set_colour_and_progress(options, ocio_config, colorspace_in, colorspace_out, progress)

    pattern_bytes = _capi.encode_path(pattern)
    with _arrays.WrappedSequence(a) as seq:
        _arrays.set_attributes(seq.handle, channel_names, frame_numbers)
        if data_window is not None or display_window is not None:
            if data_window is None:
                raise InvalidArgumentError("display_window needs the data_window of the pixels inside it")
            data = _sf_window(data_window, "data_window")
            display = _sf_window(display_window, "display_window") if display_window is not None else None
            check(_capi.lib.sf_sequence_set_frame_windows(seq.handle, -1, ctypes.byref(data),
                                                          ctypes.byref(display) if display is not None else None))
        numbers_written = _arrays.frame_numbers(seq.handle, frames)
        status = _capi.lib.sf_sequence_write(seq.handle, pattern_bytes, ctypes.byref(options))
        adapter.reraise()
        check(status)
    return [pattern_format(pattern, n) for n in numbers_written]


def pattern_frames(pattern: Pattern) -> List[int]:
    """The frame numbers found on disk for a pattern, ascending. NotFoundError if none."""
    p = _capi.encode_path(pattern)
    count = ctypes.c_size_t()
    check(_capi.lib.sf_pattern_frames(p, None, 0, ctypes.byref(count)))
    buffer = (ctypes.c_int64 * max(count.value, 1))()
    check(_capi.lib.sf_pattern_frames(p, buffer, count.value, ctypes.byref(count)))
    return list(buffer[:count.value])


def pattern_format(pattern: Pattern, frame: int) -> Union[str, bytes]:
    """The file name of one frame of a pattern, e.g. ("a.####.exr", 7) -> "a.0007.exr"."""
    p = _capi.encode_path(pattern)
    needed = ctypes.c_size_t()
    check(_capi.lib.sf_pattern_format(p, int(frame), None, 0, ctypes.byref(needed)))
    buffer = ctypes.create_string_buffer(needed.value)
    check(_capi.lib.sf_pattern_format(p, int(frame), buffer, needed.value, ctypes.byref(needed)))
    name = buffer.value
    return name if isinstance(pattern, bytes) else os.fsdecode(name)
