"""Lifetime of the objects that own a C handle: close() releases it, and a `with` block or garbage
collection calls close()."""


class OwnsHandle:
    def close(self):
        raise NotImplementedError

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # at interpreter exit the library may already be gone
            pass
