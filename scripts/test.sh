#!/usr/bin/env bash
# Every test: formatting and lints, the Rust tests (physics, grid, loaders, C ABI, header
# drift), the C hosts built with -Wall -Wextra -Werror (header as C11 and C++17), the smoke
# test, and the C hosts under AddressSanitizer and Valgrind. Builds the library once.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
. scripts/env.sh
step() { printf '\n== %s (at %d s)\n' "$*" "$SECONDS"; }

# One build for everything: the default features plus the Unity plugin entry points.
features=(--features unity)

step "rustfmt and clippy"
cargo fmt --check
cargo clippy --release --all-targets --quiet "${features[@]}" -- -D warnings
# The CPU-only build (no wgpu) still compiles.
cargo check --release --quiet --no-default-features

step "Rust tests"
# The library's unit tests and the one integration-test binary (tests/all.rs), then the doc
# tests. Not the Rust examples: clippy --all-targets above compiles them, and linking each
# one with thin LTO is minutes of CI for nothing the tests use.
cargo test --release "${features[@]}" --lib --tests 2>&1 | tee target/rust-tests.log
cargo test --release "${features[@]}" --doc 2>&1 | tee -a target/rust-tests.log
grep -q "test result: ok" target/rust-tests.log
! grep -q "test result: FAILED" target/rust-tests.log

step "C hosts (-Wall -Wextra -Werror; header as C11 and C++17)"
# The tests' build made the library: this compiles nothing, or the dev-dependencies changed a
# shared crate's features (Cargo.toml: indexmap, bitflags) and wgpu was built twice.
cargo build --release "${features[@]}" 2>&1 | tee target/build.log
! grep -q "Compiling" target/build.log || { echo "cargo build compiled again after cargo test: see Cargo.toml" >&2; exit 1; }
make -C examples/c --quiet all build/unity_fake
./examples/c/build/header_check_c
./examples/c/build/header_check_cpp
./examples/c/build/smoke --backend cpu
./examples/c/build/smoke 60 3000 --backend gpu
./examples/c/build/smoke 10 1000 --backend gpu --lose-device
mkdir -p out
# The strip (2.5 s: dry, soaked, dripping, half dry; the host checks the water ledger) and the
# paper model's pair.
./examples/c/build/render --out out/test-render.png --frames 60 --backend cpu --strip-seconds 2.5 | tee target/render.log
test -s out/test-render.png && test -s out/test-render-paper.png
grep -q "^  half dry" target/render.log
./examples/c/build/render --out out/test-render-gpu.png --frames 60 --backend gpu --strip-seconds 0
test -s out/test-render-gpu-paper.png

step "Linking against the build tree as the README shows (no install): shared with its SONAME link, and static"
ln -sf libwethair.so target/release/libwethair.so.0.1
cc -std=c11 -D_POSIX_C_SOURCE=199309L -Iinclude examples/c/smoke.c -o target/smoke-tree \
    -Ltarget/release -lwethair -Wl,-rpath,"$PWD/target/release" -lm
./target/smoke-tree --backend cpu >/dev/null
cc -std=c11 -D_POSIX_C_SOURCE=199309L -Iinclude examples/c/smoke.c -o target/smoke-tree-static \
    target/release/libwethair.a -lm -ldl -lpthread
./target/smoke-tree-static --backend cpu >/dev/null

step "A host built against the saved 0.1.0 header (tests/abi) works with this library"
cc -std=c11 -Wall -Wextra -Werror -Itests/abi tests/abi/old_host.c -o target/old_host \
    -Ltarget/release -lwethair -Wl,-rpath,"$PWD/target/release" -lm
./target/old_host

step "C++ wrapper (bindings/cpp/wethair.hpp, g++ -std=c++17 -Wall -Wextra -Werror): the paper scene"
./examples/c/build/cpp_paper_scene

step "Packaging: install into a temporary prefix; C programs built with pkg-config alone run"
prefix=$(mktemp -d)
bash scripts/install.sh "$prefix"
readelf -d "$prefix/lib/libwethair.so" | grep -q "SONAME.*\[libwethair.so.0.1\]"
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
# Shared: the program needs libwethair.so.0.1 (the SONAME), found in the prefix.
cc -std=c11 -D_POSIX_C_SOURCE=199309L -Wall -Wextra -Werror examples/c/smoke.c -o target/smoke-pkgconfig \
    $(pkg-config --cflags --libs wethair) -lm
