"""Lifetime of the objects that own a C handle: close() releases it, and a `with` block or garbage
collection calls close()."""

from __future__ import annotations


from typing import Any, TypeVar

_Self = TypeVar("_Self", bound="OwnsHandle")


class OwnsHandle:
    def close(self) -> None:
        raise NotImplementedError

    def __enter__(self: _Self) -> _Self:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # at interpreter exit the library may already be gone
            pass
