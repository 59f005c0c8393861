#!/usr/bin/python3
"""penumbra against the path tracer Intel ships with Embree (`pathtracer`, package embree-tools),
side by side on Embree's Cornell box (scenes/bench/cornell-embree.json is the same scene in our
format). One command, run with Debian's Python (it needs python3-numpy and python3-openimageio):

    /usr/bin/python3 bench/compare_pathtracer.py [--build-dir build-bench] [--reps 3]

It
  1. builds penumbra and penumbra_ray_throughput in Release (cmake, Ninja);
  2. times `penumbra render` and `pathtracer` alternately, A B A B ... (--reps of each, after one
     untimed warm-up of each), under /usr/bin/time -v (wall time and peak resident memory);
  3. compares the images in Embree's output domain: its .ppm is linear radiance clamped to [0, 1]
     and truncated to 8 bits (255.01 * v), so our EXR is clamped and quantized the same way;
  4. measures thread scaling, 1 against 2 threads, for both programs: each repetition runs one
     thread on core 0, one thread on core 1 and two threads on both, and the 2-thread time is
     compared with the ideal of those two cores (the cores of a shared VM often differ in speed);
  5. runs penumbra_ray_throughput: the render's rays per second against bare Embree
     (rtcIntersect1 / rtcOccluded1) retracing a recorded sample of the render's own rays;
  6. writes bench/results/pathtracer-comparison.json and .md and prints the table.

The timed runs are the plain commands, as a user would run them: `penumbra render SCENE -o X.exr
--no-display` (no display PNG: Embree writes only its .ppm) and `pathtracer -c cornell_box.ecs
--size 512 512 --spp 64 --max-path-length 8 -o X.ppm`; both use every core by default. Wall
times include loading the scene, building the acceleration structure and writing the image.
"""

import argparse
import datetime
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np
import OpenImageIO as oiio

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(REPO, "scenes", "bench", "cornell-embree.json")
EMBREE_MODELS = "/usr/share/doc/embree3/models"
ECS = os.path.join(EMBREE_MODELS, "cornell_box.ecs")
WIDTH = HEIGHT = 512
SPP = 64
PATH_LENGTH = 8


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def run(cmd, cwd=None, check=True):
    proc = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if check and proc.returncode != 0:
        raise SystemExit(f"command failed ({proc.returncode}): {' '.join(cmd)}\n{proc.stdout}\n{proc.stderr}")
    return proc


def build(build_dir, jobs):
    log(f"building Release in {build_dir}")
    run(["cmake", "-S", REPO, "-B", build_dir, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
         "-DPENUMBRA_BUILD_BENCHMARKS=ON"])
    run(["cmake", "--build", build_dir, "--target", "penumbra", "penumbra_ray_throughput", "-j", str(jobs)])


def parse_time_v(stderr):
    """Peak RSS (MiB), user and system seconds from GNU time -v."""
    out = {}
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", stderr)
    out["peak_rss_mib"] = int(m.group(1)) / 1024.0 if m else None
    m = re.search(r"User time \(seconds\): ([\d.]+)", stderr)
    out["user_s"] = float(m.group(1)) if m else None
    m = re.search(r"System time \(seconds\): ([\d.]+)", stderr)
    out["sys_s"] = float(m.group(1)) if m else None
    return out


def timed(cmd, cwd, cores=None):
    """Runs cmd under /usr/bin/time -v (on the given CPU cores only, when given); returns wall
    seconds, peak RSS, CPU seconds and stdout."""
    pin = (lambda: os.sched_setaffinity(0, cores)) if cores is not None else None
    start = time.perf_counter()
    proc = subprocess.run(["/usr/bin/time", "-v"] + cmd, cwd=cwd, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, preexec_fn=pin)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        raise SystemExit(f"command failed ({proc.returncode}): {' '.join(cmd)}\n{proc.stdout}\n{proc.stderr}")
    r = parse_time_v(proc.stderr)
    r["wall_s"] = wall
    cpu = (r["user_s"] or 0) + (r["sys_s"] or 0)
    r["cpu_utilization"] = cpu / wall if wall > 0 else None
    r["stdout"] = proc.stdout
    return r


def penumbra_cmd(binary, out_exr, threads=None):
    cmd = [binary, "render", SCENE, "-o", out_exr, "--no-display"]
    if threads:
        cmd += ["--threads", str(threads)]
    return cmd