readelf -d target/smoke-pkgconfig | grep -q "NEEDED.*\[libwethair.so.0.1\]"
LD_LIBRARY_PATH="$prefix/lib" ./target/smoke-pkgconfig --backend cpu
# Static: the archive plus what pkg-config --static lists; nothing of wethair loaded at run time.
cc -std=c11 -D_POSIX_C_SOURCE=199309L examples/c/smoke.c -o target/smoke-static $(pkg-config --cflags wethair) \
    "$prefix/lib/libwethair.a" $(pkg-config --static --libs-only-l wethair | sed 's/-lwethair//')
! ldd target/smoke-static | grep -q wethair
./target/smoke-static --backend cpu
unset PKG_CONFIG_PATH
rm -rf "$prefix"

step "Unity plugin: Unity played by a C host on lavapipe, under validation"
# Its instance and device are created through the plugin's interception asking for nothing:
# the plugin adds what wethair needs and simulations run on that device; with a 1.2 feature
# struct that lacks timelineSemaphore, it says so and simulations use their own device.
./examples/c/build/unity_fake --validate
./examples/c/build/unity_fake --validate --aggregate

step "Unity C# bindings with mono: a console program drives the library; struct layouts equal the header's"
mkdir -p target/cs
mcs -unsafe -nologo -warnaserror -out:target/cs/drive.exe bindings/unity/Runtime/*.cs 'bindings/unity/Tests~/Drive.cs'
LD_LIBRARY_PATH=target/release mono target/cs/drive.exe
LD_LIBRARY_PATH=target/release mono target/cs/drive.exe --layout >target/cs/layout.txt
bash 'bindings/check_layout.sh' target/cs/layout.txt include

step "Viewer, Vulkan renderer, under xvfb on lavapipe with validation: drawn from the shared VkBuffer"
make -C examples/c --quiet build/viewer
# A strand count that is not a whole number in range is refused by name (exit 2).
for bad in 5k 0 -3; do
    rc=0; ./examples/c/build/viewer --strands "$bad" 2>target/viewer-bad.log || rc=$?
    test "$rc" = 2
    grep -q "^viewer: --strands wants a strand count from 1 to 1000000$" target/viewer-bad.log
done
# Half the paper scene's strands: the session on lavapipe in 40 s instead of 108, and the spray
# still clumps them (clumping 0.853 of dry, 0.872 with all 10,000; measured 2026-12-03).
xvfb-run -a -s "-screen 0 1280x720x24" ./examples/c/build/viewer --renderer vulkan --backend gpu --validate \
    --strands 5000 --script examples/c/viewer_vulkan.script --size 640x360 | tee target/viewer-vk.log | grep -v "^wethair |"
# The GPU simulation ran on the viewer's device and was drawn from its VkBuffer; after the
# switch to the CPU backend the same renderer drew from the copy path; 0 validation errors
# (the run fails on any, the paused frame's semaphores included).
grep -q "strands drawn with Vulkan from the shared VkBuffer" target/viewer-vk.log
grep -q "strands drawn with Vulkan from the copy path" target/viewer-vk.log
grep -q "validation: 0 errors" target/viewer-vk.log
./examples/c/build/image_check out/viewer-vk-dry.ppm out/viewer-vk-wet.ppm
./examples/c/build/image_check out/viewer-vk-wet.ppm out/viewer-vk-copy.ppm
# After the window's resize the frame has the new size.
test "$(head -c 15 out/viewer-vk-resized.ppm | tr '\n' ' ')" = "P6 480 270 255 "
clumping_dropped() {
    dry=$(sed -n "s/.*$2: clumping \([0-9.]*\) m.*/\1/p" "$1")
    wet=$(sed -n "s/.*$3: clumping \([0-9.]*\) m.*/\1/p" "$1")
    awk -v d="$dry" -v w="$wet" 'BEGIN { printf "viewer clumping: dry %s m, wet %s m\n", d, w; exit !(d > 0 && w > 0 && w < 0.9 * d) }'
}
clumping_dropped target/viewer-vk.log viewer-vk-dry.ppm viewer-vk-wet.ppm
# 4x MSAA resolved into the swapchain image, under validation.
xvfb-run -a -s "-screen 0 1280x720x24" ./examples/c/build/viewer --renderer vulkan --validate --msaa 4 \
    --screenshot out/viewer-vk-msaa.png --frames 20 --size 320x180 | grep "validation: 0 errors"
