#!/usr/bin/env bash
# Installs the build into a fresh prefix (cmake --install), then builds and
# runs a tiny consumer project against that copy: with find_package (the
# shared and the static library), with pkg-config (the shared library,
# nothing but the compiler and the .pc file), and runs the installed CLI.
# Usage: install_and_consume.sh BUILD_DIR WORK_DIR C_COMPILER
set -euo pipefail
build="$1"; work="$2"; cc="$3"
here="$(cd "$(dirname "$0")" && pwd)"
rm -rf "$work"; mkdir -p "$work"
prefix="$work/prefix"

echo "== cmake --install $build --prefix $prefix"
cmake --install "$build" --prefix "$prefix" > "$work/install.log"
for f in include/treetrace/treetrace.h bin/treetrace; do
  test -e "$prefix/$f" || { echo "missing $prefix/$f"; exit 1; }
done
libdir="$(dirname "$(find "$prefix" -name 'libtreetrace.so.0' | head -1)")"
test -n "$libdir" || { echo "no libtreetrace.so.0 installed"; exit 1; }
for f in libtreetrace.so libtreetrace.a pkgconfig/treetrace.pc cmake/treetrace/treetrace-config.cmake; do
  test -e "$libdir/$f" || { echo "missing $libdir/$f"; exit 1; }
done
soname="$(readelf -d "$libdir/libtreetrace.so" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')"
[ "$soname" = "libtreetrace.so.0" ] || { echo "soname '$soname', expected libtreetrace.so.0"; exit 1; }

echo "== find_package(treetrace)"
cmake -S "$here/consumer" -B "$work/cmake-build" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_C_COMPILER="$cc" > "$work/configure.log"
cmake --build "$work/cmake-build" > "$work/build.log"
"$work/cmake-build/consumer"
"$work/cmake-build/consumer_static"
# the shared consumer really uses the installed shared library
ldd "$work/cmake-build/consumer" | grep -q "$libdir/libtreetrace.so.0" || {
  echo "consumer does not load $libdir/libtreetrace.so.0:"; ldd "$work/cmake-build/consumer"; exit 1; }

echo "== pkg-config treetrace"
export PKG_CONFIG_PATH="$libdir/pkgconfig"
pkg-config --exists treetrace
[ "$(pkg-config --modversion treetrace)" = "$(sed -n 's/^#define TT_VERSION_STRING "\(.*\)"/\1/p' "$prefix/include/treetrace/treetrace.h")" ]
# shellcheck disable=SC2046
"$cc" -std=c11 -o "$work/consumer_pc" "$here/consumer/main.c" $(pkg-config --cflags --libs treetrace) -lm
LD_LIBRARY_PATH="$libdir" "$work/consumer_pc"

echo "== installed CLI"
LD_LIBRARY_PATH="$libdir" "$prefix/bin/treetrace" --version
echo "install and consumers: ok"