def pathtracer_cmd(out_ppm, threads=None):
    cmd = ["pathtracer", "-c", ECS, "--size", str(WIDTH), str(HEIGHT), "--spp", str(SPP),
           "--max-path-length", str(PATH_LENGTH), "-o", out_ppm]
    if threads:
        cmd += ["--threads", str(threads)]
    return cmd


def parse_penumbra_summary(stdout):
    r = {}
    m = re.search(r"in ([\d.]+) s \(scene build ([\d.]+) s\)", stdout)
    if m:
        r["render_s"] = float(m.group(1))
        r["build_s"] = float(m.group(2))
    m = re.search(r"([\d.]+) M samples/s, ([\d.]+) M rays/s \((\d+) camera, (\d+) bounce, (\d+) shadow", stdout)
    if m:
        r["msamples_per_s"] = float(m.group(1))
        r["mrays_per_s"] = float(m.group(2))
        r["rays"] = {"camera": int(m.group(3)), "bounce": int(m.group(4)), "shadow": int(m.group(5))}
    return r


def median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def alternate(programs, reps, cwd, warmup=True):
    """A B (C) A B (C) ... reps times each, for programs [(label, cmd), ...]; returns {label: [results]}."""
    results = {label: [] for label, _ in programs}
    if warmup:
        log("warm-up: " + ", ".join(label for label, _ in programs))
        for _, cmd in programs:
            timed(cmd, cwd)
    for i in range(reps):
        for label, cmd in programs:
            r = timed(cmd, cwd)
            results[label].append(r)
            log(f"  {label} #{i + 1}: {r['wall_s']:.2f} s wall, {r['peak_rss_mib']:.1f} MiB peak, "
                f"CPU {r['cpu_utilization']:.2f}")
    return results


def scaling_runs(label, cmd_1, cmd_2, reps, cwd):
    """Thread scaling on the first two cores this process may use ("core 0" and "core 1" below):
    each repetition runs cmd_1 (one thread) on core 0, then on core 1, then cmd_2 (two threads) on
    both. Returns {"1": [...], "2": [...]}, the 1-thread runs in the order core 0, core 1 of each
    repetition."""
    first, second = sorted(os.sched_getaffinity(0))[:2]
    results = {"1": [], "2": []}
    for i in range(reps):
        for threads, cmd, cores in (("1", cmd_1, {first}), ("1", cmd_1, {second}), ("2", cmd_2, {first, second})):
            r = timed(cmd, cwd, cores)
            results[threads].append(r)
            log(f"  {label} {threads} thread(s) on cores {sorted(cores)} #{i + 1}: {r['wall_s']:.2f} s wall, "
                f"CPU {r['cpu_utilization']:.2f}")
    return results


def core_corrected_speedups(one, two):
    """Per repetition, the 2-thread run's speed against the ideal of its two cores: with the
    1-thread times a and b on cores 0 and 1, two threads would at best take 1 / (1/a + 1/b); the
    figure is 2 * that / the 2-thread time, which is a / t2 when the cores are equal. (The cores of
    a shared VM are not: one is often a quarter slower than the other for minutes, and a plain
    1-thread / 2-thread ratio then says which core the 1-thread run landed on.) Only repetitions
    whose runs all had their cores (CPU use >= 0.9 per thread) count."""
    speedups = []
    for i, t2 in enumerate(two):
        a, b = one[2 * i], one[2 * i + 1]
        if min(a["cpu_utilization"] or 0, b["cpu_utilization"] or 0) < 0.9 or (t2["cpu_utilization"] or 0) < 1.8:
            continue
        ideal = 1.0 / (1.0 / a["wall_s"] + 1.0 / b["wall_s"])
        speedups.append(2.0 * ideal / t2["wall_s"])
    return speedups


def read_image(path):
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise SystemExit(f"cannot read {path}: {oiio.geterror()}")
    spec = inp.spec()
    pixels = inp.read_image(format="float")
    inp.close()
    return np.asarray(pixels, dtype=np.float64).reshape(spec.height, spec.width, spec.nchannels)[:, :, :3]


def to_embree_domain(linear):
    """Embree's tutorial framebuffer: (unsigned)(255.01 * clamp(v, 0, 1))."""
    return np.floor(255.01 * np.clip(linear, 0.0, 1.0)).astype(np.float64)


