"""Reading matrix files the way the driver reads them (igea/io.h): text
(blanks, tabs or commas; '#' comments; D exponents; a UTF-8 byte order
mark and CRLF; a header row or '# names' line of column names) and .npy
(float64, C or Fortran order), through the library's reader, so that a file
that works in one works in the other."""
import ctypes
import os
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib


@dataclass(frozen=True)
class MatrixFile:
    """A matrix file read by igea.read_matrix(path, names=True)."""
    values: np.ndarray   # rows x cols, float64
    names: tuple         # the column names, () when the file has none

    def __repr__(self):
        return "MatrixFile(values=<%d x %d>, names=%r)" % (*self.values.shape, self.names)


def _failure(r, path, status, function):
    """IgeaError with the text "PATH:LINE:COL: message" the driver writes."""
    info = np.zeros(_capi.IO_INFO_LEN)
    _lib.lib.igea_io_reader_info(r, _lib.dptr(info))
    line, col = int(info[_capi.IO_INFO_LINE]), int(info[_capi.IO_INFO_COLUMN])
    err = int(info[_capi.IO_INFO_ERRNO])
    msg = _lib.lib.igea_io_reader_message(r).decode(errors="replace")
    where = path + "".join(":%d" % k for k in (line, col) if k > 0) if line > 0 else path
    if err:
        msg = msg + ": " + os.strerror(err) if msg else os.strerror(err)
    return _lib.IgeaError(status, msg, where, function)


def read_matrix(path, names=False):
    """The matrix in the text or .npy file at path as a rows x cols float64
    array (always 2-D: a 1-D .npy or a one-column text is one column).
    names=True returns a MatrixFile(values, names) with the column names of
    a header row or '# names' line. A malformed or unreadable file raises
    IgeaError whose text names file:line:column as the driver does."""
    p = os.fspath(path)
    shown = p if isinstance(p, str) else os.fsdecode(p)
    if "\0" in shown:
        raise ValueError("igea.read_matrix: path: a NUL character in %r" % shown)
    h = ctypes.c_void_p()
    _lib.call("igea.read_matrix", "igea_io_reader_create", ctypes.byref(h))
    try:
        for function, args in (("igea_io_reader_open", (os.fsencode(p), 0, None)),
                               ("igea_io_reader_load", ())):
            st = getattr(_lib.lib, function)(h, *args)
            if st != 0:
                raise _failure(h, shown, st, function)
        info = np.zeros(_capi.IO_INFO_LEN)
        _lib.lib.igea_io_reader_info(h, _lib.dptr(info))
        rows, cols = int(info[_capi.IO_INFO_ROWS]), int(info[_capi.IO_INFO_COLS])
        out = np.empty((rows, cols))
        _lib.call("igea.read_matrix", "igea_io_reader_copy", h, _lib.dptr(out),
                  _capi.ROWMAJOR)
        text = _lib.lib.igea_io_reader_names(h).decode(errors="replace")
    finally:
        _lib.lib.igea_io_reader_free(h)
    if names:
        return MatrixFile(out, tuple(text.split("\n")) if text else ())
    return out
