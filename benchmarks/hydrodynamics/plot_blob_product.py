"""Plot the CSV written by benchmark_blob_product: CPU time per blob pair per core of the open-space
RPY product (tiled, the old scalar loop, the stored matrix) against the number of blobs, with the
standard errors, and the tiled product's speed-up over each peer (pair-by-pair ratios).

    .venv/bin/python benchmarks/hydrodynamics/plot_blob_product.py results.csv results.png
"""
import math
import sys

from plot_pse import log_axes, number, read_rows, save  # first: it selects matplotlib's Agg backend

import matplotlib.pyplot as plt  # noqa: E402


def series(rows, name, error):
    points = [(number(r, "blobs"), number(r, name), number(r, error)) for r in rows]
    return [p for p in points if not math.isnan(p[1])]


def main():
    rows = read_rows("plot_blob_product.py")
    threads = rows[0].get("threads", "?")
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    for name, error, label, style in [("tiled_ns_per_pair_core", "tiled_ns_se", "tiled (TiledBlobProduct)", "o-"),
                                      ("old_ns_per_pair_core", "old_ns_se", "old scalar loop", "s--"),
                                      ("stored_ns_per_pair_core", "stored_ns_se", "stored M, matrix-vector", "^--")]:
        points = series(rows, name, error)
        if points:
            x, y, e = zip(*points)
            left.errorbar(x, y, yerr=e, fmt=style, label=label, capsize=3)
    left.axhline(1.0, color="gray", linestyle=":", label="goal: 1 ns")
    log_axes(left, "blobs (5% volume fraction)", "CPU ns per blob pair per core", f"Open-space RPY product ({threads} threads)")
    for name, error, label, style in [("old_ratio", "old_ratio_se", "old / tiled", "s-"), ("stored_ratio", "stored_ratio_se", "stored / tiled", "^-")]:
        points = series(rows, name, error)
        if points:
            x, y, e = zip(*points)
            right.errorbar(x, y, yerr=e, fmt=style, label=label, capsize=3)
    right.axhline(1.0, color="gray", linestyle=":")
    log_axes(right, "blobs", "wall time of the peer / tiled (alternating pairs)", "Speed-up of the tiled product")
    save(fig, sys.argv[2])


if __name__ == "__main__":
    sys.stdout.reconfigure(encoding='utf-8')  # an ASCII locale must not stop it
    main()
