"""vi.Error: the library's status codes and messages as a Python exception."""
from typing import Optional

from ._vi import ffi, lib


class Error(Exception):
    """A failure reported by the vibroimpact library.

    Attributes
    ----------
    message : str
        The library's detail (for scenes: ``file:line:column: key = value: why``).
    status : int
        The library's status code (``vi_status``, negative for errors).
    status_name : str
        Its symbolic name, e.g. ``"VI_ERR_RESTITUTION"``.
    file, line, column, key, value :
        Where a scene failed (``None`` when not known or not a scene).
    """

    def __init__(self, message: str, status: int = -1, *, file: Optional[str] = None,
                 line: Optional[int] = None, column: Optional[int] = None,
                 key: Optional[str] = None, value: Optional[str] = None):
        super().__init__(message)
        self.message = message
        self.status = int(status)
        self.status_name = ffi.string(lib.vi_status_name(self.status)).decode()
        self.file = file
        self.line = line
        self.column = column
        self.key = key
        self.value = value

    def __reduce__(self):
        return (_rebuild, (self.message, self.status, self.file, self.line,
                           self.column, self.key, self.value))


def _rebuild(message, status, file, line, column, key, value):
    return Error(message, status, file=file, line=line, column=column, key=key,
                 value=value)


def _s(p) -> str:
    return ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else ""


def strerror(status: int) -> str:
    """The library's fixed message for a status code."""
    return _s(lib.vi_strerror(int(status)))


def check(status: int, detail: str = "", what: str = "") -> int:
    """Raise Error for a negative status; return the status otherwise."""
    if status < 0:
        msg = detail or strerror(status)
        if what:
            msg = "%s: %s" % (what, msg)
        raise Error(msg, status)
    return status


def diag_error(d, status: int) -> Error:
    """An Error from a vi_diag (scene reader, writer)."""
    code = d.code or status
    buf = ffi.new("char[]", 1400)
    if not d.code:
        d.code = status
    if not ffi.string(d.message):
        msg = lib.vi_strerror(status)
        n = min(len(ffi.string(msg)), 511)
        ffi.memmove(d.message, msg, n)
    lib.vi_diag_format(d, buf, 1400)
    return Error(_s(buf), code, file=_s(d.file) or None, line=d.line or None,
                 column=d.column or None, key=_s(d.key) or None,
                 value=_s(d.value) or None)
