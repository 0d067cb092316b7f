#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan + coverage) in their own
# build folder and runs each for a bounded time, one after the other (the
# machine's cores are shared). Exits non-zero on any finding: a crash, a
# sanitizer report, a leak, a broken invariant (fuzz_common.h), a timeout or
# an out-of-memory. The crashing input is left in $FUZZ_DIR/artifacts; keep it
# as tests/fuzz/regressions/<target>-<what>.<ext> once the bug is fixed.
#
# Environment: FUZZ_SECONDS (per target, default 60), FUZZ_TARGETS (default
# "obj ply views accel"), FUZZ_BUILD_DIR (default build-fuzz), CC (default clang).
set -euo pipefail
cd "$(dirname "$0")/../.."

seconds="${FUZZ_SECONDS:-60}"
targets="${FUZZ_TARGETS:-obj ply views accel}"
build_dir="${FUZZ_BUILD_DIR:-build-fuzz}"
cc="${CC:-clang}"
case "$("$cc" --version 2>/dev/null | head -1)" in
  *clang*) ;;
  *) echo "run-fuzzers: $cc is not clang; libFuzzer needs clang" >&2; exit 1 ;;
esac

CC="$cc" cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTT_FUZZ=ON \
  -DTT_SANITIZE=ON -DTT_WITH_EMBREE=OFF -DTT_WITH_CUDA=OFF >/dev/null
# shellcheck disable=SC2086
cmake --build "$build_dir" -j2 --target $(printf 'fuzz_%s ' $targets) >/dev/null

work="$build_dir/fuzz-work"
mkdir -p "$work/artifacts"
failed=()
for t in $targets; do
  case "$t" in
    views) max_len=4096 ;;
    accel) max_len=65536 ;;
    *) max_len=16384 ;;
  esac
  # A scratch corpus seeded from the committed one: what the run discovers
  # stays out of the repository (merge interesting finds by hand, small).
  mkdir -p "$work/corpus-$t" "tests/fuzz/corpus/$t"
  # the loader's seeds are written by the target itself, in the current
  # format (fuzz_accel.c), rather than committed as binaries that go stale
  if [ "$t" = accel ]; then
    FUZZ_ACCEL_SEEDS="$work/corpus-$t" ASAN_OPTIONS=detect_leaks=0 "$build_dir/tests/fuzz_$t" >/dev/null 2>&1
  fi
  echo "== fuzz_$t for ${seconds}s"
  if ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1" \
     UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
     "$build_dir/tests/fuzz_$t" "$work/corpus-$t" "tests/fuzz/corpus/$t" \
       $( [ -f "tests/fuzz/$t.dict" ] && echo "-dict=tests/fuzz/$t.dict" ) -max_total_time="$seconds" -max_len="$max_len" \
       -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=10 -print_final_stats=1 \
       -artifact_prefix="$work/artifacts/$t-" >"$work/$t.log" 2>&1; then
    grep -E "^(stat::number_of_executed_units|Done)" "$work/$t.log" || true
  else
    echo "run-fuzzers: fuzz_$t FOUND A PROBLEM; the log tail (full log: $work/$t.log):" >&2
    tail -n 40 "$work/$t.log" >&2
    ls -l "$work/artifacts" >&2 || true
    failed+=("$t")
  fi
done
if [ "${#failed[@]}" -gt 0 ]; then
  echo "run-fuzzers: findings in: ${failed[*]}" >&2
  exit 1
fi
echo "run-fuzzers: no findings"
