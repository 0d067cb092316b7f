#!/usr/bin/env bash
# Installs the build into a fresh prefix (cmake --install), then builds and
# runs a tiny consumer project against that copy: with find_package (the
# shared and the static library), with pkg-config (the shared library,
# nothing but the compiler and the .pc file), and runs the installed CLI.
# Then compiles the README's C batch example against that copy and runs it
# from the source root, and pip-installs the Python package (with Debian's
# pip, no build isolation, nothing downloaded) and imports it against the
# installed library, found through pkg-config.
# Usage: install_and_consume.sh BUILD_DIR WORK_DIR C_COMPILER README [PYTHON]
set -euo pipefail
build="$1"; work="$2"; cc="$3"; readme="$4"; python="${5:-}"
src="$(dirname "$readme")"
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
# (ldd's output taken whole first: `ldd | grep -q` under pipefail fails at
# random when grep exits before ldd has finished writing)
loaded="$(ldd "$work/cmake-build/consumer")"
case "$loaded" in
  *"$libdir/libtreetrace.so.0"*) ;;
  *) echo "consumer does not load $libdir/libtreetrace.so.0:"; echo "$loaded"; exit 1 ;;
esac

echo "== pkg-config treetrace"
export PKG_CONFIG_PATH="$libdir/pkgconfig"
pkg-config --exists treetrace
[ "$(pkg-config --modversion treetrace)" = "$(sed -n 's/^#define TT_VERSION_STRING "\(.*\)"/\1/p' "$prefix/include/treetrace/treetrace.h")" ]
# shellcheck disable=SC2046
"$cc" -std=c11 -o "$work/consumer_pc" "$here/consumer/main.c" $(pkg-config --cflags --libs treetrace) -lm
LD_LIBRARY_PATH="$libdir" "$work/consumer_pc"

echo "== installed CLI"
LD_LIBRARY_PATH="$libdir" "$prefix/bin/treetrace" --version

echo "== README.md's C batch example against the installed copy"
extract="$src/python/tests/readme_examples.py"
python_for_extract="${python:-python3}"
"$python_for_extract" "$extract" "$readme" batch.c > "$work/batch.c"
# shellcheck disable=SC2046
"$cc" -std=c11 -Wall -Wextra -Werror -o "$work/readme_batch" "$work/batch.c" \
  $(pkg-config --cflags --libs treetrace)
(cd "$src" && LD_LIBRARY_PATH="$libdir" "$work/readme_batch")

if [ -n "$python" ]; then
  echo "== pip install --no-build-isolation of python/, imported against the installed library"
  cp -r "$src/python" "$work/python-src"
  rm -rf "$work/python-src/build" "$work/python-src"/*.egg-info
  PIP_ROOT_USER_ACTION=ignore "$python" -m pip install --no-build-isolation --no-deps --no-index --quiet \
    --target "$work/site" "$work/python-src"
  (cd "$work" && env -u TREETRACE_LIBRARY PYTHONPATH="$work/site" "$python" -c "
import treetrace as tt, numpy as np
assert tt.library_path.startswith('$libdir'), tt.library_path
s = tt.Scene.from_arrays(np.array([[0,0,0],[1,0,0],[0,1,0]]), [[0,1,2]])
h = tt.Accel(s, 'rtree').intersect([[0.2,0.2,1]], [0,0,-1])
assert h.prim[0] == 0 and h.t[0] == 1.0
import importlib.util, os
assert os.path.exists(os.path.join(os.path.dirname(tt.__file__), 'py.typed')), 'py.typed not installed'
assert importlib.util.find_spec('treetrace.plots'), 'treetrace.plots not installed'
print('python package from pip, library', tt.library_path)
")
else
  echo "== no Python with numpy given: the pip install check is left out"
fi
echo "install and consumers: ok"
