"""Grouped bars with a reference line, shared by the engine and Feldmann
figures; a bar without a value is marked with an x on the axis and listed
in figures.md with its reason."""

from __future__ import annotations

import math
from typing import Dict, List, Optional, Sequence, Tuple

from . import _style
from ._data import Missing


def grouped_bars(ax, groups: Sequence[str], series: Sequence[str],
                 values: Dict[Tuple[str, str], Tuple[float, str]], *, figure: str,
                 missing: Missing, what: str, ref: Optional[float] = None,
                 ref_label: str = "", log: bool = False, colours: Optional[List[str]] = None,
                 label_values: bool = False) -> None:
    """values[(group, series)] = (value, reason it is missing when NaN)."""
    n = max(len(series), 1)
    width = 0.8 / n
    colours = colours or [_style.OKABE_ITO[i % len(_style.OKABE_ITO)] for i in range(n)]
    for j, s in enumerate(series):
        xs, ys = [], []
        for i, g in enumerate(groups):
            x = i - 0.4 + width * (j + 0.5)
            v, reason = values.get((g, s), (math.nan, "not run (no row in the CSV)"))
            if math.isnan(v) or (log and v <= 0):
                missing.add(figure, s, "%s (%s)" % (g, what), reason)
                ax.plot([x], [0.0], marker="x", color=colours[j], markersize=6, clip_on=False,
                        transform=ax.get_xaxis_transform(), linestyle="none")
                continue
            xs.append(x)
            ys.append(v)
        bars = ax.bar(xs, ys, width * 0.92, color=colours[j], edgecolor="white", linewidth=0.4,
                      hatch=_style.HATCHES[j % len(_style.HATCHES)], label=s)
        if label_values:
            ax.bar_label(bars, fmt="%.2f", fontsize=6, padding=1, rotation=90)
    if ref is not None:
        ax.axhline(ref, color="black", linestyle="--", linewidth=1.1, label=ref_label, zorder=3)
    if log:
        ax.set_yscale("log")
    ax.set_xticks(range(len(groups)))
    ax.set_xticklabels(groups, rotation=20 if len(groups) > 4 else 0, ha="right"
                       if len(groups) > 4 else "center")
    ax.set_xlim(-0.6, len(groups) - 0.4)
    ax.grid(axis="x", visible=False)