def compare_images(ours_exr, embree_ppm, diff_png=None):
    ours = to_embree_domain(read_image(ours_exr))
    # The PPM is read back as 8-bit values v / 255 by OpenImageIO.
    emb = np.round(read_image(embree_ppm) * 255.0)
    if ours.shape != emb.shape:
        raise SystemExit(f"image sizes differ: {ours.shape} vs {emb.shape}")
    mean_ours = ours.mean(axis=(0, 1))
    mean_emb = emb.mean(axis=(0, 1))
    rel = lambda a, b: float(a / b - 1.0) if b > 0 else None
    # Orientation check: the unflipped comparison must be the best of the four.
    orientations = {}
    for name, img in (("as is", ours), ("flipped vertically", ours[::-1]), ("mirrored", ours[:, ::-1]),
                      ("rotated 180", ours[::-1, ::-1])):
        orientations[name] = float(np.abs(img - emb).mean() / 255.0)
    # 8x8 block means take most of the Monte Carlo noise out and leave systematic differences.
    h, w = (ours.shape[0] // 8) * 8, (ours.shape[1] // 8) * 8
    block = lambda img: img[:h, :w].reshape(h // 8, 8, w // 8, 8, 3).mean(axis=(1, 3))
    blocks_ours, blocks_emb = block(ours), block(emb)
    r = {
        "domain": "8-bit, floor(255.01 * clamp(linear, 0, 1)), as Embree writes its .ppm",
        "mean_ours": float(mean_ours.mean()),
        "mean_embree": float(mean_emb.mean()),
        "mean_relative_difference": rel(mean_ours.mean(), mean_emb.mean()),
        "mean_per_channel_ours": [float(v) for v in mean_ours],
        "mean_per_channel_embree": [float(v) for v in mean_emb],
        "mean_relative_difference_per_channel": [rel(a, b) for a, b in zip(mean_ours, mean_emb)],
        "mean_absolute_pixel_difference": float(np.abs(ours - emb).mean() / 255.0),
        "mean_absolute_difference_8x8_blocks": float(np.abs(blocks_ours - blocks_emb).mean() / 255.0),
        "clamped_fraction_ours": float((ours >= 255).mean()),
        "clamped_fraction_embree": float((emb >= 255).mean()),
        "orientation_mean_abs_difference": orientations,
        "orientation_ok": min(orientations, key=orientations.get) == "as is",
    }
    if diff_png:
        # ours | Embree | |difference| x 4, for a look.
        diff = np.clip(np.abs(ours - emb) * 4.0, 0, 255)
        strip = np.concatenate([ours, emb, diff], axis=1).astype(np.uint8)
        out = oiio.ImageOutput.create(diff_png)
        out.open(diff_png, oiio.ImageSpec(strip.shape[1], strip.shape[0], 3, "uint8"))
        out.write_image(strip)
        out.close()
        r["side_by_side_png"] = diff_png
    return r


def repo_relative(value):
    """The results with paths inside the repository written relative to it (the files are committed)."""
    if isinstance(value, dict):
        return {k: repo_relative(v) for k, v in value.items()}
    if isinstance(value, list):
        return [repo_relative(v) for v in value]
    if isinstance(value, str) and value.startswith(REPO + os.sep):
        return os.path.relpath(value, REPO)
    return value


def machine_info():
    info = {"nproc": os.cpu_count(), "platform": platform.platform()}
    try:
        with open("/proc/cpuinfo") as f:
            m = re.search(r"model name\s*:\s*(.*)", f.read())
            info["cpu"] = m.group(1).strip() if m else None
    except OSError:
        pass
    try:
        with open("/etc/os-release") as f:
            m = re.search(r'PRETTY_NAME="([^"]*)"', f.read())
            info["os"] = m.group(1) if m else None
    except OSError:
        pass
    try:
        with open("/proc/meminfo") as f:
            m = re.search(r"MemTotal:\s*(\d+)", f.read())
            info["memory_gib"] = round(int(m.group(1)) / 1024 / 1024, 1) if m else None
    except OSError:
        pass
    proc = run(["dpkg-query", "-W", "-f", "${Version}", "embree-tools"], check=False)
    info["embree_tools_version"] = proc.stdout.strip() or None
    return info


def loadavg():
    try:
        return [float(x) for x in open("/proc/loadavg").read().split()[:3]]
    except OSError:
        return None


def fmt(v, spec=".2f", suffix=""):
    return "n/a" if v is None else f"{format(v, spec)}{suffix}"


def pct(v):
    return "n/a" if v is None else f"{100.0 * v:+.2f}%"


def markdown(res):
    t = res["timing"]
    img = res["image"]
    sc = res.get("thread_scaling", {})
    rays = res.get("rays", {})
    m = res["machine"]
    lines = []
    lines.append(f"Measured {res['date']} on {m.get('cpu')} ({m.get('nproc')} cores, {m.get('memory_gib')} GiB), "
                 f"{m.get('os')}, Embree {m.get('embree_tools_version')}; load average "
                 f"{res['load_before']} before, {res['load_after']} after"
                 f"{' (the machine was busy: other jobs shared the cores)' if res['busy'] else ''}.")
    lines.append(f"Scene: Embree's Cornell box, {WIDTH}x{HEIGHT}, {SPP} spp, path length {PATH_LENGTH} "
                 f"(penumbra max_depth {PATH_LENGTH}); {t['reps']} alternating runs of each.")
    lines.append("")
    lines.append("| figure | penumbra | Embree pathtracer | ratio / result | target |")
    lines.append("|---|---|---|---|---|")
    p, e = t["penumbra"], t["pathtracer"]
    ratio = t["median_wall_ratio"]
    lines.append(f"| wall time, median (s) | {fmt(p['median_wall_s'])} | {fmt(e['median_wall_s'])} | "
                 f"**{fmt(ratio, '.2f', 'x')}** | <= 1.0x (stretch 0.8x) |")
    lines.append(f"| wall time, median of the pairwise ratios (A run / the B run after it) | | | "
                 f"{fmt(t.get('median_pairwise_wall_ratio'), '.2f', 'x')} | |")
    if "baseline" in t:
        b = t["baseline"]
        lines.append(f"| baseline penumbra (--baseline-binary): wall time, median (s) | {fmt(b['median_wall_s'])} | | "
                     f"{fmt(t['baseline_wall_ratio_to_pathtracer'], '.2f', 'x')} of pathtracer; this build "
                     f"{fmt(t['median_wall_ratio_to_baseline'], '.3f', 'x')} of the baseline's wall time, "
                     f"{fmt(t.get('median_render_ratio_to_baseline'), '.3f', 'x')} of its render time | |")
    lines.append(f"| wall times (s) | {', '.join(fmt(x) for x in p['wall_s'])} | "
                 f"{', '.join(fmt(x) for x in e['wall_s'])} | | |")
    lines.append(f"| CPU time, user + system (s, median) | {fmt(p['median_cpu_s'])} | {fmt(e['median_cpu_s'])} | "
                 f"{fmt(t.get('median_cpu_ratio'), '.2f', 'x')} | |")
    lines.append(f"| CPU use (cores busy, median) | {fmt(p['median_cpu_utilization'])} | "
                 f"{fmt(e['median_cpu_utilization'])} | | |")
    lines.append(f"| penumbra render time alone (s, median) | {fmt(p.get('median_render_s'))} | | "
                 f"scene build {fmt(p.get('median_build_s'), '.3f')} s | |")
    lines.append(f"| peak resident memory (MiB, median) | {fmt(p['median_peak_rss_mib'], '.1f')} | "
                 f"{fmt(e['median_peak_rss_mib'], '.1f')} | {fmt(t.get('peak_rss_ratio'), '.2f', 'x')} | |")
    lines.append(f"| image mean, 8-bit domain | {fmt(img['mean_ours'], '.3f')} | {fmt(img['mean_embree'], '.3f')} | "
                 f"**{pct(img['mean_relative_difference'])}** | within 1% |")
    ch = img["mean_relative_difference_per_channel"]
    lines.append(f"| image mean R / G / B | {' / '.join(fmt(v, '.2f') for v in img['mean_per_channel_ours'])} | "
                 f"{' / '.join(fmt(v, '.2f') for v in img['mean_per_channel_embree'])} | "
                 f"{' / '.join(pct(v) for v in ch)} | |")
    lines.append(f"| mean absolute difference per pixel (of 1.0) | | | {fmt(img['mean_absolute_pixel_difference'], '.4f')} "
                 f"(8x8 blocks: {fmt(img['mean_absolute_difference_8x8_blocks'], '.4f')}) | noise |")
    if sc:
        ps, es = sc.get("penumbra", {}), sc.get("pathtracer", {})
        lines.append(f"| 1 thread, median wall (s): all / core 0 / core 1 | "
                     f"{fmt(ps.get('median_wall_1_s'))} / {fmt(ps.get('median_wall_1_core0_s'))} / {fmt(ps.get('median_wall_1_core1_s'))} | "
                     f"{fmt(es.get('median_wall_1_s'))} / {fmt(es.get('median_wall_1_core0_s'))} / {fmt(es.get('median_wall_1_core1_s'))} | | |")
        lines.append(f"| 2 threads, median wall (s) | {fmt(ps.get('median_wall_2_s'))} | {fmt(es.get('median_wall_2_s'))} | | |")
        lines.append(f"| thread scaling 1 -> 2, wall, ratio of medians | {fmt(ps.get('speedup_wall'), '.2f', 'x')} | "
                     f"{fmt(es.get('speedup_wall'), '.2f', 'x')} | | |")
        lines.append(f"| thread scaling 1 -> 2, render time alone, ratio of medians | {fmt(ps.get('speedup_render'), '.2f', 'x')} | | | |")
        np_, ne_ = len(ps.get("core_corrected_speedups", [])), len(es.get("core_corrected_speedups", []))
        lines.append(f"| thread scaling 1 -> 2 against the two cores' own speeds, median (repetitions) | "
                     f"**{fmt(ps.get('speedup_core_corrected'), '.2f', 'x')}** ({np_}) | "
                     f"{fmt(es.get('speedup_core_corrected'), '.2f', 'x')} ({ne_}) | | >= 1.9x |")
    if rays:
        lines.append(f"| render rays/s (M, median, in-process render()) | {fmt(rays.get('median_render_mrays_per_s'))} | | | |")
        lines.append(f"| bare Embree on the same rays via EmbreeAccelerator (M/s) | "
                     f"{fmt(rays.get('median_bare_accelerator_mrays_per_s'))} | | "
                     f"**{fmt(rays.get('render_over_bare_accelerator'), '.1%') if rays.get('render_over_bare_accelerator') is not None else 'n/a'}** "
                     f"of bare | >= 60% |")
        lines.append(f"| bare Embree on the same rays, plain scene (M/s) | "
                     f"{fmt(rays.get('median_bare_plain_embree_mrays_per_s'))} | | "
                     f"{fmt(rays.get('render_over_bare_plain_embree'), '.1%') if rays.get('render_over_bare_plain_embree') is not None else 'n/a'} of bare | |")
        rob = rays.get("bare_plain_embree_robust_mrays_per_s")
        if rob:
            lines.append(f"| bare Embree on the same rays, plain scene with RTC_SCENE_FLAG_ROBUST (M/s, median) | "
                         f"{fmt(median(rob))} | | | |")
        rnd = rays.get("random_rays_plain_embree_mrays_per_s")
        if rnd:
            lines.append(f"| bare Embree, random rays, plain scene (M/s, median) | {fmt(median(rnd))} | | | |")
        hist = rays.get("bounce_rays_per_path_histogram")
        if hist and rays.get("recorded_rays"):
            lines.append(f"| bounce rays past the last vertex (emission only; Embree's pathtracer traces none) | "
                         f"{fmt(100.0 * hist[-1] / rays['recorded_rays'], '.1f', '%')} of the render's rays | | | |")
        lines.append(f"| replay traces the render's rays (crop counts equal) | {rays.get('replay_verified')} | | | |")
        pr = rays.get("penumbra_cli_mrays_per_s")
        if pr:
            lines.append(f"| rays/s printed by the timed `penumbra render` runs (M, median) | {fmt(median(pr))} | | | |")
    lines.append(f"| Cycles | {res.get('cycles')} | | | optional |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default=os.path.join(REPO, "build-bench"))
    ap.add_argument("--no-build", action="store_true", help="use the binaries already in --build-dir")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--reps", type=int, default=3, help="timed runs of each program (>= 3)")
    ap.add_argument("--scaling-reps", type=int, default=None, help="scaling repetitions (default: --reps)")
    ap.add_argument("--skip-scaling", action="store_true")
    ap.add_argument("--skip-rays", action="store_true")
    ap.add_argument("--results", default=os.path.join(REPO, "bench", "results"))
    ap.add_argument("--work-dir", default=None, help="images and logs (default: BUILD_DIR/compare-pathtracer)")
    ap.add_argument("--baseline-binary", default=None,
                    help="another penumbra (e.g. an earlier commit's build) timed in the same alternation")
    args = ap.parse_args()
    if args.reps < 3:
        ap.error("--reps must be at least 3")
    build_dir = os.path.abspath(args.build_dir)
    work = os.path.abspath(args.work_dir or os.path.join(build_dir, "compare-pathtracer"))

    if not shutil.which("pathtracer"):
        raise SystemExit("Embree's pathtracer is not on PATH (Debian package embree-tools)")
    if not os.path.exists(ECS):
        raise SystemExit(f"missing {ECS} (Debian package embree-tools)")
    if not os.path.exists("/usr/bin/time"):
        raise SystemExit("missing /usr/bin/time (Debian package time)")

    load_before = loadavg()
    if not args.no_build:
        build(build_dir, args.jobs)
    penumbra = os.path.join(build_dir, "tools", "penumbra")
    ray_tool = os.path.join(build_dir, "bench", "penumbra_ray_throughput")
    os.makedirs(work, exist_ok=True)
    ours_exr = os.path.join(work, "penumbra.exr")
    emb_ppm = os.path.join(work, "embree.ppm")

    res = {"date": datetime.datetime.now().isoformat(timespec="seconds"), "machine": machine_info(),
           "load_before": load_before,
           "commands": {"penumbra": " ".join(penumbra_cmd("tools/penumbra", "OUT.exr")).replace(REPO + "/", ""),
                        "pathtracer": " ".join(pathtracer_cmd("OUT.ppm"))}}

    # 1. Wall time, A B A B.
    log("timing penumbra (A) against pathtracer (B)")
    programs = [("penumbra", penumbra_cmd(penumbra, ours_exr)), ("pathtracer", pathtracer_cmd(emb_ppm))]
    if args.baseline_binary:
        programs.append(("baseline", penumbra_cmd(os.path.abspath(args.baseline_binary),
                                                  os.path.join(work, "baseline.exr"))))
    runs = alternate(programs, args.reps, work)
    timing = {"reps": args.reps}
    for label, _ in programs:
        rs = runs[label]
        entry = {
            "wall_s": [r["wall_s"] for r in rs],
            "median_wall_s": median([r["wall_s"] for r in rs]),
            "peak_rss_mib": [r["peak_rss_mib"] for r in rs],
            "median_peak_rss_mib": median([r["peak_rss_mib"] for r in rs]),
            "cpu_utilization": [r["cpu_utilization"] for r in rs],
            "median_cpu_utilization": median([r["cpu_utilization"] for r in rs]),
            "cpu_s": [(r["user_s"] or 0) + (r["sys_s"] or 0) for r in rs],
        }
        entry["median_cpu_s"] = median(entry["cpu_s"])
        if label in ("penumbra", "baseline"):
            summaries = [parse_penumbra_summary(r["stdout"]) for r in rs]
            entry["render_s"] = [s.get("render_s") for s in summaries]
            entry["median_render_s"] = median(entry["render_s"])
            entry["median_build_s"] = median([s.get("build_s") for s in summaries])
            entry["mrays_per_s"] = [s.get("mrays_per_s") for s in summaries]
            entry["rays"] = summaries[-1].get("rays")
        timing[label] = entry
    timing["median_wall_ratio"] = timing["penumbra"]["median_wall_s"] / timing["pathtracer"]["median_wall_s"]
    # Each A run and the B run right after it shared the machine's state: the median of these
    # pairwise ratios is steadier than the ratio of medians when the load changes.
    timing["pairwise_wall_ratios"] = [a / b for a, b in zip(timing["penumbra"]["wall_s"], timing["pathtracer"]["wall_s"])]
    timing["median_pairwise_wall_ratio"] = median(timing["pairwise_wall_ratios"])
    timing["median_cpu_ratio"] = timing["penumbra"]["median_cpu_s"] / timing["pathtracer"]["median_cpu_s"]
    timing["peak_rss_ratio"] = timing["penumbra"]["median_peak_rss_mib"] / timing["pathtracer"]["median_peak_rss_mib"]
    if "baseline" in timing:
        b = timing["baseline"]
        timing["baseline_wall_ratio_to_pathtracer"] = b["median_wall_s"] / timing["pathtracer"]["median_wall_s"]
        timing["median_wall_ratio_to_baseline"] = timing["penumbra"]["median_wall_s"] / b["median_wall_s"]
        timing["median_render_ratio_to_baseline"] = (timing["penumbra"]["median_render_s"] / b["median_render_s"]
                                                      if b.get("median_render_s") else None)
    res["timing"] = timing

    # 2. Images, in Embree's domain.
    res["image"] = compare_images(ours_exr, emb_ppm, os.path.join(work, "side-by-side.png"))
    if not res["image"]["orientation_ok"]:
        log("warning: the images match better flipped or mirrored: check the camera convention")

    # 3. Thread scaling, 1 against 2 threads, alternating, on cores 0 and 1 (scaling_runs).
    if not args.skip_scaling and len(os.sched_getaffinity(0)) < 2:
        log("thread scaling: skipped (one core)")
    elif not args.skip_scaling:
        reps = args.scaling_reps or args.reps
        sc = {}
        log("thread scaling: penumbra --threads 1 / 2")
        pr = scaling_runs("penumbra", penumbra_cmd(penumbra, os.path.join(work, "penumbra-t1.exr"), 1),
                          penumbra_cmd(penumbra, os.path.join(work, "penumbra-t2.exr"), 2), reps, work)
        log("thread scaling: pathtracer --threads 1 / 2")
        er = scaling_runs("pathtracer", pathtracer_cmd(os.path.join(work, "embree-t1.ppm"), 1),
                          pathtracer_cmd(os.path.join(work, "embree-t2.ppm"), 2), reps, work)
        for label, runs_ in (("penumbra", pr), ("pathtracer", er)):
            one, two = runs_["1"], runs_["2"]
            entry = {
                "wall_1_s": [r["wall_s"] for r in one], "wall_2_s": [r["wall_s"] for r in two],
                "median_wall_1_s": median([r["wall_s"] for r in one]),
                "median_wall_1_core0_s": median([r["wall_s"] for r in one[0::2]]),
                "median_wall_1_core1_s": median([r["wall_s"] for r in one[1::2]]),
                "median_wall_2_s": median([r["wall_s"] for r in two]),
                "cpu_utilization_1": median([r["cpu_utilization"] for r in one]),
                "cpu_utilization_2": median([r["cpu_utilization"] for r in two]),
            }
            entry["speedup_wall"] = entry["median_wall_1_s"] / entry["median_wall_2_s"]
            entry["core_corrected_speedups"] = core_corrected_speedups(one, two)
            entry["speedup_core_corrected"] = median(entry["core_corrected_speedups"]) if entry["core_corrected_speedups"] else None
            if label == "penumbra":
                r1 = [parse_penumbra_summary(r["stdout"]).get("render_s") for r in one]
                r2 = [parse_penumbra_summary(r["stdout"]).get("render_s") for r in two]
                entry["render_1_s"], entry["render_2_s"] = r1, r2
                if median(r1) and median(r2):
                    entry["speedup_render"] = median(r1) / median(r2)
            sc[label] = entry
        res["thread_scaling"] = sc

    # 4. Rays per second: the render against bare Embree on the same rays.
    if not args.skip_rays:
        log("rays/s: penumbra_ray_throughput")
        rays_json = os.path.join(work, "ray-throughput.json")
        proc = run([ray_tool, SCENE, "--threads", "2", "--repeat", str(args.reps), "--json", rays_json],
                   check=False)
        sys.stderr.write(proc.stderr)
        if os.path.exists(rays_json):
            with open(rays_json) as f:
                res["rays"] = json.load(f)
        else:
            res["rays"] = {"error": proc.stderr.strip()[-2000:]}
        res["rays"]["penumbra_cli_mrays_per_s"] = timing["penumbra"]["mrays_per_s"]

    res["cycles"] = "blender not installed" if not shutil.which("blender") else "blender installed, not measured"
    res["load_after"] = loadavg()
    res["busy"] = max((res["load_before"] or [0])[0], (res["load_after"] or [0])[0]) > 0.5 * (os.cpu_count() or 1)

    os.makedirs(args.results, exist_ok=True)
    md = markdown(res)
    with open(os.path.join(args.results, "pathtracer-comparison.json"), "w") as f:
        json.dump(repo_relative(res), f, indent=2)
        f.write("\n")
    with open(os.path.join(args.results, "pathtracer-comparison.md"), "w") as f:
        f.write(md)
    print(md)
    log(f"wrote {os.path.join(args.results, 'pathtracer-comparison.json')} and .md; images in {work}")


if __name__ == "__main__":
    main()
