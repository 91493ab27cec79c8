#!/usr/bin/env bash
# The main job: build the library and the C renderer, run the paper scene dry and wet, and
# write out/wethair.png (dry left, wet right) plus a ms/frame line.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
. scripts/env.sh
# The same build as the tests' (with the Unity plugin's entry points, which nothing calls
# here): after scripts/test.sh this is a no-op rather than a second build of the library.
cargo build --release --quiet --features unity
make -C examples/c --quiet build/render
mkdir -p out
./examples/c/build/render --out out/wethair.png "$@"
