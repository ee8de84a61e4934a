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


def read_rows(script):
    """The rows of the CSV named by the first argument (the second names the PNG to write)."""
    if len(sys.argv) != 3:
        sys.exit(f"usage: {script} results.csv results.png")
    with open(sys.argv[1], newline="", encoding='utf-8') as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{sys.argv[1]} holds no measurements")
    return rows


def log_axes(axes, xlabel, ylabel, title):
    """Log-log axes with their labels, a grid and a legend."""
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel(xlabel)
    axes.set_ylabel(ylabel)
    axes.set_title(title)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


def series(rows, epsilon, name):
    points = [(number(r, "blobs"), number(r, name)) for r in rows if number(r, "epsilon") == epsilon]
    return [p for p in points if not math.isnan(p[1])]


def main():
    rows = read_rows("plot_pse.py")
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
    log_axes(left, "blobs (5% volume fraction)", "milliseconds", f"Periodic RPY mobility ({threads} threads)")
    log_axes(right, "blobs", "peak resident memory (MiB)", "Peak memory of the measuring process")
    save(fig, sys.argv[2])


if __name__ == "__main__":
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
