#!/usr/bin/env bash
# The peer comparison: wethair and three other engines on the same scene (benches/peers/README.md).
#   bash benches/peers/run.sh            # needs target/peers-venv (SETUP=1 makes it) and a release build
#   SETUP=1 bash benches/peers/run.sh    # creates the venv with pinned packages first (~600 MB)
#   ARGS="--scenes paper --reps 5" bash benches/peers/run.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
venv=$root/target/peers-venv
if [ "${SETUP:-0}" = 1 ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q --upgrade pip
    "$venv/bin/pip" install -q numpy==2.4.6 warp-lang==1.19.0 taichi==1.7.4
fi
[ -x "$venv/bin/python" ] || { echo "no $venv: run with SETUP=1 first" >&2; exit 1; }
(cd "$root" && cargo build --release --quiet)
# wethair runs through its Python package, rebuilt from this build's library.
"$venv/bin/pip" install -q --force-reinstall --no-deps "$root/bindings/python"
# shellcheck disable=SC2086
"$venv/bin/python" "$root/benches/peers/bench.py" --out "$root/target/peers" ${ARGS:-}
