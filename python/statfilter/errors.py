"""Exceptions: one ``statfilter.Error`` subclass per C status code, carrying the C message.

Each subclass also derives from the closest built-in exception, so ``except ValueError`` or
``except OSError`` catch them too:

==============================  =====================  ================
status                          class                  also a
==============================  =====================  ================
SF_ERROR_INVALID_ARGUMENT (1)   InvalidArgumentError   ValueError
SF_ERROR_OUT_OF_MEMORY (2)      OutOfMemoryError       MemoryError
SF_ERROR_IO (3)                 FileError              OSError
SF_ERROR_NOT_FOUND (4)          NotFoundError          LookupError
SF_ERROR_UNSUPPORTED (5)        UnsupportedError       NotImplementedError
SF_ERROR_CANCELLED (6)          CancelledError
SF_ERROR_NUMERIC (7)            NumericError           ArithmeticError
SF_ERROR_INTERNAL (8)           InternalError          RuntimeError
==============================  =====================  ================
"""

from __future__ import annotations

from typing import Any, Optional, Tuple

from . import _capi


class Error(Exception):
    """Base of every statfilter error. ``status`` is the C sf_status code, ``status_name`` its
    name (e.g. "SF_ERROR_IO") and ``message`` the library's message."""

    status: Optional[int] = None  # set on each subclass

    def __init__(self, message: str, status: Optional[int] = None) -> None:
        if status is None:
            status = type(self).status
        self.message = message
        self.status = status
        super().__init__(message)

    @property
    def status_name(self) -> str:
        return _capi.text(_capi.lib.sf_status_name(self.status if self.status is not None else -1))

    def __str__(self) -> str:
        return self.message

    def __reduce__(self) -> Tuple[Any, ...]:
        return (type(self), (self.message, self.status))


class InvalidArgumentError(Error, ValueError):
    """A NULL pointer, bad value, wrong size or shape, or a value outside a parameter's range."""
    status = _capi.SF_ERROR_INVALID_ARGUMENT


class OutOfMemoryError(Error, MemoryError):
    status = _capi.SF_ERROR_OUT_OF_MEMORY


class FileError(Error, OSError):
    """A file could not be read or written (not an image, truncated, unwritable directory)."""
    status = _capi.SF_ERROR_IO


class NotFoundError(Error, LookupError):
    """No such frame, channel, layer, filter or parameter."""
    status = _capi.SF_ERROR_NOT_FOUND


class UnsupportedError(Error, NotImplementedError):
    status = _capi.SF_ERROR_UNSUPPORTED


class CancelledError(Error):
    """The progress callback asked to stop."""
    status = _capi.SF_ERROR_CANCELLED


class NumericError(Error, ArithmeticError):
    """NaN/Inf or other values the chosen policy rejects (e.g. beyond half float's range)."""
    status = _capi.SF_ERROR_NUMERIC


class InternalError(Error, RuntimeError):
    status = _capi.SF_ERROR_INTERNAL


class StatfilterWarning(UserWarning):
    """Something about a run the user must know although it succeeded (the filter's result
    "warning"), e.g. noise that is the same in every frame, which no temporal filter removes."""


ERRORS = {cls.status: cls for cls in (InvalidArgumentError, OutOfMemoryError, FileError, NotFoundError,
                                      UnsupportedError, CancelledError, NumericError, InternalError)}


def error_for(status: int, message: Optional[str]) -> Error:
    """The exception for a status code (an unknown code gives a plain Error)."""
    cls = ERRORS.get(status)
    if cls is None:
        return Error(message or "unknown status %d" % status, status)
    return cls(message or _capi.text(_capi.lib.sf_status_name(status)), status)


def check(status: int, handle: Any = None) -> None:
    """Raise the matching Error unless status is SF_OK. The message comes from
    ``sf_filter_last_error(handle)`` when a filter handle is given, else ``sf_last_error()``.
    Call it right after the C call, before any other statfilter call on this thread."""
    if status == _capi.SF_OK:
        return
    message = ""
    if handle is not None:
        message = _capi.text(_capi.lib.sf_filter_last_error(handle))
    if not message:
        message = _capi.text(_capi.lib.sf_last_error())
    raise error_for(status, message)
