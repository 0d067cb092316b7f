"""treetrace.plots: the committed reports' figures plot the numbers their
tables print (so regenerating them changed no number), every figure the
reports link exists, the engine plot reads both the old results.csv rows
and yard's engine.csv, the dynamic plot reads dyn's dynamic.csv, and a
missing point is listed with its reason, never left as a silent gap."""
import csv
import math
import os
import re
import shutil
import subprocess
import sys

import pytest

pytest.importorskip("matplotlib")

from treetrace.plots import _data, engine, fig3, make_all  # noqa: E402

from conftest import ROOT  # noqa: E402

RESULTS = os.path.join(ROOT, "bench")
PAPERS = os.path.join(RESULTS, "results-2026-11-22")
ENGINE = os.path.join(RESULTS, "results-2026-12-02")


def _report_tables(path):
    """{heading: [rows as lists of cells]} for every '#### ' section."""
    out, head = {}, None
    for line in open(path, encoding="utf-8"):
        if line.startswith("#### "):
            head = line[5:].strip()
            out[head] = []
        elif line.startswith("## ") or line.startswith("### "):
            head = None
        elif head and line.startswith("|") and not line.startswith("|---"):
            out[head].append([c.strip() for c in line.strip().strip("|").split("|")])
    return out


def _same(value, printed):
    """value (from the CSV, 6 digits) is what the report printed, to the
    printed digits: within half a unit of its last digit (the report rounds
    the unrounded number, so a CSV value on a rounding boundary may go the
    other way)."""
    text = printed.rstrip("x").rstrip(" s")
    digits = len(text.split(".")[1]) if "." in text else 0
    return abs(value - float(text)) <= 0.5 * 10 ** -digits * 1.001


def test_committed_figure3_plots_the_tables_numbers():
    rows = _data.read_csv(os.path.join(PAPERS, "results.csv"))
    views = fig3.collect(rows)
    tables = _report_tables(os.path.join(PAPERS, "report.md"))
    checked = 0
    for (scene, view), d in views.items():
        assert d["HTR"] is not None and d["SEQ"] is not None and d["Embree"] is not None
        table = tables["%s:%s" % (scene, view)][1:]  # past the header row
        for cells in table:
            dm = int(cells[0])
            b, s = d["BTR"][dm], d["SLTR"][dm]
            assert _same(float(b["primary_interior_per_ray"]), cells[1])
            assert _same(float(s["primary_interior_per_ray"]), cells[2])
            assert _same(float(b["trace_median_s"]), cells[3])
            assert _same(float(s["trace_median_s"]), cells[4])
            checked += 1
    assert checked == 7 * 12
    # conference:main's SLTR at d_min 11, the old plot's "gap", is there
    assert float(views[("conference", "main")]["SLTR"][11]["primary_interior_per_ray"]) > 60


def test_committed_engine_plot_is_the_tables_ratios():
    recs, source = engine.records(ENGINE)
    assert source == "results.csv"
    tables = _report_tables(os.path.join(ENGINE, "report.md"))
    checked = 0
    for head, table in tables.items():
        view = head.split(" (")[0]
        for cells in table[1:]:
            label = cells[0].replace(" **(default)**", "")
            if label.startswith("Embree"):
                continue
            for kind, col in (("primary", 3), ("shadow", 5)):
                r = next(r for r in recs if r["view"] == view and r["config"] == label
                         and r["kind"] == kind)
                assert _same(r["x"], cells[col]), (view, label, kind, r["x"], cells[col])
                checked += 1
            r = next(r for r in recs if r["view"] == view and r["config"] == label)
            assert _same(r["build_x"], cells[7]) and _same(r["memory_x"], cells[9])
    assert checked == 7 * 8 * 2


@pytest.mark.parametrize("folder", [PAPERS, ENGINE])
def test_committed_reports_link_existing_figures(folder):
    for name in ("report.md", "figures.md"):
        text = open(os.path.join(folder, name), encoding="utf-8").read()
        links = re.findall(r"\]\(([^)]+\.(?:png|pdf|md))\)", text)
        assert links
        for link in links:
            assert os.path.exists(os.path.join(folder, link)), "%s links %s" % (name, link)
    assert not [f for f in os.listdir(folder) if re.match(r"fig3-.*-(interior|time)\.png", f)]


def _write(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)


def test_missing_points_are_listed_and_marked(tmp_path):
    out = tmp_path / "r"
    out.mkdir()
    rows = list(csv.DictReader(open(os.path.join(PAPERS, "results.csv"))))
    keep = []
    for r in rows:
        if r["scene"] != "cornell":
            continue  # one scene is enough here, and quick
        if (r["scene"], r["view"], r["traversal"], _data.option(r, "dmin")) == (
                "cornell", "main", "SLTR", "11"):
            continue  # a run that never happened
        if (r["scene"], r["view"], r["traversal"], _data.option(r, "dmin")) == (
                "cornell", "main", "BTR", "3"):
            r = dict(r, status="error", error="out of memory building the boxes")
        keep.append(r)
    _write(out / "results.csv", list(rows[0].keys()), [list(r.values()) for r in keep])
    made = make_all(str(out))
    assert ("Havran & Bittner Figure 3, cornell:main", ["fig3-cornell-main.pdf",
                                                          "fig3-cornell-main.png"]) in made
    md = (out / "figures.md").read_text()
    assert "| fig3-cornell-main | SLTR primary_interior_per_ray | d_min 11 | not run" in md
    assert "| fig3-cornell-main | BTR trace_median_s | d_min 3 | error: out of memory" in md
    assert md.count("| fig3-") == 4  # N_I and T_R of each: nothing else is missing


