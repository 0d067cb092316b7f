#!/usr/bin/env bash
# 1 rank against 2 MPI ranks of 1 thread each, on the shared views, with
# both tile splits. Reported per run: the trace pass's CPU seconds per rank
# (min of REPEAT; CPU time, so other load on a shared machine does not
# inflate it), and from them the efficiency T1 / (2 max(T2 rank)) that two
# ranks on two free cores would reach (the balance of the split and every
# per-rank overhead are in it); and the wall-clock efficiency as measured
# (meaningful on a quiet machine only). Prints a Markdown table.
# Usage: tools/mpi_scaling.sh [BUILD_DIR] [SIZE] [REPEAT]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
size="${2:-512x512}"
repeat="${3:-5}"
tt="$build/treetrace"
scenes="${TT_SCENES_DIR:-../shared/scenes}"
run() { mpirun -np "$1" --oversubscribe --allow-run-as-root "$tt" render "${@:2}"; }
key() { sed -n "s/^$1: //p"; }
echo "| view | 1 rank CPU s | queue: rank CPU s | queue eff. | interleave: rank CPU s | interleave eff. | wall eff. queue / interleave |"
echo "|---|---:|---|---:|---|---:|---:|"
for pair in bun_zipper.ply:bunny:main bun_zipper.ply:bunny:side sibenik.obj:sibenik:main \
            sibenik.obj:sibenik:back conference.ply:conference:main \
            conference.ply:conference:corner; do
  file="${pair%%:*}"
  view="${pair#*:}"
  args=("$scenes/$file" --view "$view" --size "$size" --threads 1 --repeat "$repeat")
  one=$(run 1 "${args[@]}" --mpi-split queue)
  c1=$(echo "$one" | key rank_0_cpu_s)
  w1=$(echo "$one" | key trace_s)
  row="| $view | $(printf '%.4f' "$c1")"
  walls=""
  for split in queue interleave; do
    out=$(run 2 "${args[@]}" --mpi-split "$split")
    x=$(echo "$out" | key rank_0_cpu_s)
    y=$(echo "$out" | key rank_1_cpu_s)
    w2=$(echo "$out" | key trace_s)
    row+=$(awk -v c="$c1" -v x="$x" -v y="$y" 'BEGIN {
      m = x > y ? x : y; printf " | %.4f, %.4f | %.2f", x, y, c / (2 * m) }')
    walls+=$(awk -v a="$w1" -v b="$w2" 'BEGIN { printf "%.2f", a / (2 * b) }')" / "
  done
  echo "$row | ${walls% / } |"
done
