"""A library function is replaced only where it is the code the replacement was written for."""
from __future__ import annotations

import types

from ringlab.server import library_patch


def library_function(x):
    return x + 1


def test_replaced_only_if_the_source_matches():
    owner = types.SimpleNamespace(f=library_function)
    originals = {}
    assert not library_patch.replace_if_unchanged(owner, "f", abs, "0" * 64, originals)  # the library changed
    assert owner.f is library_function and not originals
    sha = library_patch.source_sha256(library_function)
    assert library_patch.replace_if_unchanged(owner, "f", abs, sha, originals)
    assert owner.f is abs and originals == {"f": library_function}
    assert library_patch.replace_if_unchanged(owner, "f", abs, sha, originals)  # once only
    assert not library_patch.matches(len, sha)  # a builtin has no source
