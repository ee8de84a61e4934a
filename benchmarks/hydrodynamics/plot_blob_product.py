"""Plot the CSV written by benchmark_blob_product: CPU time per blob pair per core of the open-space
RPY product (tiled, the old scalar loop, the stored matrix) against the number of blobs, with the
standard errors, and the tiled product's speed-up over each peer (pair-by-pair ratios).

    .venv/bin/python benchmarks/hydrodynamics/plot_blob_product.py results.csv results.png
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(row, name):
    try:
        return float(row[name])
    except (KeyError, ValueError):
        return math.nan


def series(rows, name, error):
    points = [(number(r, "blobs"), number(r, name), number(r, error)) for r in rows]
    return [p for p in points if not math.isnan(p[1])]


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_blob_product.py results.csv results.png")
    with open(sys.argv[1], newline="", encoding='utf-8') as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{sys.argv[1]} holds no measurements")
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
    left.set_xscale("log")
    left.set_yscale("log")
    left.set_xlabel("blobs (5% volume fraction)")
    left.set_ylabel("CPU ns per blob pair per core")
    left.set_title(f"Open-space RPY product ({threads} threads)")
    left.grid(True, which="both", alpha=0.3)
    left.legend(fontsize=7)
    for name, error, label, style in [("old_ratio", "old_ratio_se", "old / tiled", "s-"), ("stored_ratio", "stored_ratio_se", "stored / tiled", "^-")]:
        points = series(rows, name, error)
        if points:
            x, y, e = zip(*points)
            right.errorbar(x, y, yerr=e, fmt=style, label=label, capsize=3)
    right.axhline(1.0, color="gray", linestyle=":")
    right.set_xscale("log")
    right.set_yscale("log")
    right.set_xlabel("blobs")
    right.set_ylabel("wall time of the peer / tiled (alternating pairs)")
    right.set_title("Speed-up of the tiled product")
    right.grid(True, which="both", alpha=0.3)
    right.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)
    print(f"wrote {sys.argv[2]}")


if __name__ == "__main__":
    sys.stdout.reconfigure(encoding='utf-8')  # an ASCII locale must not stop it
    main()