test -s out/viewer-vk-msaa.png

step "Viewer, OpenGL 3.3 renderer, under xvfb on llvmpipe: the scripted session; the fallback"
xvfb-run -a -s "-screen 0 1280x720x24" ./examples/c/build/viewer --renderer gl --script examples/c/viewer_test.script \
    --size 640x360 | tee target/viewer.log | grep -v "^wethair |"
# The frames show hair, the wet one differs from the dry one where the hair is, and the
# clumping measure dropped.
./examples/c/build/image_check out/viewer-dry.ppm out/viewer-wet.ppm
clumping_dropped target/viewer.log viewer-dry.ppm viewer-wet.ppm
# The wet model's toggles (soak, rain, wind): the soaked frame differs from the dry one, and
# the ledger printed with every stats line balances to the quantum.
xvfb-run -a -s "-screen 0 1280x720x24" ./examples/c/build/viewer --renderer gl --wet-model \
    --script examples/c/viewer_wet.script --size 480x270 | tee target/viewer-wet.log | grep "^water:"
./examples/c/build/image_check out/viewer-wet-model-dry.ppm out/viewer-wet-model.ppm
awk '/^water:/ {n++; if ($3 != $6 + $9 + $12 + $15) bad++} END {exit !(n > 0 && bad == 0)}' target/viewer-wet.log
# Skinned roots: the host sets every root's frame each frame (a ripple over the scalp).
xvfb-run -a -s "-screen 0 1280x720x24" ./examples/c/build/viewer --renderer gl --backend cpu --skinned-roots \
    --screenshot out/viewer-skinned.png --frames 30 --size 320x180 | grep -v "^wethair |"
test -s out/viewer-skinned.png
# Fixed steps of 1/144 s over 1/60 s frames: 2.4 steps a frame, so the frames take 2 or 3 and
# the vertices show a blend between the last two (its value is printed each second).
xvfb-run -a -s "-screen 0 1280x720x24" ./examples/c/build/viewer --renderer gl --backend cpu --fixed-step 144 \
    --screenshot out/viewer-fixed.png --frames 30 --size 320x180 | tee target/viewer-fixed.log | grep -v "^wethair |"
grep -Eq "^fixed step 1/144 s: last frame [23] steps" target/viewer-fixed.log
test -s out/viewer-fixed.png
# With no Vulkan driver the default renderer says why and falls back to OpenGL; the
# screenshot mode writes a PNG.
VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json xvfb-run -a -s "-screen 0 1280x720x24" \
    ./examples/c/build/viewer --screenshot out/viewer-shot.png --frames 20 --size 320x180 --backend cpu \
    | tee target/viewer-fallback.log | grep -v "^wethair |"
grep -q "Vulkan renderer unavailable" target/viewer-fallback.log
grep -q "drawing with OpenGL" target/viewer-fallback.log
test -s out/viewer-shot.png

step "Render-side shaders for engines: HLSL through glslang's HLSL front end (GLSL is built above, WGSL in the Rust tests)"
glslangValidator -D -V --quiet -e VSMain -S vert bindings/shaders/kajiya_kay.hlsl -o target/kk_hlsl_vs.spv
glslangValidator -D -V --quiet -e PSMain -S frag bindings/shaders/kajiya_kay.hlsl -o target/kk_hlsl_ps.spv

step "Vulkan host: wethair on the host's VkDevice, drawn from the shared VkBuffer, under validation"
# Fails on any validation error (bar Debian's known false InconsistentSpirv report), on a
# shared buffer that differs from the copy path's bytes, on a refusal that is not refused, and
# on an image without hair.
./examples/c/build/vulkan_host --validate --compare --check-errors --frames 30 --out out/test-vulkan.png
test -s out/test-vulkan.png
# Fixed steps at 50 Hz, the last frame without a step: the buffer handed out shows the new
# blend, equal to the copy path's.
./examples/c/build/vulkan_host --validate --compare --fixed-step --frames 12 --out out/test-vulkan-fixed.png

