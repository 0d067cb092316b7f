#!/bin/bash
# A/B timing of several treetrace configurations on the shared views, for a
# machine shared with other jobs: the configurations alternate inside every
# round (so a load change hits them all alike) and the best of the rounds is
# kept per view and configuration; ratios are to the first configuration.
#
#   tools/bench_views.sh ROUNDS 'LABEL|BINARY|EXTRA ARGS' ...
#   e.g. tools/bench_views.sh 3 'rt|build/treetrace|' \
#            'em|build/treetrace|--accel embree --embree-quality medium'
#
# Environment: VIEWS (default: the seven views below), SIZE (1024x1024),
# THREADS (2), REPEAT (5), SCENES (../shared/scenes). On a loaded machine
# THREADS=1 gave far steadier A/B numbers than 2 threads.
set -u
SCENES=${SCENES:-../shared/scenes}
VIEWS=${VIEWS:-"bunny:main bunny:side cornell:main sibenik:main sibenik:back conference:main conference:corner"}
scene_file() {
    case $1 in
    bunny) echo bun_zipper.ply ;; bunny_res4) echo bun_zipper_res4.ply ;;
    cornell) echo cornell_box.obj ;; sibenik) echo sibenik.obj ;;
    conference) echo conference.ply ;; *) echo "$1.obj" ;;
    esac
}
field() { # the number after "KEY": in a JSON text
    sed -n "s/.*\"$1\": *\([-0-9.eE+]*\).*/\1/p" | head -n 1
}
rounds=$1
shift
for r in $(seq "$rounds"); do
    for v in $VIEWS; do
        f=$SCENES/$(scene_file "${v%%:*}")
        for cfg in "$@"; do
            lab=${cfg%%|*} rest=${cfg#*|}
            bin=${rest%%|*} extra=${rest#*|}
            # shellcheck disable=SC2086 # extra holds several arguments
            j=$("$bin" render "$f" --view "$v" $extra --size "${SIZE:-1024x1024}" \
                --threads "${THREADS:-2}" --repeat "${REPEAT:-5}" --json 2>/dev/null)
            echo "$v $lab $(echo "$j" | field primary_mrays_per_s) $(echo "$j" | field shadow_mrays_per_s)" \
                "$(echo "$j" | field build_s) $(echo "$j" | field accel_bytes)"
        done
    done
done | awk '
    { k = $1 SUBSEP $2; if (!($2 in seen)) { seen[$2] = 1; labs[++nl] = $2 }
      if (!($1 in vseen)) { vseen[$1] = 1; views[++nv] = $1 }
      if ($3 > p[k]) p[k] = $3; if ($4 > s[k]) s[k] = $4
      if (!(k in b) || $5 < b[k]) b[k] = $5; mem[k] = $6 }
    END {
      print "view label primary shadow (ratio to " labs[1] ") build_s bytes"
      for (i = 1; i <= nv; i++) for (j = 1; j <= nl; j++) {
        k = views[i] SUBSEP labs[j]; k0 = views[i] SUBSEP labs[1]
        printf "%s %s %.2f %.2f (%.2f %.2f) %.3f %d\n", views[i], labs[j], p[k], s[k],
               (p[k0] > 0 ? p[k] / p[k0] : 0), (s[k0] > 0 ? s[k] / s[k0] : 0), b[k], mem[k]
      }
    }'
