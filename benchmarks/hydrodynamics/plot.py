"""Plot the CSV written by benchmark_hydrodynamics: time against bead count (log-log), with the
explicit-inverse peer and the baseline (non-AVX2) kernel where they were measured.

    .venv/bin/python benchmarks/hydrodynamics/plot.py results.csv results.png
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def column(rows, name):
    values = []
    for row in rows:
        try:
            value = float(row[name])
        except (KeyError, ValueError):
            value = math.nan
        values.append(value)
    return values


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot.py results.csv results.png")
    with open(sys.argv[1], newline="", encoding='utf-8') as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{sys.argv[1]} holds no measurements")
    beads = column(rows, "beads")
    threads = rows[0].get("threads", "?")
    kernel = rows[0].get("kernel", "?")
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    series = [("seconds", f"Cholesky solve ({kernel} kernel)", "o-"),
              ("baseline_kernel_seconds", "Cholesky solve (baseline kernel)", "s--"),
              ("peer_seconds", "explicit B.inverse() (source's method)", "^-")]
    for name, label, style in series:
        points = [(n, t) for n, t in zip(beads, column(rows, name)) if not math.isnan(t)]
        if points:
            left.plot(*zip(*points), style, label=label)
    left.set_xscale("log")
    left.set_yscale("log")
    left.set_xlabel("beads")
    left.set_ylabel("seconds")
    left.set_title(f"Resistance tensor of a bead shell ({threads} threads)")
    left.grid(True, which="both", alpha=0.3)
    left.legend()
    for name, label, style in [("peak_mib", "Cholesky solve", "o-"), ("peer_peak_mib", "explicit inverse", "^-")]:
        points = [(n, m) for n, m in zip(beads, column(rows, name)) if not math.isnan(m)]
        if points:
            right.plot(*zip(*points), style, label=label)
    right.set_xscale("log")
    right.set_yscale("log")
    right.set_xlabel("beads")
    right.set_ylabel("peak memory (MiB)")
    right.set_title("Peak resident memory")
    right.grid(True, which="both", alpha=0.3)
    right.legend()
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)
    print(f"wrote {sys.argv[2]}")


if __name__ == "__main__":
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
