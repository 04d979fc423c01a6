"""Keywords renamed to the driver's spelling (docs/vocabulary.md): the old
name is still accepted, with a DeprecationWarning, and giving both is an
error."""
import warnings

_UNSET = object()


def renamed(where, new_name, new_value, old_name, old_value, default=None):
    """The value of keyword new_name, or of its old spelling old_name (with a
    DeprecationWarning). Either one left at _UNSET counts as not given."""
    if old_value is _UNSET:
        return default if new_value is _UNSET else new_value
    if new_value is not _UNSET:
        raise TypeError(f"{where}: give {new_name}= only ({old_name}= is its old name)")
    warnings.warn(f"{where}: {old_name}= is now {new_name}= (the driver's --"
                  f"{new_name.replace('_', '-')})", DeprecationWarning, stacklevel=3)
    return old_value
