#!/usr/bin/env bash
# Load against build, on every shared scene: the time `treetrace build`
# takes to build each structure (build_s) and the time `info --accel-file`
# takes to map, verify and validate the saved file (accel_load_s), min of
# ROUNDS interleaved rounds, as a Markdown table (docs/mpi.md and the note
# quote it). Usage: tools/accel_file_bench.sh [BUILD_DIR] [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
rounds="${2:-3}"
tt="$build/treetrace"
scenes="${TT_SCENES_DIR:-../shared/scenes}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
key() { sed -n "s/^$1: //p"; }
min() { sort -g | head -1; }
echo "| scene | structure | triangles | file MB | build s | load s | build / load |"
echo "|---|---|---:|---:|---:|---:|---:|"
configs=("rtree" "rtree --layout complete --build insert" "kdtree")
tail -n +2 "$scenes/scenes.tsv" | while IFS=$'\t' read -r name file tris _rest; do
  for cfg in "${configs[@]}"; do
    # shellcheck disable=SC2086
    [ "$cfg" = "rtree --layout complete --build insert" ] && [ "$tris" -gt 100000 ] && continue
    b=(); l=()
    for ((i = 0; i < rounds; i++)); do
      # shellcheck disable=SC2086
      out=$("$tt" build "$scenes/$file" -o "$work/s.tta" --accel $cfg)
      b+=("$(echo "$out" | key build_s)")
      bytes=$(echo "$out" | key file_bytes)
      l+=("$("$tt" info "$scenes/$file" --accel-file "$work/s.tta" | key accel_load_s)")
    done
    bs=$(printf '%s\n' "${b[@]}" | min)
    ls=$(printf '%s\n' "${l[@]}" | min)
    awk -v n="$name" -v c="$cfg" -v t="$tris" -v by="$bytes" -v b="$bs" -v l="$ls" 'BEGIN {
      printf "| %s | %s | %d | %.1f | %.4f | %.5f | %.0fx |\n", n, c, t, by / 1e6, b, l, b / l }'
  done
done
