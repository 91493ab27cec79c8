"""Shared fixtures. The tests run against the installed package (the wheel with the library
inside it); the repository's root gives the header and the C programs they compare with."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture
def root():
    return ROOT


@pytest.fixture
def paper():
    """A 1,000-strand paper-scene groom."""
    import wethair

    with wethair.Groom.paper_scene(1000, 6) as g:
        yield g


def require_gpu():
    """Whether a missing GPU adapter must fail the test (CI sets WETHAIR_REQUIRE_GPU=1)."""
    return os.environ.get("WETHAIR_REQUIRE_GPU") == "1"
