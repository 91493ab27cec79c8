"""The ctypes structs and enums equal the C header's."""

import re
import subprocess
import sys

import wethair
from wethair.enums import HEADER_PREFIX


def test_struct_layouts_equal_the_headers(root, tmp_path):
    lines = tmp_path / "python-layout.txt"
    out = subprocess.run([sys.executable, "-m", "wethair.layout"], check=True, capture_output=True, text=True)
    lines.write_text(out.stdout)
    assert out.stdout.count("\nsize ") + 1 >= 18
    # Fails (diff) on any size or offset that differs.
    subprocess.run(["bash", str(root / "bindings/check_layout.sh"), str(lines), str(root / "include")], check=True)


def test_enum_values_equal_the_headers(root):
    header = (root / "include/wethair.h").read_text()
    constants = {m.group(1): int(m.group(2)) for m in re.finditer(r"^\s+(WETHAIR_\w+) = (\d+),$", header, re.M)}
    assert len(constants) > 30
    for kind, prefix in HEADER_PREFIX.items():
        for member in kind:
            name = prefix + member.name
            assert constants.get(name) == member.value, f"{kind.__name__}.{member.name}: header has {constants.get(name)}"
        # and every header constant of that prefix is mirrored (the Result prefix is shared)
        if kind is not wethair.Result:
            mirrored = {prefix + m.name for m in kind}
            assert {n for n in constants if n.startswith(prefix)} <= mirrored


def test_the_package_carries_the_library_it_was_built_with():
    assert wethair.version() == wethair.__version__
    assert wethair.library_path().endswith(("libwethair.so", "libwethair.dylib", "wethair.dll"))
