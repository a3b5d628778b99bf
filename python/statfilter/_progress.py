"""Adapting a Python progress callable to sf_progress_callback.

The Python callable is ``progress(fraction, stage)`` with fraction in [0, 1] and stage a short
name ("read", "write", "copy", ...). Returning None or a true value continues; returning False
(or any other false value except None) cancels the work, which then raises CancelledError.

An exception raised by the callable never crosses into C: it is caught, the work is cancelled,
and ``reraise()`` raises it again once the C call has returned.
"""

from . import _capi


class ProgressAdapter:
    def __init__(self, callback):
        if callback is not None and not callable(callback):
            raise TypeError("progress must be callable as progress(fraction, stage), got %r" % (callback,))
        self.callback = callback
        self.exception = None
        # The ctypes function object must stay alive while C may call it: it lives on self, and
        # callers keep self until the C call has returned.
        self.c_function = _capi.sf_progress_callback(self._call) if callback is not None \
            else _capi.sf_progress_callback()  # NULL

    def _call(self, user, fraction, stage):
        if self.exception is not None:
            return 1
        try:
            result = self.callback(fraction, _capi.text(stage))
        except BaseException as exc:  # includes KeyboardInterrupt: must not unwind through C
            self.exception = exc
            return 1
        return 1 if (result is not None and not result) else 0

    def reraise(self):
        """Raise the exception the callable raised during the last C call, if any."""
        exc, self.exception = self.exception, None
        if exc is not None:
            raise exc
