"""statfilter: temporal denoising of rendered frame sequences (ctypes bindings of libstatfilter).

Arrays are float32 NumPy arrays shaped (frames, height, width, channels).

    import statfilter as sf
    noisy, info = sf.read_sequence("render/indirect.####.exr", return_info=True)
    out = sf.Filter("copy")(noisy)
    sf.write_sequence("out/indirect.####.exr", out, frame_numbers=info.frame_numbers,
                      channel_names=info.channel_names)
"""

from ._capi import library_path
from .errors import (CancelledError, Error, FileError, InternalError, InvalidArgumentError, NotFoundError,
                     NumericError, OutOfMemoryError, UnsupportedError)
from .filter import Filter, filters, version
from .metrics import compare
from .sequence import SequenceInfo, pattern_format, pattern_frames, read_sequence, write_sequence

__version__ = "0.1.0"

__all__ = [
    "CancelledError", "Error", "FileError", "Filter", "InternalError", "InvalidArgumentError", "NotFoundError",
    "NumericError", "OutOfMemoryError", "SequenceInfo", "UnsupportedError", "compare", "filters", "library_path",
    "pattern_format", "pattern_frames", "read_sequence", "version", "write_sequence",
]
