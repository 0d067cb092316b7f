"""Reading a results folder: the bench CSVs as lists of dicts with numbers
parsed, the machine from report.md, and the bookkeeping of points that a
figure could not draw (each gets a reason, listed in figures.md)."""

from __future__ import annotations

import csv
import math
import os
import re
from typing import Dict, List, Optional

Row = Dict[str, str]


def read_csv(path: str) -> List[Row]:
    """The rows of a CSV file as dicts ([] when the file is absent)."""
    if not os.path.exists(path):
        return []
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def num(row: Optional[Row], key: str) -> float:
    """row[key] as a float; NaN when the row, the column or the value is absent."""
    if row is None:
        return math.nan
    value = row.get(key)
    if value is None or value == "":
        return math.nan
    try:
        return float(value)
    except ValueError:
        return math.nan


def option(row: Row, key: str) -> Optional[str]:
    """The value of key=value in the row's options column."""
    m = re.search(r"(?:^|\s)%s=(\S+)" % re.escape(key), row.get("options", ""))
    return m.group(1) if m else None


def tables(row: Row) -> List[str]:
    return [t for t in row.get("tables", "").split(";") if t]


def ok(row: Optional[Row]) -> bool:
    return row is not None and row.get("status", "ok") == "ok"


def why_missing(row: Optional[Row]) -> str:
    """Why a point has no value: its run's error, or that it was not run."""
    if row is None:
        return "not run (no row in the CSV for this configuration)"
    status = row.get("status", "")
    if status and status != "ok":
        return "%s: %s" % (status, row.get("error") or "no message")
    return "the run recorded no value for it"


def machine(results_dir: str) -> Dict[str, str]:
    """CPU, threads, compiler and date from report.md's machine table
    (written by treetrace bench before it calls the plots); {} if absent."""
    path = os.path.join(results_dir, "report.md")
    out: Dict[str, str] = {}
    if not os.path.exists(path):
        return out
    keys = {"CPU": "cpu", "render threads": "threads", "compiler": "compiler", "date": "date",
            "reference": "reference"}
    with open(path, encoding="utf-8") as f:
        for line in f:
            m = re.match(r"\|\s*([^|]+?)\s*\|\s*([^|]+?)\s*\|\s*$", line)
            if m and m.group(1) in keys:
                out[keys[m.group(1)]] = m.group(2)
            if line.startswith("## ") and out:
                break
    return out


def machine_caption(m: Dict[str, str]) -> str:
    """One line naming the machine: "Intel Xeon, 2 threads, gcc 12.2.0, 2026-11-22"."""
    parts = []
    if m.get("cpu"):
        parts.append(re.sub(r"\((R|TM)\)", "", m["cpu"]).replace(" Processor", "").strip())
    if m.get("threads"):
        parts.append("%s threads" % m["threads"])
    if m.get("compiler"):
        parts.append(m["compiler"])
    if m.get("date"):
        parts.append(m["date"].split(" ")[0])
    return ", ".join(parts) if parts else "machine not recorded (no report.md)"


class Missing:
    """The points figures left out, with why: listed in figures.md and
    marked on the plots, never a silent gap."""

    def __init__(self) -> None:
        self.items: List[Dict[str, str]] = []

    def add(self, figure: str, series: str, where: str, reason: str) -> None:
        self.items.append({"figure": figure, "series": series, "where": where, "reason": reason})

    def for_figure(self, figure: str) -> List[Dict[str, str]]:
        return [m for m in self.items if m["figure"] == figure]
