"""The packed extension (scripts/python.sh addon: the add-on, its manifest and the wheel in one
zip) installs into a fresh Blender user folder and registers its operators, as an artist's
*Install from Disk* would. In a child process: an installed extension stays registered."""

import os
import subprocess
import sys

SCRIPT = r"""
import os, sys
import bpy
r = bpy.ops.extensions.package_install_files(filepath=sys.argv[-1], repo="user_default", enable_on_install=True)
import addon_utils
names = [m.__name__ for m in addon_utils.modules()]
print("RESULT", sorted(r), "bl_ext.user_default.wethair" in names, hasattr(bpy.types, "WETHAIR_OT_bake"),
      "bake" in dir(bpy.ops.wethair))
sys.stdout.flush()
os._exit(0)
"""


def test_the_extension_zip_installs_and_registers(tmp_path):
    zipf = os.environ.get("WETHAIR_ADDON_ZIP")
    assert zipf and os.path.exists(zipf), "pack the add-on first: bash scripts/python.sh addon"
    env = dict(os.environ, HOME=str(tmp_path), BLENDER_USER_RESOURCES=str(tmp_path / "blender"))
    out = subprocess.run(
        [sys.executable, "-c", SCRIPT, zipf], env=env, capture_output=True, text=True, timeout=300, cwd=tmp_path
    )
    line = [ln for ln in out.stdout.splitlines() if ln.startswith("RESULT")]
    assert line, out.stdout + out.stderr
    assert line[0] == "RESULT ['FINISHED'] True True True", line[0]
    # Installed into the fresh user folder: the add-on and the wheel's package beside it.
    assert list(tmp_path.rglob("extensions/user_default/wethair/blender_manifest.toml"))
    assert list(tmp_path.rglob("wethair/libwethair.so"))
