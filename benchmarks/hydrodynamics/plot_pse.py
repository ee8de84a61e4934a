"""Plot the CSV written by benchmark_pse: time per product and per noise sample against the number
of blobs (log-log), for each tolerance, with the dense Ewald sum where it was measured; and memory.

    .venv/bin/python benchmarks/hydrodynamics/plot_pse.py results.csv results.png
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


def series(rows, epsilon, name):
    points = [(number(r, "blobs"), number(r, name)) for r in rows if number(r, "epsilon") == epsilon]
    return [p for p in points if not math.isnan(p[1])]


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_pse.py results.csv results.png")
    with open(sys.argv[1], newline="", encoding='utf-8') as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{sys.argv[1]} holds no measurements")
    threads = rows[0].get("threads", "?")
    tolerances = sorted({number(r, "epsilon") for r in rows}, reverse=True)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    for epsilon in tolerances:
        for name, label, style in [("product_ms", "PSE product", "o-"), ("noise_ms", "PSE noise sample", "s-"),
                                   ("peer_product_ms", "dense product", "^--"), ("peer_noise_ms", "dense noise (Lanczos)", "v--")]:
            points = series(rows, epsilon, name)
            if points:
                left.plot(*zip(*points), style, label=f"{label}, ε = {epsilon:g}")
        points = series(rows, epsilon, "peak_mib")
        if points:
            right.plot(*zip(*points), "o-", label=f"PSE peak, ε = {epsilon:g}")
        points = series(rows, epsilon, "peer_peak_mib")
        if points:
            right.plot(*zip(*points), "^--", label=f"PSE and dense alive, ε = {epsilon:g}")
    left.set_xscale("log")
    left.set_yscale("log")
    left.set_xlabel("blobs (5% volume fraction)")
    left.set_ylabel("milliseconds")
    left.set_title(f"Periodic RPY mobility ({threads} threads)")
    left.grid(True, which="both", alpha=0.3)
    left.legend(fontsize=7)
    right.set_xscale("log")
    right.set_yscale("log")
    right.set_xlabel("blobs")
    right.set_ylabel("peak resident memory (MiB)")
    right.set_title("Peak memory of the measuring process")
    right.grid(True, which="both", alpha=0.3)
    right.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)
    print(f"wrote {sys.argv[2]}")


if __name__ == "__main__":
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