ENGINE_CSV = ["scene", "view", "width", "height", "triangles", "threads", "rounds", "engine",
              "config", "accel", "options", "is_default", "mode", "flags", "kind", "rays",
              "best_s", "mrays_per_s", "x_embree", "x_embree_robust", "x_embree_p8",
              "x_embree_p16", "x_packets_off", "status", "error", "isa", "packets_offered",
              "build_s", "builds", "memory_bytes", "x_embree_build", "x_embree_memory"]


def _engine_row(view, engine_, config, mode, flags, kind, x, status="ok", default="0"):
    d = dict.fromkeys(ENGINE_CSV, "")
    d.update(scene=view.split(":")[0], view=view.split(":")[1], engine=engine_, config=config,
             mode=mode, flags=flags, kind=kind, x_embree=x, status=status, is_default=default,
             x_embree_build="2.0", x_embree_memory="0.5")
    if status != "ok":
        d.update(x_embree="", error="kernel refused the ray batch")
    return [d[k] for k in ENGINE_CSV]


def test_engine_plot_reads_yards_engine_csv(tmp_path):
    rows = []
    for view in ("bunny:main", "sibenik:main"):
        for kind in ("primary", "shadow", "ao"):
            rows.append(_engine_row(view, "embree", "Embree 3 (medium)", "single", "default",
                                    kind, "1.0"))
            rows.append(_engine_row(view, "embree", "Embree 3 (medium)", "single", "robust",
                                    kind, "0.8"))
            rows.append(_engine_row(view, "embree", "Embree 3 (medium)", "p16", "default",
                                    kind, "1.7"))
            rows.append(_engine_row(view, "treetrace", "rtree sah, compact", "auto", "", kind,
                                    "0.9", default="1"))
            rows.append(_engine_row(view, "treetrace", "rtree sah, compact", "off", "", kind,
                                    "0.7", default="1"))
            bad = view == "sibenik:main" and kind == "ao"
            rows.append(_engine_row(view, "treetrace", "kdtree nlogn, htr", "auto", "", kind,
                                    "0.8", status="error" if bad else "ok"))
    _write(tmp_path / "engine.csv", ENGINE_CSV, rows)
    recs, source = engine.records(str(tmp_path))
    assert source == "engine.csv"
    configs = {r["config"] for r in recs}
    assert configs == {"rtree sah, compact", "kdtree nlogn, htr", "Embree 3 (medium) robust",
                       "Embree 3 (medium) p16"}  # packets=off rows and the reference left out
    assert {r["kind"] for r in recs} == {"primary", "shadow", "ao"}
    made = make_all(str(tmp_path))
    assert [t for t, _ in made] == ["Engine table: throughput against Embree",
                                    "Engine table: build time and memory against Embree"]
    md = (tmp_path / "figures.md").read_text()
    assert "| engine | kdtree nlogn, htr | sibenik:main (ao rays) | error: kernel refused" in md


def test_dynamic_plot_reads_dyns_columns(tmp_path):
    header = ["scene", "mode", "engine", "frame", "triangles", "update_ms", "primary_ms",
              "shadow_ms", "trace_ms", "sah", "fresh_sah", "sah_ratio", "fresh_trace_ms",
              "trace_ratio", "memory_bytes", "refit", "removed", "inserted", "layout"]
    rows = []
    for mode in ("deform", "edits", "growth"):
        for engine_ in ("treetrace", "embree-refit", "embree-low"):
            for frame in range(0, 21):
                fresh = frame % 10 == 0 or frame == 20
                ours = engine_ == "treetrace"
                rows.append(["bunny", mode, engine_, frame, 69451, 3.0 + frame * 0.1, 20, 10, 30,
                             100 + frame if ours else "", 100 if ours and fresh else "",
                             (100 + frame) / 100 if ours and fresh else "",
                             30 if ours and fresh else "",
                             1 + frame / 100 if ours and fresh else "", 1 << 20, 5, 1, 1,
                             "inplace"])
    _write(tmp_path / "dynamic.csv", header, rows)
    made = make_all(str(tmp_path), svg=True)
    assert [t for t, _ in made] == ["Dynamic scenes: drift over frames",
                                    "Dynamic scenes: update time per frame"]
    assert made[0][1] == ["dynamic-drift.pdf", "dynamic-drift.png", "dynamic-drift.svg"]
    assert (tmp_path / "dynamic-drift.pdf").read_bytes()[:5] == b"%PDF-"
    assert "None: every figure" in (tmp_path / "figures.md").read_text()


def test_command_line(tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    bad = subprocess.run([sys.executable, "-m", "treetrace.plots", str(tmp_path / "none")],
                         capture_output=True, text=True, env=env)
    assert bad.returncode == 2 and "not a results folder" in bad.stderr
    shutil.copy(os.path.join(ENGINE, "results.csv"), tmp_path / "results.csv")
    shutil.copy(os.path.join(ENGINE, "report.md"), tmp_path / "report.md")
    good = subprocess.run([sys.executable, "-m", "treetrace.plots", str(tmp_path), "--out",
                           str(tmp_path / "figs")], capture_output=True, text=True, env=env)
    assert good.returncode == 0, good.stderr
    assert "wrote 2 figures (4 files)" in good.stdout
    assert sorted(os.listdir(tmp_path / "figs")) == [
        "engine-build-memory.pdf", "engine-build-memory.png", "engine.pdf", "engine.png",
        "figures.md"]
    # the caption names the machine from report.md
    assert _data.machine_caption(_data.machine(str(tmp_path))).startswith("Intel Xeon, 2 threads")
    assert not math.isnan(_data.num({"x": "1.5"}, "x"))
