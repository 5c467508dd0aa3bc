"""Shared paths for the Python package's tests."""
import os
import shutil

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENES = os.path.join(ROOT, "share", "scenes")


def program():
    """The command-line program of the same build, or None."""
    env = os.environ.get("VIBROIMPACT_PROGRAM")
    if env:
        return env
    for d in ("test-release", "rel", "python"):
        p = os.path.join(ROOT, "build", d, "vibroimpact")
        if os.access(p, os.X_OK):
            return p
    return shutil.which("vibroimpact")


@pytest.fixture
def prog():
    p = program()
    if not p:
        pytest.skip("the vibroimpact program is not built")
    return p
