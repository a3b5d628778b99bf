"""Adapting a Python progress callable to sf_progress_callback.

The Python callable is ``progress(fraction, stage)`` with fraction in [0, 1] and stage a short
name ("read", "write", "copy", ...). Returning None or a true value continues; returning False
(or any other false value except None) cancels the work, which then raises CancelledError.

An exception raised by the callable never crosses into C: it is caught, the work is cancelled,
and ``reraise()`` raises it again once the C call has returned.
"""

from __future__ import annotations

from typing import Any, Callable, Optional

from . import _capi

#: ``progress(fraction, stage)``: fraction in [0, 1], stage a short name; returning False cancels.
ProgressCallback = Callable[[float, str], Optional[bool]]


class ProgressAdapter:
    def __init__(self, callback: Optional[ProgressCallback]) -> None:
        if callback is not None and not callable(callback):
            raise TypeError("progress must be callable as progress(fraction, stage), got %r" % (callback,))
        self.callback = callback
        self.exception: Optional[BaseException] = None
        # The ctypes function object must stay alive while C may call it: it lives on self, and
        # callers keep self until the C call has returned.
        self.c_function = _capi.sf_progress_callback(self._call) if callback is not None \
            else _capi.sf_progress_callback()  # NULL

    def _call(self, user: Any, fraction: float, stage: bytes) -> int:
        if self.exception is not None:
            return 1
        try:
            result = self.callback(fraction, _capi.text(stage))
        except BaseException as exc:  # includes KeyboardInterrupt: must not unwind through C
            self.exception = exc
            return 1
        return 1 if (result is not None and not result) else 0

    def reraise(self) -> None:
        """Raise the exception the callable raised during the last C call, if any."""
        exc, self.exception = self.exception, None
        if exc is not None:
            raise exc
