#!/usr/bin/env python3
"""The README's measured times against the benchmark results it quotes.

Usage: docs_quoted_figures_test.py ROOT [--shift WHAT DELTA]

Times cannot be re-measured by a test (the machines are shared and noisy): the benchmarks write
them to bench/results/ (bench/compare_pathtracer.py, bench/time_to_error.py), and the README
quotes those files. Each figure the README states about them is found in its text by a pattern
and must be the file's, to the README's last digit; a benchmark rerun that moves a figure, or a
figure changed by hand, fails until the other side follows. With --shift, the figure WHAT is taken
as the README's plus DELTA: the test then passes when that figure, and only that one, fails.
"""
import os
import re
import sys

from figure_checks import report


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def table_rows(markdown, title):
    """The rows (lists of cells) of the first table after the line that starts with `title`."""
    lines = markdown.splitlines()
    start = next((i for i, line in enumerate(lines) if line.startswith(title)), None)
    if start is None:
        raise SystemExit(f"no table titled {title!r}")
    rows, seen_table = [], False
    for line in lines[start + 1:]:
        if line.startswith("|"):
            seen_table = True
            rows.append([cell.strip() for cell in line.strip().strip("|").split("|")])
        elif seen_table:
            break
    return rows


def cell(rows, first, column):
    for row in rows:
        if row[0].startswith(first):
            return row[column]
    raise SystemExit(f"no row starting {first!r}")


def number(text, pattern=r"[-+]?\d+\.\d+"):
    m = re.search(pattern, text)
    if not m:
        raise SystemExit(f"no number in {text!r}")
    return float(m.group(0))


def stated(text, pattern, what):
    m = re.search(pattern, text)
    if not m:
        raise SystemExit(f"README: the sentence with {what} is not found (pattern {pattern!r})")
    return m.groups()


def main():
    root = sys.argv[1]
    shift = (sys.argv[3], float(sys.argv[4])) if len(sys.argv) == 5 and sys.argv[2] == "--shift" else None
    text = re.sub(r"\s+", " ", read(os.path.join(root, "README.md")))
    checks = []  # (what, stated text, the file's value)

    speed = read(os.path.join(root, "bench/results/pathtracer-comparison.md"))
    rows = table_rows(speed, "| figure |")
    wall, scaling, agreement = stated(
        text, r"penumbra takes (\d+\.\d+)x of `pathtracer`'s wall time .*? scales (\d+\.\d+)x from 1 to 2 threads, "
              r"and its image agrees with Embree's within (\d+\.\d+)% in mean", "the speed figures")
    checks.append(("wall time against Embree's pathtracer", wall, number(cell(rows, "wall time, median (s)", 3))))
    checks.append(("thread scaling", scaling,
                   number(cell(rows, "thread scaling 1 -> 2 against the two cores' own speeds", 1))))
    checks.append(("image mean against Embree's", agreement,
                   abs(number(cell(rows, "image mean, 8-bit domain", 3)))))

    tte = read(os.path.join(root, "bench/results/time-to-error.md"))
    at64 = table_rows(tte, "At the RMSE Cycles reaches with 64 spp")
    header = at64[0]
    image_column = header.index("adaptive (image RMSE) / Cycles")
    bokeh, caustic = stated(text, r"(\d+\.\d+)x of Cycles' time on the bokeh and (\d+\.\d+)x on the caustic",
                            "adaptive sampling against Cycles")
    checks.append(("adaptive (image RMSE) / Cycles, bokeh", bokeh, number(cell(at64, "dof", image_column))))
    checks.append(("adaptive (image RMSE) / Cycles, caustic", caustic,
                   number(cell(at64, "caustic", image_column))))

    relative = table_rows(tte, "penumbra adaptive against penumbra fixed")
    absolute = table_rows(tte, "penumbra adaptive (image RMSE) against penumbra fixed")
    columns = {spp: relative[0].index(f"{spp} spp") for spp in (64, 128, 256)}

    def wall_and_spp(rows, spp):
        text = cell(rows, "penumbrae", columns[spp])
        return number(text), number(text, r"(?<=spp )\d+\.\d+"), number(text, r"(?<=\()\d+\.\d+")

    both = [wall_and_spp(rows, spp) for rows in (relative, absolute) for spp in (128, 256)]
    t_low, t_high, s_low, s_high = stated(
        text, r"\(at 128 and 256 spp: (\d+\.\d+)x-(\d+\.\d+)x of the fixed render's time at its RMSE, "
              r"(\d+\.\d+)x-(\d+\.\d+)x of its samples\)", "adaptive against fixed sampling")
    checks.append(("adaptive / fixed time, fewest", t_low, min(w for w, _, _ in both)))
    checks.append(("adaptive / fixed time, most", t_high, max(w for w, _, _ in both)))
    checks.append(("adaptive / fixed samples, fewest", s_low, min(s for _, s, _ in both)))
    checks.append(("adaptive / fixed samples, most", s_high, max(s for _, s, _ in both)))
    stated_spp = stated(text, r"adaptive needs (\d+\.\d+)x, (\d+\.\d+)x, (\d+\.\d+)x the samples", "the samples")
    stated_cpu = stated(text, r"the samples and (\d+\.\d+)x, (\d+\.\d+)x, (\d+\.\d+)x the CPU time", "the CPU times")
    for spp, s, c in zip((64, 128, 256), stated_spp, stated_cpu):
        _, samples, cpu = wall_and_spp(relative, spp)
        checks.append((f"adaptive / fixed samples at {spp} spp", s, samples))
        checks.append((f"adaptive / fixed CPU time at {spp} spp", c, cpu))

    return report([(what, figure, measured, 0.5 * 10 ** -len(figure.split(".")[1]) + 1e-12,
                    f"results file {measured:g}") for what, figure, measured in checks], shift)

if __name__ == "__main__":
    sys.exit(main())
