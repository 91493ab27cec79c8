"""Builds the wheel with the compiled library inside it (a platform wheel, not a pure one).

The library is taken from ``$WETHAIR_LIBRARY`` or ``../../target/release`` (build it first:
``cargo build --release``); ``scripts/python.sh`` does both steps."""

import os
import shutil
import subprocess
import sys

from setuptools import setup
from setuptools.command.build_py import build_py
from wheel.bdist_wheel import bdist_wheel

HERE = os.path.dirname(os.path.abspath(__file__))
NAME = {"darwin": "libwethair.dylib", "win32": "wethair.dll"}.get(sys.platform, "libwethair.so")


class BuildWithLibrary(build_py):
    """Copies the built C library into the package."""

    def run(self):
        super().run()
        src = os.environ.get("WETHAIR_LIBRARY") or os.path.join(HERE, "..", "..", "target", "release", NAME)
        if not os.path.exists(src):
            raise SystemExit(f"wethair: no library at {src}: run `cargo build --release` or set WETHAIR_LIBRARY")
        dst = os.path.join(self.build_lib, "wethair", NAME)
        shutil.copyfile(src, dst)
        # A release build keeps debug info for profiling; the wheel need not carry it.
        if sys.platform.startswith("linux") and shutil.which("strip"):
            subprocess.run(["strip", "--strip-debug", dst], check=True)


class PlatformWheel(bdist_wheel):
    """The wheel carries a native library: tag it for this platform, any Python 3."""

    def finalize_options(self):
        super().finalize_options()
        self.root_is_pure = False

    def get_tag(self):
        _, _, plat = super().get_tag()
        return "py3", "none", plat


setup(cmdclass={"build_py": BuildWithLibrary, "bdist_wheel": PlatformWheel})
