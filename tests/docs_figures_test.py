#!/usr/bin/env python3
"""The README's statistical figures against the runs of the README's own commands.

Usage: docs_figures_test.py README.md OUTPUTS [--shift WHAT DELTA]

OUTPUTS holds the `out/` folder the README's command blocks wrote (readme_snippets_test.py keeps
its convergence.json files there when PENUMBRA_SNIPPETS_KEEP names it). Each figure the README
states is found in its text by a pattern and recomputed from those runs, with its standard error
from the spread over the runs' seeds; a stated figure further from the run than three standard
errors plus half a unit of its last digit fails the test, which prints every figure either way.
With --shift, the figure WHAT (as printed) is taken as the README's plus DELTA, as if changed by
hand: the test then passes when that figure, and only that one, fails.
"""
import json
import math
import os
import re
import sys

from figure_checks import report


def load(outputs, folder):
    path = os.path.join(outputs, folder, "convergence.json")
    if not os.path.isfile(path):
        raise SystemExit(f"{path} is missing: the README's commands must have run first "
                         "(readme_snippets_test.py with PENUMBRA_SNIPPETS_KEEP set; ctest runs it before this test)")
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def series(study, name, strategy=None):
    """The sampler's (and strategy's) entry of a convergence.json."""
    for s in study["samplers"]:
        if s["sampler"] == name and (strategy is None or s["strategy"] == strategy):
            return s
    raise SystemExit(f"no {name} {strategy or ''} series in the study")


def rung(entry, spp):
    """The mean MSE over the seeds at a rung, and its standard error."""
    index = [r["spp"] for r in entry["rungs"]].index(spp)
    values = [run["mse"][index] for run in entry["runs"]]
    n = len(values)
    mean = sum(values) / n
    std = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1)) if n > 1 else float("inf")
    return mean, std / math.sqrt(n)


def slope(entry):
    runs = [run["slope"] for run in entry["runs"]]
    n = len(runs)
    mean = sum(runs) / n
    std = math.sqrt(sum((v - mean) ** 2 for v in runs) / (n - 1))
    return mean, std / math.sqrt(n), std


def ratio(a, b, power):
    """(a / b)^power of two means with standard errors, and the ratio's standard error."""
    value = (a[0] / b[0]) ** power
    return value, value * power * math.hypot(a[1] / a[0], b[1] / b[0])


def stated(text, pattern, what):
    m = re.search(pattern, text)
    if not m:
        raise SystemExit(f"README: the sentence with {what} is not found (pattern {pattern!r})")
    return m.groups()


def half_unit(figure):
    decimals = len(figure.split(".")[1]) if "." in figure else 0
    return 0.5 * 10 ** -decimals


def main():
    readme, outputs = sys.argv[1], sys.argv[2]
    shift = (sys.argv[4], float(sys.argv[5])) if len(sys.argv) == 6 and sys.argv[3] == "--shift" else None
    with open(readme, encoding="utf-8") as f:
        text = re.sub(r"\s+", " ", f.read())
    checks = []  # (what, stated text, measured, standard error)

    soft = load(outputs, "convergence-soft-shadows")
    independent, stratified = series(soft, "independent"), series(soft, "stratified")
    slope_i, slope_s = slope(independent), slope(stratified)
    s_independent, s_stratified, s_std, s_ratio = stated(
        text, r"slope (-?\d+\.\d+) \(MSE ~ 1/N\); the stratified sampler at (-?\d+\.\d+) \(over 3 seeds each, "
              r"\+-(\d+\.\d+)\), so at 256 spp its RMSE is (\d+\.\d+) times", "the convergence slopes")
    checks.append(("independent sampler's slope", s_independent, slope_i[0], slope_i[1]))
    checks.append(("stratified sampler's slope", s_stratified, slope_s[0], slope_s[1]))
    # The spread itself, known to about half its size from three seeds.
    checks.append(("stratified slope's spread over seeds", s_std, slope_s[2], 0.5 * slope_s[2]))
    r256 = ratio(rung(stratified, 256), rung(independent, 256), 0.5)
    checks.append(("RMSE ratio at 256 spp (stratified / independent)", s_ratio, *r256))
    (s_ratio64,) = stated(text, r"stratified sampler's RMSE at 64 spp is (\d+\.\d+) times", "the 64-spp ratio")
    r64 = ratio(rung(stratified, 64), rung(independent, 64), 0.5)
    checks.append(("RMSE ratio at 64 spp (stratified / independent)", s_ratio64, *r64))

    veach = load(outputs, "veach")
    mis, bsdf, light = (rung(series(veach, "stratified", s), 32) for s in ("mis", "bsdf", "light"))
    s_bsdf, s_light = stated(text, r"At 32 spp MIS has (\d+\.\d+) times less MSE than BSDF sampling alone and "
                                   r"(\d+\.\d+) times less than light sampling alone", "the MIS ratios")
    checks.append(("MSE of BSDF sampling over MIS at 32 spp", s_bsdf, *ratio(bsdf, mis, 1)))
    checks.append(("MSE of light sampling over MIS at 32 spp", s_light, *ratio(light, mis, 1)))

    return report([(what, figure, measured, 3 * error + half_unit(figure),
                    f"measured {measured:.4f} +- {error:.4f} (allowed {3 * error + half_unit(figure):.4f})")
                   for what, figure, measured, error in checks], shift)

if __name__ == "__main__":
    sys.exit(main())
