"""The engine table as grouped bars: each structure's throughput over
Embree's (Embree's line at 1.0) for every view and ray kind, and build
time and memory over Embree's. Reads engine.csv (one row per measurement,
with Embree's default/ROBUST/packet variants and our packet modes) when the
results folder has one, else the engine rows (tables E) of results.csv."""

from __future__ import annotations

import math
import os
from typing import Dict, List, Tuple

from . import _style
from ._bars import grouped_bars
from ._data import (Missing, Row, machine_caption, num, ok, option, read_csv, tables,
                    why_missing)

EMBREE = "Embree 3 (medium)"
# the library's defaults in results.csv's engine rows (engine.csv says so itself)
OLD_DEFAULTS = ("rtree sah, compact", "kdtree nlogn, htr")


def _label_old(r: Row) -> str:
    if r["accel"] == "embree":
        return "Embree 3 (%s)" % (option(r, "quality") or "medium")
    if r["accel"] == "rtree":
        b, lay = option(r, "build") or "?", option(r, "layout") or "?"
        return "rtree %s, %s%s" % (b, lay, " (Feldmann)" if (b, lay) == ("insert", "complete")
                                   else "")
    if r["accel"] == "kdtree":
        return "kdtree %s, %s" % (option(r, "builder") or "?", r["traversal"].lower())
    return r["accel"]


def records(results_dir: str) -> Tuple[List[Dict], str]:
    """Normalised records {view, config, default, kind, x, build_x, memory_x,
    why} and which CSV they came from."""
    new = read_csv(os.path.join(results_dir, "engine.csv"))
    out: List[Dict] = []
    if new:
        for r in new:
            if r.get("engine") == "treetrace" and r.get("mode", "auto") not in ("auto", ""):
                continue  # packets off/on: what they buy is its own question
            config = r.get("config", "")
            if r.get("engine") == "embree":
                variant = [v for v in (r.get("flags") if r.get("flags") != "default" else "",
                                       r.get("mode") if r.get("mode") != "single" else "") if v]
                if not variant:
                    continue  # the reference itself: the line at 1.0
                config = "%s %s" % (config or EMBREE, " ".join(variant))
            good = ok(r)
            out.append({"view": "%s:%s" % (r["scene"], r["view"]), "config": config,
                        "default": r.get("is_default") == "1", "kind": r.get("kind", ""),
                        "x": num(r, "x_embree") if good else math.nan,
                        "build_x": num(r, "x_embree_build") if good else math.nan,
                        "memory_x": num(r, "x_embree_memory") if good else math.nan,
                        "why": why_missing(r) if not good else "no x_embree in the row"})
        return out, "engine.csv"
    rows = [r for r in read_csv(os.path.join(results_dir, "results.csv")) if "E" in tables(r)]
    # the reference is Embree at medium build quality (the table's first row)
    embree = {(r["scene"], r["view"]): r for r in rows
              if r["accel"] == "embree" and option(r, "quality") in (None, "medium")}

    def rate(r, kind):
        return num(r, kind + "_rays") / num(r, kind + "_min_s") * 1e-6 if ok(r) else math.nan

    for r in rows:
        if r["accel"] == "embree":
            continue
        e = embree.get((r["scene"], r["view"]))
        label = _label_old(r)
        for kind in ("primary", "shadow"):
            x = rate(r, kind) / rate(e, kind) if e is not None else math.nan
            why = why_missing(r) if not ok(r) else (
                "Embree's run is missing" if e is None else why_missing(e))
            out.append({"view": "%s:%s" % (r["scene"], r["view"]), "config": label,
                        "default": label in OLD_DEFAULTS, "kind": kind, "x": x,
                        "build_x": num(r, "build_s") / num(e, "build_s") if ok(r) and ok(e)
                        else math.nan,
                        "memory_x": num(r, "memory_bytes") / num(e, "memory_bytes")
                        if ok(r) and ok(e) else math.nan, "why": why})
    return out, "results.csv"


def _order(items: List[str]) -> List[str]:
    seen: List[str] = []
    for i in items:
        if i not in seen:
            seen.append(i)
    return seen


@_style.styled
def plot(results_dir: str, machine: Dict[str, str], out_dir: str, formats: List[str],
         missing: Missing) -> List[Tuple[str, List[str]]]:
    recs, source = records(results_dir)
    if not recs:
        return []
    views = _order([r["view"] for r in recs])
    configs = _order([r["config"] for r in recs])
    labels = {r["config"]: r["config"] + (" (default)" if r["default"] else "") for r in recs}
    kinds = [k for k in ("primary", "shadow", "ao") if any(r["kind"] == k for r in recs)]
    out = []
    stem = "engine"
    fig = _style.figure(max(8.0, 1.2 * len(views) + 3), 3.0 * len(kinds) + 0.8)
    axes = fig.subplots(len(kinds), 1, squeeze=False)[:, 0]
    for ax, kind in zip(axes, kinds):
        vals = {(r["view"], labels[r["config"]]): (r["x"], r["why"]) for r in recs
                if r["kind"] == kind}
        grouped_bars(ax, views, [labels[c] for c in configs], vals, figure=stem,
                     missing=missing, what=kind + " rays", ref=1.0,
                     ref_label="Embree 3 (medium), one ray at a time = 1.0")
        ax.set_ylabel("%s rays: Mrays/s\nover Embree's (higher is faster)" % kind)
    fig.tight_layout()
    handles, labs = axes[0].get_legend_handles_labels()
    _style.legend_above(fig, handles, labs, "Engine table: throughput against Embree")
    _style.caption(fig, "Each structure as a user gets it (the library's defaults but for the "
                   "builder and layout named) against Embree 3 at medium build quality, traced "
                   "in the same run; throughput from the fastest timed pass of each ray kind. "
                   "Scenes and views on the x axis. Source: %s. Machine: %s."
                   % (source, machine_caption(machine)))
    out.append(("Engine table: throughput against Embree", _style.save(fig, out_dir, stem,
                                                                        formats)))

    # build time and memory: per scene (they do not depend on the view)
    stem = "engine-build-memory"
    scenes = _order([r["view"].split(":")[0] for r in recs])
    ours = [c for c in configs if not c.startswith("Embree")]
    fig = _style.figure(max(8.0, 1.2 * len(scenes) + 3), 6.6)
    axes = fig.subplots(2, 1)
    for ax, key, name in ((axes[0], "build_x", "build time"), (axes[1], "memory_x", "memory")):
        vals = {}
        for r in recs:
            scene = r["view"].split(":")[0]
            if r["config"] in ours and (scene, labels[r["config"]]) not in vals:
                vals[(scene, labels[r["config"]])] = (r[key], r["why"])
        grouped_bars(ax, scenes, [labels[c] for c in ours], vals, figure=stem, missing=missing,
                     what=name, ref=1.0, ref_label="Embree 3 (medium) = 1.0", log=True)
        ax.set_ylabel("%s over Embree's\n(log scale, lower is better)" % name)
    fig.tight_layout()
    handles, labs = axes[0].get_legend_handles_labels()
    _style.legend_above(fig, handles, labs, "Engine table: build time and memory against Embree")
    _style.caption(fig, "Build time (minimum over the builds made) and memory (everything the "
                   "structure holds, triangles included; Embree: its memory monitor) over "
                   "Embree 3's at medium build quality, per scene. Source: %s. Machine: %s."
                   % (source, machine_caption(machine)))
    out.append(("Engine table: build time and memory against Embree",
                _style.save(fig, out_dir, stem, formats)))
    return out
