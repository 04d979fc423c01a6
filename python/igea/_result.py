"""What every result class shares: a concise repr, to_dict() and to_json().

A result is a frozen dataclass whose fields are the JSON keys of the
driver's command of the same name (docs/vocabulary.md). The decorator
`result` gives it

- a repr of one line: scalars and short strings shown, arrays as
  <dtype shape>, nested results and long lists abbreviated;
- to_dict(): the fields as JSON types, as the driver writes them (numpy
  arrays as nested lists, numpy scalars as Python numbers, NaN and
  +-Inf as None, which the driver writes as null; nested results as
  their to_dict());
- to_json(**kw): json.dumps(to_dict(), **kw).

The decorator goes above @dataclass, which would otherwise write its own
(field-by-field, array-printing) repr over the one given here."""
import dataclasses
import json
import math

import numpy as np

__all__ = ["result", "to_json_value"]

_LIST_SHOWN = 6      # lists of at most this many scalars are shown whole
_STR_SHOWN = 40      # longer strings are cut


def to_json_value(v):
    """v as the value the driver's JSON writer gives it (see module doc)."""
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        return v.to_dict() if hasattr(v, "to_dict") else {
            f.name: to_json_value(getattr(v, f.name)) for f in dataclasses.fields(v)}
    if isinstance(v, np.ndarray):
        return to_json_value(v.tolist())
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        v = float(v)
        return v if math.isfinite(v) else None
    if isinstance(v, dict):
        return {str(k): to_json_value(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [to_json_value(x) for x in v]
    return v


def _is_scalar(v):
    return v is None or isinstance(v, (bool, int, float, str, np.bool_, np.number))


def _short(v):
    """The repr of one field value: at most a few dozen characters."""
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        return "<%s>" % type(v).__name__
    if isinstance(v, np.ndarray):
        if v.size == 1 and v.ndim <= 1:
            return "<%s %s: %s>" % (v.dtype, v.shape, _short(v.reshape(-1)[0]))
        return "<%s %s>" % (v.dtype, v.shape)
    if isinstance(v, (bool, np.bool_)):
        return repr(bool(v))
    if isinstance(v, (float, np.floating)):
        return "%.6g" % float(v)
    if isinstance(v, (int, np.integer)):
        return repr(int(v))
    if isinstance(v, str):
        return repr(v if len(v) <= _STR_SHOWN else v[:_STR_SHOWN - 3] + "...")
    if isinstance(v, (list, tuple)):
        if len(v) <= _LIST_SHOWN and all(_is_scalar(x) for x in v):
            inner = ", ".join(_short(x) for x in v)
            return ("[%s]" if isinstance(v, list) else "(%s)") % inner
        kinds = sorted({type(x).__name__ for x in v})
        return "[%d %s]" % (len(v), "/".join(kinds) if kinds else "items")
    if isinstance(v, dict):
        return "{%d keys}" % len(v)
    if v is None:
        return "None"
    return "<%s>" % type(v).__name__


def _repr(self):
    parts = ["%s=%s" % (f.name, _short(getattr(self, f.name)))
             for f in dataclasses.fields(self) if f.repr]
    return "%s(%s)" % (type(self).__name__, ", ".join(parts))


def _to_dict(self):
    """The fields as JSON types: the driver's --json document of the same
    command (arrays as lists, NaN/Inf as None = JSON null)."""
    omit = getattr(self, "_json_omit", ())      # fields the driver writes elsewhere
    d = {f.name: to_json_value(getattr(self, f.name)) for f in dataclasses.fields(self)
         if f.name not in omit}
    extra = getattr(self, "_json_extra", None)   # the driver's keys that are not fields
    if extra is not None:
        d.update({k: to_json_value(v) for k, v in extra().items()})
    return d


def _to_json(self, **kw):
    """json.dumps(self.to_dict(), **kw): the driver's --json document."""
    return json.dumps(self.to_dict(), allow_nan=False, **kw)


def result(cls):
    """Class decorator (above @dataclass): concise repr, to_dict, to_json."""
    if not dataclasses.is_dataclass(cls):
        raise TypeError("igea._result.result: %s is not a dataclass (put the decorator "
                        "above @dataclass)" % cls.__name__)
    cls.__repr__ = _repr
    if "to_dict" not in cls.__dict__:
        cls.to_dict = _to_dict
    if "to_json" not in cls.__dict__:
        cls.to_json = _to_json
    return cls
