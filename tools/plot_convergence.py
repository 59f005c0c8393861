#!/usr/bin/python3
"""Plots a `penumbra converge` report: MSE against samples per pixel and against render time,
log-log, every sampler on the same axes, with the fitted slope in the legend and error bars of
one standard deviation over the seeds; with --adaptive, the adaptive runs too (dash-dotted,
against their mean samples per pixel).

Usage: /usr/bin/python3 tools/plot_convergence.py DIR/convergence.json DIR/convergence.png
(needs matplotlib: Debian's python3-matplotlib)."""

import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    with open(argv[1]) as f:
        report = json.load(f)

    fig, (by_spp, by_time) = plt.subplots(1, 2, figsize=(11, 4.4))
    colours = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown", "tab:pink", "tab:olive"]
    for i, sampler in enumerate(report["samplers"]):
        colour = colours[i % len(colours)]
        rungs = sampler["rungs"]
        spp = [r["spp"] for r in rungs]
        mse = [r["mse"] for r in rungs]
        err = [r["mse_std"] for r in rungs]
        seconds = [max(r["seconds"], 1e-4) for r in rungs]
        seeds = len(sampler["runs"])
        slope = sampler["slope"]
        label = f"{sampler['name']}: slope {slope:.2f}"
        if seeds > 1:
            label += f" \u00b1 {sampler['slope_std']:.2f} ({seeds} seeds)"
        by_spp.errorbar(spp, mse, yerr=err if seeds > 1 else None, color=colour, marker="o", ms=4, capsize=2,
                        label=label)
        # The fitted line: log MSE = slope * log spp + c, through the points' centroid.
        pts = [(math.log(s), math.log(m)) for s, m in zip(spp, mse) if m > 0]
        if len(pts) >= 2:
            cx = sum(p[0] for p in pts) / len(pts)
            cy = sum(p[1] for p in pts) / len(pts)
            xs = [spp[0], spp[-1]]
            by_spp.plot(xs, [math.exp(cy + slope * (math.log(x) - cx)) for x in xs], color=colour, ls="--", lw=1)
        by_time.errorbar(seconds, mse, yerr=err if seeds > 1 else None, color=colour, marker="o", ms=4, capsize=2,
                         label=sampler["name"])
        # --adaptive: the adaptive runs, at their mean samples per pixel and their time.
        adaptive = sorted(sampler.get("adaptive", {}).get("runs", []), key=lambda r: r["mean_spp"])
        if adaptive:
            label = f"{sampler['name']} adaptive"
            by_spp.plot([r["mean_spp"] for r in adaptive], [r["mse"] for r in adaptive], color=colour, marker="s",
                        ms=4, ls="-.", label=label + " (mean spp)")
            by_time.plot([max(r["seconds"], 1e-4) for r in adaptive], [r["mse"] for r in adaptive], color=colour,
                         marker="s", ms=4, ls="-.", label=label)

    floor = report["reference"].get("mse_floor", 0)
    for ax in (by_spp, by_time):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.set_ylabel("MSE against the reference")
        if floor > 0:
            ax.axhline(floor, color="grey", ls=":", lw=1)
    by_spp.set_xlabel("samples per pixel")
    by_time.set_xlabel("render time (s)")
    by_spp.legend(fontsize=8)
    by_time.legend(fontsize=8)

    ref = report["reference"]
    ref_text = f"reference {ref['spp']} spp" if ref["source"] == "rendered" else f"reference {ref['source']}"
    frozen = f", frozen: {report['frozen']}" if report.get("frozen") else ""
    w, h = report["resolution"]
    fig.suptitle(f"{report['scene']} at {w}x{h}, {ref_text}{frozen}", fontsize=10)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