step "C hosts under AddressSanitizer + UBSan (leaks fail the run)"
make -C examples/c --quiet BUILD=build-asan CFLAGS="-O1 -g -fno-omit-frame-pointer" SAN="-fsanitize=address,undefined -fno-sanitize-recover=all"
# The CPU backend: Mesa's lavapipe allocates for the process's lifetime, which LeakSanitizer
# would report against the GPU runs.
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 ./examples/c/build-asan/smoke 120 4000 --backend cpu
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 ./examples/c/build-asan/render --out out/asan-render.png --frames 30 --backend cpu --strip-seconds 1.6
ASAN_OPTIONS=detect_leaks=1 ./examples/c/build-asan/header_check_c
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 ./examples/c/build-asan/cpp_paper_scene
# The Vulkan host on lavapipe: lavapipe is preloaded so that the loader's dlclose keeps its
# frames named, and lsan.supp drops only the driver's, loader's and LLVM's own allocations.
LD_PRELOAD="$(gcc -print-file-name=libasan.so) /usr/lib/x86_64-linux-gnu/libvulkan_lvp.so" \
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 LSAN_OPTIONS=suppressions=$PWD/examples/c/lsan.supp:print_suppressions=0 \
    ./examples/c/build-asan/vulkan_host --compare --check-errors --frames 10 --out out/asan-vulkan.png
# The viewer, the same way: each renderer with its Mesa driver preloaded inside the virtual
# display's session (OpenGL on the CPU backend, Vulkan on the GPU backend's shared buffer).
make -C examples/c --quiet BUILD=build-asan CFLAGS="-O1 -g -fno-omit-frame-pointer" SAN="-fsanitize=address,undefined -fno-sanitize-recover=all" build-asan/viewer
for renderer in gl vulkan; do
    driver=/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so
    [ "$renderer" = vulkan ] && driver=/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so
    rm -f out/viewer-asan.ppm
    xvfb-run -a -s "-screen 0 1280x720x24" sh -c "LD_PRELOAD='$(gcc -print-file-name=libasan.so) $driver' \
        ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 LSAN_OPTIONS=suppressions=$PWD/examples/c/lsan.supp:print_suppressions=0 \
        ./examples/c/build-asan/viewer --renderer $renderer --script examples/c/viewer_asan.script --size 480x270 --strands 5000 \
        --backend $([ "$renderer" = vulkan ] && echo gpu || echo cpu)" | grep -v "^wethair |"
    test -s out/viewer-asan.ppm
done

step "C smoke under Valgrind (memcheck; definite leaks and errors fail)"
valgrind --quiet --error-exitcode=99 --leak-check=full --show-leak-kinds=definite --errors-for-leak-kinds=definite \
    ./examples/c/build/smoke 60 1000 --backend cpu

step "Python package and Blender add-on: the wheel with this library, pytest; the add-on inside real Blender (bpy 4.5 LTS)"
bash scripts/python.sh test 2>&1 | tee target/python-tests.log
grep -q "passed" target/python-tests.log
! grep -Eq "[0-9]+ (failed|error)" target/python-tests.log

step "Peer bench harness: NumPy and wethair (through its Python package) agree on the tiny scene"
target/pyenv/bin/python benches/peers/bench.py --scenes tiny --engines numpy,wethair --threads 2 --reps 1 \
    --max-disagreement 1e-6 --out target/peers-smoke

step "The main job prints only its own lines (no Mesa warning without XDG_RUNTIME_DIR); it reuses this build of the library"
built=$(stat -c %.9Y target/release/libwethair.so)
env -u XDG_RUNTIME_DIR bash scripts/main.sh --frames 10 --strip-seconds 2 --out out/test-main.png 2>&1 | tee target/main.log
test "$(stat -c %.9Y target/release/libwethair.so)" = "$built" || { echo "scripts/main.sh rebuilt the library: its cargo build must use the features above" >&2; exit 1; }
! grep -qi "error\|warning" target/main.log
grep -q "^timing (paper model): dry" target/main.log
grep -q "^wet model .* ms/frame" target/main.log

rust=$(cat target/rust-tests.log target/python-tests.log | grep -o "[0-9]* passed" | awk '{s+=$1} END {print s}')
c_checks=39  # viewer --strands refusal, peer bench harness, build-tree links shared and static, 0.1.0 host, main job output, header C11 and C++17, smoke cpu+gpu+device loss, render cpu+gpu, C++ wrapper, install + pkg-config shared and static, Unity fake x2, C# drive + layout, viewer Vulkan session + copy frame + MSAA, viewer GL session + fallback + wet model + skinned roots, HLSL, Vulkan host, 7 under ASan, valgrind, fmt+clippy
printf "\nwethair tests: %d passed, 0 failed (%d s)\n" "$((rust + c_checks))" "$SECONDS"
