#!/usr/bin/env bash
# Installs wethair into PREFIX in cargo-c's layout (build first: cargo build --release):
#   PREFIX/include/wethair/wethair.h, wethair.hpp      the C header and the C++ wrapper
#   PREFIX/lib/libwethair.so.0.1.0 (+ .so.0.1, .so)    the shared library, SONAME libwethair.so.0.1
#   PREFIX/lib/libwethair.a                            the static library
#   PREFIX/lib/pkgconfig/wethair.pc                    pkg-config --cflags --libs [--static] wethair
#   PREFIX/share/wethair/shaders/                      the render-side Kajiya-Kay shaders
# usage: scripts/install.sh PREFIX     (LIBDIR=lib64 to change the library folder's name)
set -euo pipefail
cd "$(dirname "$0")/.."
prefix=${1:?usage: scripts/install.sh PREFIX}
mkdir -p "$prefix"
prefix=$(cd "$prefix" && pwd)
libdir=${LIBDIR:-lib}
version=$(grep -m1 '^version' Cargo.toml | sed 's/.*"\(.*\)"/\1/')
IFS=. read -r major minor _ <<<"$version"
if [ "$major" = 0 ]; then soversion="0.$minor"; else soversion="$major"; fi
target=target/release
for f in libwethair.so libwethair.a; do
    [ -e "$target/$f" ] || { echo "install: $target/$f missing; run cargo build --release" >&2; exit 1; }
done
install -d "$prefix/include/wethair" "$prefix/$libdir/pkgconfig" "$prefix/share/wethair/shaders"
install -m 644 include/wethair.h bindings/cpp/wethair.hpp "$prefix/include/wethair/"
install -m 755 "$target/libwethair.so" "$prefix/$libdir/libwethair.so.$version"
ln -sf "libwethair.so.$version" "$prefix/$libdir/libwethair.so.$soversion"
ln -sf "libwethair.so.$soversion" "$prefix/$libdir/libwethair.so"
install -m 644 "$target/libwethair.a" "$prefix/$libdir/libwethair.a"
install -m 644 bindings/shaders/* "$prefix/share/wethair/shaders/"
# What a static link needs besides the archive (Rust's std on Linux).
cat >"$prefix/$libdir/pkgconfig/wethair.pc" <<PC
prefix=$prefix
exec_prefix=\${prefix}
libdir=\${exec_prefix}/$libdir
includedir=\${prefix}/include

Name: wethair
Description: Real-time wet hair: mass-spring strands clumped by water particles, behind a C ABI
Version: $version
Libs: -L\${libdir} -lwethair
Libs.private: -lpthread -ldl -lm -lgcc_s -lc
Cflags: -I\${includedir}/wethair
PC
echo "installed wethair $version into $prefix"
