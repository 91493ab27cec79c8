"""Runs the add-on's tests in real Blender: the ``bpy`` module (Blender as a Python module,
from PyPI) with the installed ``wethair`` wheel; the add-on is imported from this folder's
parent, as Blender would load it."""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [os.path.dirname(HERE), HERE]


def pytest_unconfigure(config):
    # bpy 4.5's module build can hang in its exit handlers (a helper thread's condition
    # variable is destroyed while the thread waits on it); the results are already written,
    # so leave without them.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(int(getattr(config, "_wethair_status", 0)))


def pytest_sessionfinish(session, exitstatus):
    session.config._wethair_status = exitstatus
