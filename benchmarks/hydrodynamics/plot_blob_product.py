"""Plot the CSVs written by benchmark_blob_product: CPU time per blob pair per core of the mobility
product (tiled, the old scalar loop, the stored matrix) against the number of blobs, with the
standard errors, and the tiled product's speed-up over each peer (pair-by-pair ratios). Several CSVs
(open space and wall, double and single precision) share the axes, each labelled by its file name.

    .venv/bin/python benchmarks/hydrodynamics/plot_blob_product.py results.csv [more.csv ...] results.png
"""
import csv
import math
import pathlib
import sys

from plot_pse import log_axes, number, save  # first: it selects matplotlib's Agg backend

import matplotlib.pyplot as plt  # noqa: E402

PRODUCTS = [("tiled_ns_per_pair_core", "tiled_ns_se", "tiled", "o-"), ("old_ns_per_pair_core", "old_ns_se", "old scalar loop", "s--"),
            ("stored_ns_per_pair_core", "stored_ns_se", "stored M", "^:")]
RATIOS = [("old_ratio", "old_ratio_se", "old / tiled", "s-"), ("stored_ratio", "stored_ratio_se", "stored / tiled", "^:")]


def series(rows, name, error):
    points = [(number(r, "blobs"), number(r, name), number(r, error)) for r in rows]
    return [p for p in points if not math.isnan(p[1])]


def read(path):
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{path} holds no measurements")
    return rows


def draw(axes, rows, label, columns, color):
    for name, error, what, style in columns:
        points = series(rows, name, error)
        if points:
            x, y, e = zip(*points)
            axes.errorbar(x, y, yerr=e, fmt=style, color=color, label=f"{label}: {what}", capsize=3)


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: plot_blob_product.py results.csv [more.csv ...] results.png")
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5))
    threads = "?"
    for k, path in enumerate(sys.argv[1:-1]):
        rows = read(path)
        threads = rows[0].get("threads", "?")
        label = pathlib.Path(path).stem.replace("blob-product-", "").replace("-two-core-epyc", "")
        draw(left, rows, label, PRODUCTS if k == 0 else PRODUCTS[:1], f"C{k}")
        draw(right, rows, label, RATIOS, f"C{k}")
    left.axhline(1.0, color="gray", linestyle=":", label="goal: 1 ns")
    log_axes(left, "blobs (5% volume fraction)", "CPU ns per blob pair per core", f"Blob mobility product ({threads} threads)")
    right.axhline(1.0, color="gray", linestyle=":")
    log_axes(right, "blobs", "wall time of the peer / tiled (alternating pairs)", "Speed-up of the tiled product")
    save(fig, sys.argv[-1])


if __name__ == "__main__":
    sys.stdout.reconfigure(encoding='utf-8')  # an ASCII locale must not stop it
    main()
