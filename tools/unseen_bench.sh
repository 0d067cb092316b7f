#!/usr/bin/env bash
# raybench (../shared/bench) on the scenes the project was never tuned on
# (tools/unseen_scenes.py: atrium, field, terrain; two views each), so a
# speed lever is judged on more than the shared four (issue 17).
# usage: tools/unseen_bench.sh [BUILD_DIR] [raybench options...]
#   e.g. tools/unseen_bench.sh build --accel rtree --accel kdtree --embree p16
# Generates the scenes into BUILD_DIR/unseen once (Debian's python3-numpy,
# scripts/python-deps.sh) and builds raybench into BUILD_DIR/yardsticks.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/${1:-build}"
[ $# -gt 0 ] && shift
scenes="$build/unseen"
if [ ! -r "$scenes/views.tsv" ]; then
  /usr/bin/python3 "$root/tools/unseen_scenes.py" "$scenes"
fi
if [ ! -x "$build/yardsticks/raybench" ]; then
  make -s -C "$root/../shared/bench" TT="$root" OUT="$build/yardsticks" >&2
fi
tail -n +2 "$scenes/views.tsv" | while IFS=$'\t' read -r scene view _; do
  echo "== $scene:$view"
  "$build/yardsticks/raybench" "$scenes/$scene.ply" "$scenes/views.tsv" "$scene:$view" \
    --threads 2 "$@"
done
