"""Havran & Bittner's Figure 3 for every view: interior nodes per ray and
time per frame against d_min, with all four kd-tree traversals (BTR and
SLTR on trees with sparse boxes every d_min levels; HTR and SEQ on a tree
without boxes, so constant lines) and Embree's time for scale."""

from __future__ import annotations

import math
from typing import Dict, List, Optional, Tuple

from . import _style
from ._data import Missing, Row, machine_caption, num, ok, option, tables, why_missing

TRAVERSALS = ["HTR", "BTR", "SLTR", "SEQ"]  # the paper's order; colours follow it


def _size(rows: List[Row]) -> Optional[Tuple[str, str]]:
    for r in rows:
        if "H3" in tables(r):
            return r["width"], r["height"]
    return None


def _views(rows: List[Row]) -> List[Tuple[str, str]]:
    seen: List[Tuple[str, str]] = []
    for r in rows:
        key = (r["scene"], r["view"])
        if key not in seen:
            seen.append(key)
    return seen


def collect(rows: List[Row]) -> Dict:
    """The figure's numbers, per view: {(scene, view): {"dmins": [...],
    "BTR"/"SLTR": {dmin: row}, "HTR"/"SEQ"/"Embree": row or None}}."""
    size = _size(rows)
    if size is None:
        return {}
    prim = [r for r in rows if (r["width"], r["height"]) == size and r["rays"] == "primary"
            and r.get("device", "cpu") in ("", "cpu")]
    dmins = sorted({int(option(r, "dmin")) for r in prim if "H3" in tables(r)
                    and r["accel"] == "kdtree" and r["traversal"] in ("BTR", "SLTR")
                    and int(option(r, "dmin") or -1) >= 0})
    out = {}
    for scene, view in _views([r for r in prim if "H3" in tables(r)]):
        mine = [r for r in prim if r["scene"] == scene and r["view"] == view]
        kd = [r for r in mine if r["accel"] == "kdtree" and option(r, "builder") == "nlogn"]
        d: Dict = {"dmins": dmins, "size": size}
        for t in ("BTR", "SLTR"):
            d[t] = {int(option(r, "dmin")): r for r in kd if r["traversal"] == t}
        for t in ("HTR", "SEQ"):
            d[t] = next((r for r in kd if r["traversal"] == t and option(r, "dmin") == "-1"), None)
        d["Embree"] = next((r for r in mine if r["accel"] == "embree"), None)
        d["triangles"] = next((r["triangles"] for r in mine if r.get("triangles")), "")
        out[(scene, view)] = d
    return out


def _series(d: Dict, name: str, key: str, scale: float = 1.0):
    """y values over d_min and, for each d_min without one, the reason."""
    ys, gaps = [], []
    for dm in d["dmins"]:
        row = d[name].get(dm) if name in ("BTR", "SLTR") else d[name]
        y = num(row, key) * scale if ok(row) else math.nan
        if name == "Embree" and key != "trace_median_s":
            y = math.nan
        ys.append(y)
        if math.isnan(y):
            gaps.append((dm, why_missing(row) if not ok(row) or row is None else
                         "the run recorded no %s" % key))
    return ys, gaps


@_style.styled
def plot_view(scene: str, view: str, d: Dict, machine: Dict[str, str], out_dir: str,
              formats: List[str], missing: Missing) -> List[str]:
    stem = "fig3-%s-%s" % (scene, view)
    fig = _style.figure(9.0, 3.6)
    ax_n, ax_t = fig.subplots(1, 2)
    x = d["dmins"]
    panels = [(ax_n, "primary_interior_per_ray", 1.0, "interior nodes per ray, $N_I$"),
              (ax_t, "trace_median_s", 1e3, "time per frame, $T_R$ [ms]")]
    marked = False
    for ax, key, scale, ylabel in panels:
        names = TRAVERSALS + (["Embree"] if key == "trace_median_s" else [])
        for i, name in enumerate(names):
            ys, gaps = _series(d, name, key, scale)
            colour = _style.OKABE_ITO[i] if name != "Embree" else _style.GREY
            const = name in ("HTR", "SEQ", "Embree")
            label = {"HTR": "HTR (no boxes)", "SEQ": "SEQ (no boxes)", "Embree": "Embree 3"}.get(
                name, name)
            ax.plot(x, ys, color=colour, marker=None if const else _style.MARKERS[i],
                    markersize=4, linestyle={"HTR": "--", "SEQ": ":", "Embree": "-."}.get(name, "-"),
                    linewidth=1.6, label=label)
            for dm, reason in gaps:
                missing.add(stem, "%s %s" % (name, key), "d_min %d" % dm, reason)
                ax.plot([dm], [0], marker="x", color=colour, markersize=7, clip_on=False,
                        transform=ax.get_xaxis_transform(), linestyle="none")
                marked = True
        ax.set_xlabel("$d_{min}$ (levels between sparse boxes)")
        ax.set_ylabel(ylabel)
        ax.set_ylim(bottom=0)
        if x:
            ax.set_xticks(x)
            ax.set_xlim(min(x) - 0.3, max(x) + 0.3)
    handles, labels = ax_t.get_legend_handles_labels()
    if marked:
        from matplotlib.lines import Line2D
        handles.append(Line2D([], [], marker="x", color="black", linestyle="none"))
        labels.append("missing point (see figures.md)")
    fig.tight_layout()
    _style.legend_above(fig, handles, labels, "%s:%s - Havran & Bittner Fig. 3" % (scene, view),
                        ncol=len(labels))
    w, h = d["size"]
    tri = (", %s triangles" % d["triangles"]) if d.get("triangles") else ""
    _style.caption(fig, "Scene %s, view %s%s; primary rays at %sx%s; SAH kd-trees (O(n log n) "
                   "build); BTR and SLTR with sparse boxes every d_min levels, HTR and SEQ "
                   "without boxes (constant). Time: median of the timed passes. Machine: %s."
                   % (scene, view, tri, w, h, machine_caption(machine)))
    return _style.save(fig, out_dir, stem, formats)


def plot_all(rows: List[Row], machine: Dict[str, str], out_dir: str, formats: List[str],
             missing: Missing) -> List[Tuple[str, List[str]]]:
    """Every view's figure: [(title, file names)]."""
    out = []
    for (scene, view), d in collect(rows).items():
        files = plot_view(scene, view, d, machine, out_dir, formats, missing)
        out.append(("Havran & Bittner Figure 3, %s:%s" % (scene, view), files))
    return out
