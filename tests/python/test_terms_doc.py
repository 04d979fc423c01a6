"""docs/terms.md is the table generated from the library's term catalogue."""
import os
import sys

from igea import _lib

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "tests"))
import gen_terms_doc  # noqa: E402


def test_terms_doc_is_generated_from_the_library():
    want = gen_terms_doc.render(gen_terms_doc.load(_lib.lib._name))
    with open(os.path.join(REPO, "docs", "terms.md")) as fh:
        have = fh.read()
    assert have == want, ("docs/terms.md differs from the library's catalogue: run "
                          "python3 tests/gen_terms_doc.py build/lib/libigea.so.1 docs/terms.md")
