"""Figures from a `treetrace bench` results folder, drawn with matplotlib
as PDF (vector) and PNG (SVG on request):

    python3 -m treetrace.plots RESULTS_DIR [--svg] [--out DIR]

- fig3-SCENE-VIEW: Havran & Bittner's Figure 3 (results.csv, H3 rows);
- engine, engine-build-memory: the engine table (engine.csv, else the E
  rows of results.csv);
- feldmann-*: Feldmann's Tables 1-4 (results.csv, F1-F4 rows);
- dynamic-drift, dynamic-update: the dynamic table (dynamic.csv).

figures.md lists the figures and every point a figure could not draw with
the reason (the run's error, or that it was not run): no silent gaps.

>>> import treetrace.plots as tp
>>> tp.make_all("no/such/folder")
Traceback (most recent call last):
  ...
FileNotFoundError: no/such/folder: not a results folder (no results.csv, engine.csv or dynamic.csv)
"""

from __future__ import annotations

import os
from typing import List, Optional, Tuple

from . import dynamic, engine, feldmann, fig3
from ._data import Missing, machine, machine_caption, read_csv

__all__ = ["make_all"]

_INPUTS = ("results.csv", "engine.csv", "dynamic.csv")


def make_all(results_dir: str, out_dir: Optional[str] = None, svg: bool = False
             ) -> List[Tuple[str, List[str]]]:
    """Draws every figure the folder's CSVs allow into out_dir (default: the
    folder) and writes figures.md there; returns [(title, file names)].

    >>> import os, tempfile, treetrace.plots as tp
    >>> d = tempfile.mkdtemp()
    >>> _ = open(os.path.join(d, "dynamic.csv"), "w").write(
    ...     "scene,mode,engine,frame,update_ms,sah_ratio,trace_ratio\\n"
    ...     "bunny,deform,treetrace,0,5.0,1.0,1.0\\n"
    ...     "bunny,deform,treetrace,1,1.0,1.1,1.05\\n")
    >>> [title for title, files in tp.make_all(d)]
    ['Dynamic scenes: drift over frames', 'Dynamic scenes: update time per frame']
    >>> sorted(f for f in os.listdir(d) if f.startswith("dynamic-drift"))
    ['dynamic-drift.pdf', 'dynamic-drift.png']
    """
    if not any(os.path.exists(os.path.join(results_dir, f)) for f in _INPUTS):
        raise FileNotFoundError("%s: not a results folder (no %s)" % (
            results_dir, ", ".join(_INPUTS[:-1]) + " or " + _INPUTS[-1]))
    out_dir = out_dir or results_dir
    os.makedirs(out_dir, exist_ok=True)
    formats = ["pdf", "png"] + (["svg"] if svg else [])
    m = machine(results_dir)
    missing = Missing()
    rows = read_csv(os.path.join(results_dir, "results.csv"))
    made: List[Tuple[str, List[str]]] = []
    made += fig3.plot_all(rows, m, out_dir, formats, missing)
    made += engine.plot(results_dir, m, out_dir, formats, missing)
    made += feldmann.plot_all(rows, m, out_dir, formats, missing)
    made += dynamic.plot(results_dir, m, out_dir, formats, missing)
    _write_index(out_dir, made, missing, m)
    return made


def _write_index(out_dir: str, made, missing: Missing, m) -> None:
    lines = ["# Figures", "",
             "Drawn by `python3 -m treetrace.plots` (matplotlib) from this folder's CSVs; "
             "machine: %s. Each figure is a PDF (vector, for papers) and a PNG." %
             machine_caption(m), ""]
    for title, files in made:
        png = next((f for f in files if f.endswith(".png")), files[0])
        others = ", ".join("[%s](%s)" % (f.rsplit(".", 1)[1].upper(), f) for f in files
                           if not f.endswith(".png"))
        lines += ["## %s" % title, "", "![%s](%s)" % (title, png), "", others, ""]
    lines += ["## Missing points", ""]
    if not missing.items:
        lines += ["None: every figure has every point its CSV rows call for.", ""]
    else:
        lines += ["Marked with an x on the figure's axis.", "",
                  "| figure | series | where | why |", "|---|---|---|---|"]
        for it in missing.items:
            lines.append("| %s | %s | %s | %s |" % (it["figure"], it["series"], it["where"],
                                                     it["reason"].replace("|", "/")))
        lines.append("")
    with open(os.path.join(out_dir, "figures.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines))
