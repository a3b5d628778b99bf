"""statfilter: temporal denoising of rendered frame sequences (ctypes bindings of libstatfilter).

Arrays are float32 NumPy arrays shaped (frames, height, width, channels).

    import statfilter as sf
    noisy, info = sf.read_sequence("render/indirect.####.exr", return_info=True)
    out = sf.Filter("copy")(noisy)
    sf.write_sequence("out/indirect.####.exr", out, frame_numbers=info.frame_numbers,
                      channel_names=info.channel_names)
"""

from ._oidn_library import use_pyoidn_if_unset

use_pyoidn_if_unset()  # before any plugin is loaded: the oidn plugin then finds pyoidn's library

from ._capi import library_path  # noqa: E402
from .errors import (CancelledError, Error, FileError, InternalError, InvalidArgumentError,  # noqa: E402
                     NotFoundError, NumericError, OutOfMemoryError, StatfilterWarning, UnsupportedError)
from .filter import Filter, filters, plugins, version  # noqa: E402
from .detect import Detection, crop_windows, detect, merge  # noqa: E402
from .metrics import compare  # noqa: E402
from .sequence import SequenceInfo, Window, pattern_format, pattern_frames, read_sequence, write_sequence  # noqa: E402

__version__ = "0.1.0"

__all__ = [
    "Detection", "crop_windows", "detect", "merge",
    "CancelledError", "Error", "FileError", "Filter", "InternalError", "InvalidArgumentError", "NotFoundError",
    "NumericError", "OutOfMemoryError", "SequenceInfo", "StatfilterWarning", "UnsupportedError", "Window", "compare", "filters", "library_path",
    "pattern_format", "pattern_frames", "plugins", "read_sequence", "version", "write_sequence",
]
