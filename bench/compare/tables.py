#!/usr/bin/python3
"""Markdown tables from bench/capabilities.sh's runs.tsv (usage: tables.py runs.tsv).

Table 1: each geotex capability per size, "wall s / CPU s (user+sys) / peak RSS MB".
Table 2: each comparison: geotex's runs (default threads, and --threads 1 when measured) and the other
tool's run on the same input, back to back, with the ratios other / geotex of CPU time (against both
geotex runs) and of wall time (against the default run); > 1: geotex is faster. Then quality rows.
When a label was measured more than once, the last run counts.
"""
import csv
import sys

SIZES = ["1e4", "1e5", "1e6"]
# comparison group -> (label of geotex's run, group holding it)
REFERENCE = {
    "smooth-cgal": ("geotex smooth, barycentric mass, rescale", "smooth-cgal"),
    "smooth-openmesh": ("geotex smooth, explicit umbrella, 0.5, 10 steps", "smooth-openmesh"),
    "denoise-meshlab": ("denoise mrf (defaults)", "cap"),
    "param-cgal": ("param (conformal, disk)", "cap"),
    "param-natural": ("geotex param --method natural", "param-natural"),
}
TITLE = {
    "smooth-cgal": "implicit cotangent step vs CGAL smooth_shape (noisy cube; 1 step, lambda = 1 h^2)",
    "smooth-openmesh": "explicit umbrella smoothing vs OpenMesh JacobiLaplaceSmootherT (noisy cube; 10 iterations)",
    "denoise-meshlab": "denoising: geotex mrf vs MeshLab TwoStep Smooth (noisy cube)",
    "param-cgal": "conformal parametrization vs CGAL Discrete_conformal_map (spiky plane)",
    "param-natural": "free-boundary parametrization: geotex natural conformal vs CGAL LSCM (spiky plane)",
}


def load(path):
    runs = {}
    order = []
    with open(path, newline="") as f:
        for row in csv.DictReader(f, delimiter="\t"):
            key = (row["size"], row["group"], row["label"], row["status"] == "quality")
            if key not in runs:
                order.append(key)
            runs[key] = row
    return runs, order


def num(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return None


def cell(row):
    if row is None:
        return "–"
    s = f"{row['wall_s']} / {row['cpu_s']} / {row['rss_mb']}"
    if row["status"] != "ok":
        s += f" ({row['status']})"
    return s


def faces(x):
    n = num(x)
    return f"{int(n):,}" if n else ""


def main():
    runs, order = load(sys.argv[1])
    sizes = [s for s in SIZES if any(k[0] == s for k in order)]

    print("### geotex capabilities: wall s / CPU s (user+sys) / peak RSS MB\n")
    labels = [k[2] for k in order if k[1] == "cap" and not k[3]]
    labels = list(dict.fromkeys(labels))
    print("| capability | " + " | ".join(f"{s} faces" for s in sizes) + " |")
    print("|---|" + "---|" * len(sizes))
    for label in labels:
        cells = []
        for s in sizes:
            row = runs.get((s, "cap", label, False))
            cells.append(f"{faces(row['faces'])}: {cell(row)}" if row else "–")
        print(f"| {label} | " + " | ".join(cells) + " |")
    loads = {s: [num(r["load"]) for k, r in runs.items() if k[0] == s and num(r["load"]) is not None] for s in sizes}
    print("\nLoad average (1 min) at the start of the runs: " + ", ".join(
        f"{s}: {min(v):.1f}–{max(v):.1f}" for s, v in loads.items() if v) + "\n")

    for group, (ref_label, ref_group) in REFERENCE.items():
        if not any(k[1] == group for k in order):
            continue
        print(f"### {TITLE[group]}\n")
        print("| size | faces | tool | wall s | CPU s | peak MB | CPU ratio other/geotex | CPU ratio other/geotex 1 thread "
              "| wall ratio | load | note |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for s in sizes:
            ref = runs.get((s, ref_group, ref_label, False))
            if ref is None:
                continue
            ref1 = runs.get((s, group, ref_label + " (1 thread)", False))
            geotex = [ref] + ([ref1] if ref1 else [])
            rows = geotex + [runs[k] for k in order if k[0] == s and k[1] == group and not k[3]
                             and runs[k] is not ref and runs[k] is not ref1]
            for r in rows:
                ratio_cpu = ratio_cpu1 = ratio_wall = ""
                if r not in geotex and r["status"] == "ok":
                    a, b = num(r["cpu_s"]), num(ref["cpu_s"])
                    ratio_cpu = f"{a / b:.2f}" if a is not None and b else ""
                    if ref1 and ref1["status"] == "ok":
                        b = num(ref1["cpu_s"])
                        ratio_cpu1 = f"{a / b:.2f}" if a is not None and b else ""
                    a, b = num(r["wall_s"]), num(ref["wall_s"])
                    ratio_wall = f"{a / b:.2f}" if a is not None and b else ""
                name = f"geotex: {r['label']}" if r in geotex and not r["label"].startswith("geotex") else r["label"]
                status = "" if r["status"] == "ok" else f" **{r['status']}**"
                print(f"| {s} | {faces(r['faces'])} | {name}{status} | {r['wall_s']} | {r['cpu_s']} | {r['rss_mb']} | "
                      f"{ratio_cpu} | {ratio_cpu1} | {ratio_wall} | {r['load']} | {r['note'].strip()} |")
            for k in order:
                if k[0] == s and k[1] == group and k[3]:
                    print(f"| {s} | | quality: {k[2]} | | | | | | | | {runs[k]['note']} |")
        print()

    data = [k for k in order if k[0] == "data"]
    pairs = list(dict.fromkeys(k[1] for k in data))
    data.sort(key=lambda k: (pairs.index(k[1]), k[3]))  # per pair: timed runs, then quality rows
    if data:
        print("### Denoising quality and time on the real pairs (geotex compare RESULT Original.obj)\n")
        print("| pair | faces | run | wall s | CPU s | peak MB | mean normal error, Ev |")
        print("|---|---|---|---|---|---|---|")
        for k in data:
            r = runs[k]
            pair = k[1].replace("denoise-", "")
            if k[3]:
                print(f"| {pair} | | {k[2]} | | | | {r['note']} |")
            else:
                print(f"| {pair} | {faces(r['faces'])} | {k[2]} | {r['wall_s']} | {r['cpu_s']} | {r['rss_mb']} | |")
        print()


if __name__ == "__main__":
    main()
