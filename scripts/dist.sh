#!/usr/bin/env bash
# Builds the release library and lays out dist/wethair-VERSION-OS-ARCH/ for plugin builds to
# pick up (the Unreal plugin's Build.cs and the Unity package look there): include/, lib/
# (shared with SONAME, static, pkg-config), share/wethair/shaders/. Same layout as install.sh.
# Built with the Unity plugin entry points (cargo feature `unity`): Unity needs them, other
# hosts never call them.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --features unity
version=$(grep -m1 '^version' Cargo.toml | sed 's/.*"\(.*\)"/\1/')
os=$(uname -s | tr '[:upper:]' '[:lower:]')
out="dist/wethair-$version-$os-$(uname -m)"
rm -rf "$out"
bash scripts/install.sh "$out" >/dev/null
echo "$out"
