"""python3 -m treetrace.plots RESULTS_DIR [--out DIR] [--svg]"""

from __future__ import annotations

import argparse
import os
import sys


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python3 -m treetrace.plots",
                                description="Draw the figures of a `treetrace bench` results "
                                "folder (PDF + PNG) with matplotlib, and figures.md.")
    p.add_argument("results_dir", help="the folder with results.csv / engine.csv / dynamic.csv")
    p.add_argument("--out", help="where to write the figures (default: RESULTS_DIR)")
    p.add_argument("--svg", action="store_true", help="also write SVG files")
    a = p.parse_args(argv)
    if "MPLBACKEND" not in os.environ:
        import matplotlib
        matplotlib.use("Agg")  # files only: no display needed
    from . import make_all
    try:
        made = make_all(a.results_dir, a.out, a.svg)
    except FileNotFoundError as e:
        print("treetrace.plots: %s" % e, file=sys.stderr)
        return 2
    out = a.out or a.results_dir
    print("treetrace.plots: wrote %d figures (%d files) and figures.md to %s"
          % (len(made), sum(len(f) for _, f in made), out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
