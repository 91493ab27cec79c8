#!/usr/bin/env bash
# The Python package and the Blender add-on (bindings/python, bindings/blender).
#   bash scripts/python.sh test      # wheel with the built library; pytest of the package, then of the add-on in real Blender
#   bash scripts/python.sh picture   # the README's picture: a dry and a wet bake rendered by Blender's EEVEE (minutes on a CPU)
#   bash scripts/python.sh addon     # dist/wethair-blender-0.1.0.zip: the add-on as a Blender 4.2+ extension, wheel inside
# Needs the release library (cargo build --release); makes target/pyenv, a venv with pinned
# packages: bpy (Blender 4.5 LTS as a Python module, 373 MB), pytest, and NumPy (bpy's).
set -euo pipefail
cd "$(dirname "$0")/.."
what=${1:-test}
venv=target/pyenv
lib=target/release/libwethair.so
[ -f "$lib" ] || cargo build --release --quiet
if [ ! -x "$venv/bin/python" ]; then
    /usr/bin/python3 -m venv "$venv"
    "$venv/bin/pip" install -q --disable-pip-version-check bpy==4.5.4 pytest==9.2.0
fi
# The wheel carries this build's library; installed over any earlier one.
rm -rf target/wheels
WETHAIR_LIBRARY="$PWD/$lib" "$venv/bin/pip" wheel -q --disable-pip-version-check --no-deps -w target/wheels bindings/python
"$venv/bin/pip" install -q --disable-pip-version-check --force-reinstall --no-deps target/wheels/wethair-*.whl
rm -rf bindings/python/build bindings/python/src/*.egg-info
# The add-on as a Blender 4.2+ extension: its files, the manifest and the wheel in one zip.
pack_addon() {
    stage=target/blender-addon
    rm -rf "$stage" && mkdir -p "$stage/wheels" dist
    cp bindings/blender/wethair_blender/*.py bindings/blender/wethair_blender/blender_manifest.toml "$stage/"
    cp target/wheels/wethair-*.whl "$stage/wheels/"
    rm -f dist/wethair-blender-0.1.0.zip
    (cd "$stage" && python3 -m zipfile -c ../../dist/wethair-blender-0.1.0.zip ./*)
    echo "dist/wethair-blender-0.1.0.zip"
}
# Run from outside the source tree, so that tests import the installed package.
case $what in
test)
    pack_addon
    export WETHAIR_ADDON_ZIP=$PWD/dist/wethair-blender-0.1.0.zip
    (cd target && "$PWD/pyenv/bin/python" -m pytest -q -p no:cacheprovider ../bindings/python/tests)
    (cd target && "$PWD/pyenv/bin/python" -m pytest -q -p no:cacheprovider ../bindings/blender/tests)
    ;;
picture)
    (cd target && "$PWD/pyenv/bin/python" ../bindings/blender/tests/picture.py ../docs/blender-wet.png)
    ;;
addon)
    pack_addon
    ;;
*) echo "usage: $0 test|picture|addon" >&2; exit 2 ;;
esac
