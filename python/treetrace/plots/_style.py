"""The figures' look: Okabe & Ito's colour-blind-safe palette, distinct
markers and hatches (so series stay apart in grey print), readable fonts,
a caption naming the scene and the machine, and the PDF + PNG writer."""

from __future__ import annotations

import functools
import os
import textwrap
from typing import List

import matplotlib.pyplot as plt

# Okabe & Ito (2008), "Color Universal Design": distinguishable with any
# common colour-vision deficiency.
OKABE_ITO = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442",
             "#000000"]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*"]
HATCHES = ["", "//", "..", "xx", "\\\\", "++", "oo", "--"]
GREY = "#555555"

RC = {
    "font.size": 10,
    "axes.titlesize": 11,
    "axes.labelsize": 10,
    "legend.fontsize": 8.5,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "axes.grid": True,
    "grid.color": "#dddddd",
    "grid.linewidth": 0.6,
    "axes.axisbelow": True,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "pdf.fonttype": 42,  # TrueType in the PDF: text stays text (searchable, editable)
    "svg.fonttype": "none",
    "savefig.bbox": "tight",
}


def styled(fn):
    """Runs a figure function under RC without changing the caller's rcParams."""
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        with plt.rc_context(RC):
            return fn(*args, **kwargs)
    return wrapper


def figure(width: float, height: float):
    return plt.figure(figsize=(width, height))


def caption(fig, text: str) -> None:
    """The caption under the axes: what was measured, the scene, the machine
    (wrapped to the figure's width: about 17 characters an inch at 8 pt)."""
    width = int(fig.get_figwidth() * 17)
    fig.text(0.01, -0.01, textwrap.fill(text, width), ha="left", va="top", fontsize=8,
             color=GREY)


def save(fig, out_dir: str, stem: str, formats: List[str]) -> List[str]:
    """Writes stem.pdf, stem.png (and .svg when asked); returns the file names.
    No creation dates inside, so the same data gives the same files."""
    names = []
    for fmt in formats:
        name = "%s.%s" % (stem, fmt)
        meta = {"pdf": {"CreationDate": None, "ModDate": None, "Producer": None},
                "svg": {"Date": None}, "png": {"Software": None}}.get(fmt, {})
        fig.savefig(os.path.join(out_dir, name), format=fmt, dpi=150, metadata=meta)
        names.append(name)
    plt.close(fig)
    return names


def legend_above(fig, handles, labels, title: str, ncol: int = 3) -> None:
    """The legend in rows above the axes and the title above it, placed by
    the legend's height so neither overlaps the plots nor floats away."""
    rows = -(-len(labels) // ncol)
    h = fig.get_figheight()
    fig.legend(handles, labels, loc="lower center", ncol=ncol, frameon=False,
               bbox_to_anchor=(0.5, 1.0))
    fig.suptitle(title, y=1.0 + (rows * 0.2 + 0.12) / h, va="bottom")
