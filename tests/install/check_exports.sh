#!/usr/bin/env bash
# The shared library exports exactly the functions the public header
# declares: every tt_ name declared in treetrace.h, nothing else.
# Usage: check_exports.sh LIBRARY HEADER
set -euo pipefail
lib="$1"; header="$2"
exported="$(nm -D --defined-only "$lib" | awk '{print $3}' | sed 's/@.*//' | sort -u)"
declared="$(grep -oE '\btt_[a-z0-9_]+[[:space:]]*\(' "$header" | sed 's/[[:space:]]*($//' | sort -u)"
# names followed by '(' that are not functions: the callback typedefs
declared="$(comm -23 <(echo "$declared") <(grep -oE '\(\*tt_[a-z0-9_]+\)' "$header" | tr -d '(*)' | sort -u))"
extra="$(comm -23 <(echo "$exported") <(echo "$declared"))"
missing="$(comm -13 <(echo "$exported") <(echo "$declared"))"
status=0
[ -z "$extra" ] || { echo "exported but not in the public header:"; echo "$extra"; status=1; }
[ -z "$missing" ] || { echo "declared but not exported:"; echo "$missing"; status=1; }
echo "$(echo "$exported" | wc -l) symbols exported"
exit $status
