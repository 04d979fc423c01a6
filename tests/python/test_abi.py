"""The ctypes prototype table against the library's exports."""
import subprocess

import igea  # noqa: F401  (loads the library)
from igea import _lib


def test_prototype_table_matches_exports():
    """Every exported igea_* symbol is declared in _lib.PROTOTYPES and vice versa."""
    from igea import _lib
    path = _lib.lib._name
    out = subprocess.run(["nm", "-D", "--defined-only", path], capture_output=True, text=True).stdout
    exported = {line.split()[-1] for line in out.splitlines() if line.split()[-1].startswith("igea_")}
    assert exported == set(_lib.PROTOTYPES), exported ^ set(_lib.PROTOTYPES)
