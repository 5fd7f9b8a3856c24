#!/usr/bin/env python3
"""Plots the CSV of `pvrt accuracy` (pvrt runs it for --plot).

Usage: plot_accuracy.py RESULTS.csv OUT.png [--title TITLE]

Panels, as the CSV has rows for them:
  samples  RMSE against render time, log-log, one curve per sample pattern, each point
           labelled with its c; the equal-time reading (a vertical line at the latest time
           every curve reaches, with each curve's error there) and the equal-error reading
           (a horizontal line at the smallest error every curve reaches, with the time each
           needs) are marked, interpolated in log-log space as pvrt prints them.
  depth    RMSE against max_trace_level.
  quality  the quality variant: time and RMSE against the thread count P (c = c0 x P).
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402,F401

FLOOR = 1e-3  # an exact match (RMSE 0) is drawn here on the log axis


def interpolate(points, x, key_x, key_y):
    """y at x along points sorted by key_x, linear in log-log; None outside."""
    pts = sorted(points, key=lambda p: p[key_x])
    for a, b in zip(pts, pts[1:]):
        lo, hi = sorted((a[key_x], b[key_x]))
        if lo <= x <= hi:
            la, lb = math.log(max(a[key_x], 1e-12)), math.log(max(b[key_x], 1e-12))
            t = 0.0 if lb == la else (math.log(max(x, 1e-12)) - la) / (lb - la)
            ya, yb = math.log(max(a[key_y], 1e-12)), math.log(max(b[key_y], 1e-12))
            return math.exp(ya + t * (yb - ya))
    return None


def time_at_error(curve, error):
    """First time the curve (in time order) comes down to error."""
    pts = sorted(curve, key=lambda p: p[0])
    for i, p in enumerate(pts):
        if p[1] <= error:
            if i == 0:
                return p[0] if p[1] == error else None
            return interpolate([pts[i - 1], p], error, 1, 0)
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    args = ap.parse_args()
    with open(args.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    modes = [m for m in ("samples", "depth", "quality") if any(r["mode"] == m for r in rows)]
    if not modes:
        sys.exit("plot_accuracy: no rows in " + args.csv)
    fig, axes = plt.subplots(1, len(modes), figsize=(6.5 * len(modes), 5), squeeze=False)
    for ax, mode in zip(axes[0], modes):
        sub = [r for r in rows if r["mode"] == mode]
        if mode == "samples":
            plot_samples(ax, sub)
        elif mode == "depth":
            ax.plot([int(r["depth"]) for r in sub], [max(float(r["rmse"]), FLOOR) for r in sub], "o-")
            ax.set_yscale("log")
            ax.set_xlabel("max_trace_level")
            ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
            ax.set_ylabel("RMSE (8-bit levels)")
            ax.set_title("trace depth ({} c={})".format(sub[0]["sampler"], sub[0]["spp"]))
            ax.grid(True, which="both", alpha=0.3)
        else:
            p = [int(r["threads"]) for r in sub]
            ax.plot(p, [float(r["seconds"]) for r in sub], "o-", label="time (s)")
            ax.set_xlabel("threads P (c = c0 x P, nearest square)")
            ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
            ax.set_ylabel("render time (s)")
            for r in sub:
                ax.annotate("c={}".format(r["spp"]), (int(r["threads"]), float(r["seconds"])), fontsize=8,
                            textcoords="offset points", xytext=(4, 4))
            ax2 = ax.twinx()
            ax2.plot(p, [float(r["rmse"]) for r in sub], "s--", color="tab:red", label="RMSE")
            ax2.set_ylabel("RMSE (8-bit levels)", color="tab:red")
            ax.set_title("quality variant (c/P constant)")
            ax.grid(True, alpha=0.3)
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.png, dpi=110)


def plot_samples(ax, sub):
    curves = {}
    for r in sub:
        curves.setdefault(r["sampler"], []).append((float(r["seconds"]), float(r["rmse"]), r["spp"]))
    for name, pts in curves.items():
        pts.sort()
        line, = ax.plot([p[0] for p in pts], [max(p[1], FLOOR) for p in pts], "o-", label=name)
        for t, e, c in pts:
            ax.annotate("c={}".format(c), (t, max(e, FLOOR)), fontsize=7, textcoords="offset points",
                        xytext=(3, 3), color=line.get_color())
    golden = [r for r in sub if r["sampler"] == "pov" and r.get("golden_rmse")]
    if golden:
        pts = sorted((float(r["seconds"]), max(float(r["golden_rmse"]), FLOOR)) for r in golden)
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "x:", color="grey", label="pov vs POV-Ray image")
    if len(curves) >= 2:
        t_eq = min(max(p[0] for p in pts) for pts in curves.values())
        e_eq = max(min(p[1] for p in pts) for pts in curves.values())
        ax.axvline(t_eq, color="black", linestyle="--", linewidth=0.8, label="equal time {:.3g} s".format(t_eq))
        ax.axhline(max(e_eq, FLOOR), color="black", linestyle=":", linewidth=0.8,
                   label="equal error {:.3g}".format(e_eq))
        for name, pts in curves.items():
            e = interpolate([(p[0], p[1]) for p in pts], t_eq, 0, 1)
            if e is not None:
                ax.plot([t_eq], [max(e, FLOOR)], "D", color="black", markersize=5)
            t = time_at_error([(p[0], p[1]) for p in pts], e_eq)
            if t is not None:
                ax.plot([t], [max(e_eq, FLOOR)], "s", color="black", markersize=5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("render time (s)")
    ax.set_ylabel("RMSE against the reference (8-bit levels)")
    ax.set_title("error vs time by sample pattern")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)


if __name__ == "__main__":
    main()
