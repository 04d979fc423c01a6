"""Data frames as inputs (pandas, or anything with the same members): S
(or a design) as a DataFrame whose columns name the terms, and the
per-row (dw, sigma) and per-term (spec) vectors as Series.

Labels are never ignored silently: a Series beside a frame S must carry
S's row labels (per-row vectors) or its column names (per-term vectors),
in any order (they are then put in S's order, as pandas aligns); other
labels are refused naming the argument. A Series with the default labels
0 .. n-1 is taken in order only when S's own labels are the default ones
too. Without a frame S, nothing is aligned: arrays are taken in order."""
import numpy as np


def is_frame(x):
    return hasattr(x, "columns") and hasattr(x, "to_numpy")


def _is_series(x):
    return hasattr(x, "index") and hasattr(x, "to_numpy") and not hasattr(x, "columns")


def _labels(index):
    return [str(v) for v in index]


def _align(v, name, want, what):
    """v (a Series) in the order of the labels want, or ValueError."""
    got = _labels(v.index)
    if got == want:
        return v.to_numpy()
    if len(set(got)) == len(got) == len(want) and set(got) == set(want):
        at = {k: i for i, k in enumerate(got)}
        return v.to_numpy()[[at[k] for k in want]]
    raise ValueError("%s: its index (%s) is not %s (%s): align it, or pass an array to pair "
                     "by position" % (name, _short(got), what, _short(want)))


def _short(labels):
    s = ", ".join(labels[:4])
    return s + (", ... (%d)" % len(labels) if len(labels) > 4 else "")


def inputs(S, names, rows=(), cols=()):
    """S as an array, the term names (a frame's columns unless names is
    given), and the vectors of rows (name -> value, per row of S) and of
    cols (name -> value, per term) aligned to S's labels when S is a frame.
    Returns (S, names, {name: value})."""
    out = dict(rows)
    out.update(cols)
    if not is_frame(S):
        return S, names, out
    terms = _labels(S.columns)
    index = _labels(S.index) if hasattr(S, "index") else None
    arr = S.to_numpy()
    if names is None:
        names = terms
    for k, v in rows:
        if _is_series(v) and index is not None:
            out[k] = _align(v, k, index, "S's index")
    for k, v in cols:
        if _is_series(v):
            out[k] = _align(v, k, [str(n) for n in names], "S's columns")
    return arr, names, out
