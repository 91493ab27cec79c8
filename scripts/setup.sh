#!/usr/bin/env bash
# Installs what building and testing wethair needs on a fresh Debian machine (as root), and
# checks the Rust toolchain is there. Safe to run again: it installs only what is missing.
set -euo pipefail
need=()
for tool in cc:gcc c++:g++ make:make valgrind:valgrind pkg-config:pkg-config; do
    command -v "${tool%%:*}" >/dev/null 2>&1 || need+=("${tool##*:}")
done
# AddressSanitizer's runtime for gcc.
ldconfig -p 2>/dev/null | grep -q libasan || need+=(libasan8)
# The Vulkan loader and Mesa's lavapipe (a software Vulkan device) for the GPU backend's tests
# on machines without a GPU.
ldconfig -p 2>/dev/null | grep -q libvulkan.so.1 || need+=(libvulkan1)
[ -e /usr/share/vulkan/icd.d/lvp_icd.x86_64.json ] || need+=(mesa-vulkan-drivers)
# The Vulkan C host: headers and link library, the GLSL compiler for its shaders, and the
# Khronos validation layer it runs under in the tests.
[ -e /usr/include/vulkan/vulkan.h ] || need+=(libvulkan-dev)
command -v glslangValidator >/dev/null 2>&1 || need+=(glslang-tools)
[ -e /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json ] || need+=(vulkan-validationlayers)
# The viewer: GLFW and GL headers, Mesa's software GL, and a virtual X display for its tests.
[ -e /usr/include/GLFW/glfw3.h ] || need+=(libglfw3-dev)
[ -e /usr/include/GL/glcorearb.h ] || need+=(libgl-dev)
[ -e /usr/lib/x86_64-linux-gnu/dri/swrast_dri.so ] || need+=(libgl1-mesa-dri)
command -v xvfb-run >/dev/null 2>&1 || need+=(xvfb)
command -v xauth >/dev/null 2>&1 || need+=(xauth)
# The Python package's and the Blender add-on's tests (scripts/python.sh) run in a venv of
# the system Python (whatever python3 a PATH puts first), which needs ensurepip; pip fills it.
dpkg -s python3-venv >/dev/null 2>&1 || need+=(python3-venv)
# The Unity bindings' C# is built and run with mono in the tests.
command -v mcs >/dev/null 2>&1 || need+=(mono-mcs)
command -v mono >/dev/null 2>&1 || need+=(mono-runtime)
if [ ${#need[@]} -gt 0 ]; then
    if [ "$(id -u)" != 0 ]; then
        echo "setup: missing ${need[*]}; run as root or install them" >&2
        exit 1
    fi
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
command -v cargo >/dev/null || { echo "setup: cargo not found (install Rust 1.80+ with rustup)" >&2; exit 1; }
rustup component list --installed 2>/dev/null | grep -q clippy || rustup component add clippy rustfmt >/dev/null 2>&1 || true
