"""The dynamic table's drift over frames (dynamic.csv of `treetrace bench
--only D`, columns in the bench's documentation): the updated tree's SAH
cost and trace time over a fresh build's (1.0 = as good as rebuilding),
one line per scene and edit mode, and the update time per frame against
Embree's refit and low-quality rebuild."""

from __future__ import annotations

import math
import os
from typing import Dict, List, Tuple

from . import _style
from ._data import Missing, Row, machine_caption, num, read_csv, why_missing

MODES = ["deform", "edits", "growth"]


def _lines(rows: List[Row], engine: str) -> Dict[Tuple[str, str], List[Row]]:
    out: Dict[Tuple[str, str], List[Row]] = {}
    for r in rows:
        if r.get("engine") == engine:
            out.setdefault((r["scene"], r["mode"]), []).append(r)
    for v in out.values():
        v.sort(key=lambda r: int(r["frame"]))
    return out


@_style.styled
def plot(results_dir: str, machine: Dict[str, str], out_dir: str, formats: List[str],
         missing: Missing) -> List[Tuple[str, List[str]]]:
    rows = read_csv(os.path.join(results_dir, "dynamic.csv"))
    if not rows:
        return []
    ours = _lines(rows, "treetrace")
    stem = "dynamic-drift"
    fig = _style.figure(9.0, 3.6)
    ax_sah, ax_t = fig.subplots(1, 2)
    for i, ((scene, mode), rs) in enumerate(sorted(ours.items(), key=lambda kv: (
            kv[0][0], MODES.index(kv[0][1]) if kv[0][1] in MODES else 9))):
        colour = _style.OKABE_ITO[i % len(_style.OKABE_ITO)]
        for ax, key in ((ax_sah, "sah_ratio"), (ax_t, "trace_ratio")):
            pts = [(int(r["frame"]), num(r, key)) for r in rs if not math.isnan(num(r, key))]
            if not pts:
                missing.add(stem, "%s %s %s" % (scene, mode, key), "every frame",
                            why_missing(rs[0]) if rs[0].get("status", "ok") != "ok"
                            else "no frame has a fresh build to compare with")
                continue
            ax.plot([p[0] for p in pts], [p[1] for p in pts], color=colour,
                    marker=_style.MARKERS[i % len(_style.MARKERS)], markersize=4,
                    linewidth=1.5, label="%s, %s" % (scene, mode))
    for ax, what in ((ax_sah, "SAH cost"), (ax_t, "trace time")):
        ax.axhline(1.0, color="black", linestyle="--", linewidth=1.0, label="fresh build = 1.0")
        ax.set_xlabel("frame (edits applied by tt_accel_update)")
        ax.set_ylabel("%s over a fresh build's" % what)
    h, lab = ax_sah.get_legend_handles_labels()
    fig.tight_layout()
    _style.legend_above(fig, h, lab, "Dynamic scenes: drift of the updated R-tree",
                        ncol=min(4, len(lab)))
    _style.caption(fig, "The default R-tree (compact layout) updated in place frame after "
                   "frame, against a fresh default build of the same frame (every 10th frame "
                   "and the last): SAH cost and primary + shadow trace time ratios; above 1.0 "
                   "the update has drifted. Machine: %s." % machine_caption(machine))
    out = [("Dynamic scenes: drift over frames", _style.save(fig, out_dir, stem, formats))]

    # update time per frame: ours against Embree's refit and rebuilds
    stem = "dynamic-update"
    engines = ["treetrace", "embree-refit", "embree-low", "embree-medium"]
    present = [e for e in engines if any(r.get("engine") == e for r in rows)]
    groups = sorted({(r["scene"], r["mode"]) for r in rows})
    fig = _style.figure(4.2 * min(len(groups), 3), 3.4 * (-(-len(groups) // 3)))
    axes = fig.subplots(-(-len(groups) // 3), min(len(groups), 3), squeeze=False).ravel()
    for ax, (scene, mode) in zip(axes, groups):
        for j, e in enumerate(present):
            rs = _lines(rows, e).get((scene, mode), [])
            pts = [(int(r["frame"]), num(r, "update_ms")) for r in rs
                   if int(r["frame"]) > 0 and not math.isnan(num(r, "update_ms"))]
            if not pts:
                missing.add(stem, e, "%s %s" % (scene, mode),
                            why_missing(rs[0] if rs else None))
                continue
            ax.plot([p[0] for p in pts], [p[1] for p in pts], color=_style.OKABE_ITO[j],
                    marker=_style.MARKERS[j], markersize=3, linewidth=1.3, label=e)
        ax.set_title("%s, %s" % (scene, mode))
        ax.set_xlabel("frame")
        ax.set_ylabel("update time [ms]")
        ax.set_yscale("log")
    for ax in axes[len(groups):]:
        ax.set_visible(False)
    fig.tight_layout()
    h, lab = axes[0].get_legend_handles_labels()
    _style.legend_above(fig, h, lab, "Dynamic scenes: update time per frame",
                        ncol=len(lab) or 1)
    _style.caption(fig, "treetrace: tt_accel_update of the default R-tree; Embree 3 with "
                   "RTC_SCENE_FLAG_DYNAMIC: rtcCommitScene after a refit or at that build "
                   "quality. Frame 0 (the first build) left out. Machine: %s."
                   % machine_caption(machine))
    out.append(("Dynamic scenes: update time per frame", _style.save(fig, out_dir, stem,
                                                                     formats)))
    return out
