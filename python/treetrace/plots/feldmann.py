"""Feldmann's comparisons as grouped bars per view: the insertion
strategies (Table 1, over R*-treeSrfc's time as the paper compares them),
forced reinsert or not (Table 2), the R-tree traversals (Table 3) and the
R*-tree against the kd-tree (Table 4), each with Embree's time for scale."""

from __future__ import annotations

import math
from typing import Callable, Dict, List, Optional, Tuple

from . import _style
from ._bars import grouped_bars
from ._data import Missing, Row, machine_caption, num, ok, option, tables, why_missing

STRATEGIES = ["minVolume", "minSurface", "minOverlap", "R*-tree", "R*-treeSrfc"]


def _views(rows: List[Row]) -> List[str]:
    out: List[str] = []
    for r in rows:
        v = "%s:%s" % (r["scene"], r["view"])
        if v not in out:
            out.append(v)
    return out


def _embree(rows: List[Row], r: Row) -> Optional[Row]:
    return next((e for e in rows if e["accel"] == "embree" and e["scene"] == r["scene"]
                 and e["view"] == r["view"] and e["width"] == r["width"]
                 and e["rays"] == r["rays"] and option(e, "quality") in (None, "high")), None)


def _value(r: Optional[Row], scale: float = 1e3) -> Tuple[float, str]:
    if not ok(r):
        return math.nan, why_missing(r)
    return num(r, "trace_median_s") * scale, "the run recorded no time"


TABLES: List[Dict] = [
    {"id": "F1", "stem": "feldmann-strategies",
     "title": "Feldmann Table 1: R-tree insertion strategies",
     "series": lambda r: option(r, "strategy"), "order": STRATEGIES,
     "ylabel": "time per frame over\nR*-treeSrfc's (lower is better)", "ratio_to": "R*-treeSrfc",
     "caption": "R-trees with m = 2, M = 4 and forced reinsert, built with each node-selection "
                "strategy, stackless traversal; primary + shadow rays. Bars: median time per "
                "frame over the R*-treeSrfc tree's, as the paper compares them"},
    {"id": "F2", "stem": "feldmann-reinsert",
     "title": "Feldmann Table 2: forced reinsert or not (R*-treeSrfc)",
     "series": lambda r: "forced reinsert" if option(r, "reinsert") == "1" else "no reinsert",
     "order": ["forced reinsert", "no reinsert"], "ylabel": "time per frame [ms]",
     "caption": "R*-treeSrfc R-trees (m = 2, M = 4) built with and without forced reinsert, "
                "stackless traversal; primary + shadow rays; median time per frame"},
    {"id": "F3", "stem": "feldmann-traversals", "title": "Feldmann Table 3: R-tree traversals",
     "series": lambda r: r["traversal"], "order": ["stackless", "ordered", "stack"],
     "ylabel": "time per frame [ms]",
     "caption": "The R*-treeSrfc R-tree traced with each traversal; primary + shadow rays; "
                "median time per frame"},
    {"id": "F4", "stem": "feldmann-rtree-kdtree", "title": "Feldmann Table 4: R*-tree vs kd-tree",
     "series": lambda r: "%s %s" % ("R*-tree" if r["accel"] == "rtree" else "kd-tree",
                                    r["rays"]),
     "order": ["R*-tree primary", "kd-tree primary", "R*-tree primary+shadow",
               "kd-tree primary+shadow"], "ylabel": "time per frame [ms]",
     "caption": "The R*-treeSrfc R-tree (stack traversal) and an SAH kd-tree (HTR), primary "
                "rays alone and with shadow rays; median time per frame"},
]


@_style.styled
def plot_table(rows: List[Row], spec: Dict, machine: Dict[str, str], out_dir: str,
               formats: List[str], missing: Missing) -> Optional[Tuple[str, List[str]]]:
    mine = [r for r in rows if spec["id"] in tables(r) and r["accel"] != "embree"
            and r.get("device", "cpu") in ("", "cpu")]
    if not mine:
        return None
    views = _views(mine)
    key: Callable[[Row], str] = spec["series"]
    series = [s for s in spec["order"] if any(key(r) == s for r in mine)]
    series += [s for s in {key(r) for r in mine} if s not in series]
    by = {("%s:%s" % (r["scene"], r["view"]), key(r)): r for r in mine}
    vals: Dict[Tuple[str, str], Tuple[float, str]] = {}
    for v in views:
        base = by.get((v, spec["ratio_to"])) if spec.get("ratio_to") else None
        for s in series:
            val, why = _value(by.get((v, s)))
            if spec.get("ratio_to"):
                b, bwhy = _value(base)
                val, why = (val / b, why) if not math.isnan(b) else (math.nan, "reference: " + bwhy)
            vals[(v, s)] = (val, why)
    if not spec.get("ratio_to"):
        # Embree with the same rays as each bar group's runs (Table 4 has two kinds)
        kinds = sorted({r["rays"] for r in mine})
        for kind in kinds:
            name = "Embree 3" if len(kinds) == 1 else "Embree 3 %s" % kind
            series.append(name)
            for v in views:
                r = next(r for r in mine
                         if "%s:%s" % (r["scene"], r["view"]) == v and r["rays"] == kind)
                vals[(v, name)] = _value(_embree(rows, r))
    fig = _style.figure(max(7.5, 1.3 * len(views) + 2.5), 3.6)
    ax = fig.subplots()
    colours = [_style.GREY if n.startswith("Embree") else _style.OKABE_ITO[i]
               for i, n in enumerate(series)]
    if sum(n.startswith("Embree") for n in series) == 2:
        colours[-2] = "#999999"
    grouped_bars(ax, views, series, vals, figure=spec["stem"], missing=missing,
                 what=spec["id"], ref=1.0 if spec.get("ratio_to") else None,
                 ref_label="R*-treeSrfc = 1.0", colours=colours)
    ax.set_ylabel(spec["ylabel"])
    fig.tight_layout()
    h, lab = ax.get_legend_handles_labels()
    _style.legend_above(fig, h, lab, spec["title"], ncol=min(len(lab), 4))
    size = "%sx%s" % (mine[0]["width"], mine[0]["height"])
    embree = "" if spec.get("ratio_to") else "; Embree 3 (high build quality) traced in the same run"
    _style.caption(fig, "%s, at %s%s. Scenes and views on the x axis. Machine: %s."
                   % (spec["caption"], size, embree, machine_caption(machine)))
    return spec["title"], _style.save(fig, out_dir, spec["stem"], formats)


def plot_all(rows: List[Row], machine: Dict[str, str], out_dir: str, formats: List[str],
             missing: Missing) -> List[Tuple[str, List[str]]]:
    out = []
    for spec in TABLES:
        got = plot_table(rows, spec, machine, out_dir, formats, missing)
        if got:
            out.append(got)
    return out
