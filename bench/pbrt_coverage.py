#!/usr/bin/python3
"""How much of real pbrt-v4 scenes penumbra renders: every pbrt-v4 scene under ../shared/data
(Bitterli's twelve in bitterli/, the Cornell box, Veach's MIS scene), rendered small, with what
the importer dropped or approximated. One command, run with Debian's Python (python3-numpy,
python3-openimageio, python3-matplotlib):

    /usr/bin/python3 bench/pbrt_coverage.py [--binary build/tools/penumbra] [--res-width 192]
        [--spp 16] [--seeds 4] [--threads 2] [--scenes coffee,veach-mis,...] [--out build/pbrt-coverage]
        [--no-convert]

Per scene it runs `penumbra render SCENE -o OUT.exr --res WxH --spp N --seed S --threads T -q --film
beauty --no-display` under `/usr/bin/time -v`, once per seed 1..--seeds (W from --res-width, H
keeping the aspect of the file's xresolution/yresolution), and records:
  - the exit status, the wall time of the whole process (parsing, mesh loading, BVH build, render,
    writing the EXR) and its peak resident memory, of the first seed's run;
  - every warning on stderr, grouped by kind: the file:line:column prefix dropped, paths reduced
    to their extension (`*.tga`: the format is what matters), quoted file names to "<file>",
    numbers to N, the importer's "(K times)" counted as K;
  - the first error line when the render fails (a failed scene's warnings are those printed before
    the error);
  - the mean of each channel of the render over the mean of the same channel of the reference
    (Tungsten's render at full size, `TungstenRender.exr` or `reference-tungsten.exr`). Means do
    not depend on the resolution or the reconstruction filter, so a small render can be compared
    with the full-size reference; they do depend on the noise of a short render (caustics above
    all), on placeholder textures (bitterli/README.md lists them: a flat sky or a grey texture
    changes the light) and on where pbrt-v4's conversion differs from Tungsten's scene. The means are
    those of all seeds' runs, pixels with a non-finite value left out (water-caustic's reference
    has one); the relative standard error of the runs' mean luminances is the noise in the ratio.
A scene stopped by an image penumbra cannot read (.tga, .pfm) is rendered again the same way from a
copy of its file in --out whose .tga and .pfm files are converted to PNG and EXR (OpenImageIO), to
show what lies behind the error: its warnings and mean ratio are reported apart (--no-convert
skips it); the summary line counts the data set's files as they are.
Two kinds of warning do not change the image in expectation and are not counted as feature
warnings: the sampler (penumbra's stratified sampler for pbrt's, different noise only) and the
Film's file name (the EXR is the one -o names). Every other warning is a feature warning.

Writes bench/results/pbrt-coverage.md (the table, the summary line "N of M scenes rendered
without a feature warning", the warning and error kinds ranked by how many scenes they touch) and
bench/results/pbrt-coverage.png (each scene's render beside its reference, each scaled to a mean
luminance of 0.18 and gamma 2.2; a failed scene's converted copy where it rendered). Images and
logs go to --out. A benchmark, not a test: nothing in
tests/ runs it.
"""

import argparse
import datetime
import os
import re
import subprocess
import sys
import time

import numpy as np
import OpenImageIO as oiio

from time_to_error import machine_description  # the same machine line as the other benchmarks

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.normpath(os.path.join(REPO, "..", "shared", "data"))
RESULTS = os.path.join(REPO, "bench", "results")
REFERENCE_NAMES = ("TungstenRender.exr", "reference-tungsten.exr")

# Warnings that leave the image unchanged in expectation (see the docstring).
BENIGN = (re.compile(r'^Sampler .* is rendered with penumbra\'s stratified sampler'),
          re.compile(r'^Film filename .* is not used'))


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def find_scenes():
    """(name, pbrt file, reference) for every scene-v4.pbrt under DATA, Bitterli's first."""
    found = []
    for root, _, files in os.walk(DATA):
        for f in files:
            if f.endswith(".pbrt") and f.startswith("scene"):
                path = os.path.join(root, f)
                ref = next((os.path.join(root, r) for r in REFERENCE_NAMES if os.path.exists(os.path.join(root, r))), None)
                found.append((os.path.basename(root), path, ref))
    return sorted(found, key=lambda s: (not s[1].startswith(os.path.join(DATA, "bitterli")), s[0]))


def placeholders():
    """scene -> placeholder files, from the table in bitterli/README.md."""
    out = {}
    try:
        for line in open(os.path.join(DATA, "bitterli", "README.md")):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) == 3 and cells[0].startswith("`"):
                out[cells[0].strip("`")] = re.findall(r"`([^`]+)`", cells[2])
    except OSError:
        pass
    return out


def pbrt_resolution(path):
    """The Film's xresolution and yresolution (comments dropped), or None."""
    text = "\n".join(l.split("#", 1)[0] for l in open(path, errors="replace"))
    x = re.search(r'"integer xresolution"\s*\[?\s*(\d+)', text)
    y = re.search(r'"integer yresolution"\s*\[?\s*(\d+)', text)
    return (int(x.group(1)), int(y.group(1))) if x and y else None


def image_size(path):
    inp = oiio.ImageInput.open(path)
    spec = inp.spec()
    inp.close()
    return spec.width, spec.height


def read_rgb(path):
    buf = oiio.ImageBuf(path)
    px = buf.get_pixels(oiio.FLOAT)
    return np.asarray(px, dtype=np.float64)[:, :, :3]


LOCATION = re.compile(r"^\S+?:\d+:\d+:\s*")
TIMES = re.compile(r"\s*\((\d+) times\)\s*$")


def normalise(message):
    """A warning or error message without location, paths, file names and numbers; and its count."""
    m = LOCATION.sub("", message.strip())
    count = 1
    t = TIMES.search(m)
    if t:
        count = int(t.group(1))
        m = m[:t.start()]
    m = re.sub(r"\s*\(at /.*$", "", m)                                   # the JSON pointer of a failed value
    m = re.sub(r'"[^"]*\.(?:exr|png|pfm|tga|jpg|jpeg|tif|tiff|hdr|ply|obj|pbrt)"', '"<file>"', m, flags=re.I)
    m = re.sub(r"(?:\S*/)+[^:/]*?(\.[A-Za-z0-9]+)(?=[:\s,)]|$)", r"*\1", m)  # paths: their extension
    m = re.sub(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?(?![\w.])", "N", m)
    return m.strip(), count


def parse_stderr(text):
    warnings, errors = {}, []
    for line in text.splitlines():
        if line.startswith("penumbra: warning: "):
            kind, count = normalise(line[len("penumbra: warning: "):])
            warnings[kind] = warnings.get(kind, 0) + count
        elif line.startswith("penumbra: error: ") or line.startswith("error: "):
            errors.append(line.split("error: ", 1)[1])
        elif ("terminate called" in line or "Segmentation fault" in line or "Assertion" in line) and not errors:
            errors.append(line.strip())
    return warnings, errors


def parse_time_v(path):
    wall = rss = None
    for line in open(path):
        line = line.strip()
        if line.startswith("Elapsed (wall clock) time"):
            parts = line.rsplit(" ", 1)[1].split(":")
            wall = sum(float(p) * 60 ** i for i, p in enumerate(reversed(parts)))
        elif line.startswith("Maximum resident set size (kbytes)"):
            rss = int(line.rsplit(" ", 1)[1]) / 1024
    return wall, rss


def is_benign(kind):
    return any(b.search(kind) for b in BENIGN)


def render_scene(args, name, path, ref, workdir):
    res = pbrt_resolution(path) or (image_size(ref) if ref else (1, 1))
    width = args.res_width
    height = max(1, round(width * res[1] / res[0]))
    r = {"name": name, "file": os.path.relpath(path, DATA), "reference": os.path.relpath(ref, DATA) if ref else None,
         "resolution": [width, height], "full_resolution": list(res)}
    if ref:
        m, bad = finite_mean(read_rgb(ref))
        r["ref_mean"], r["ref_nonfinite"] = m.tolist(), bad
    r.update(render_seeds(args, name, path, width, height, workdir, r.get("ref_mean")))
    # A scene stopped by an image penumbra cannot read: render a copy whose .tga and .pfm files are
    # converted (PNG and EXR, through OpenImageIO, into the work folder), to see what lies behind.
    if args.convert and r["status"] != 0 and any("cannot read the image" in e for e in r["errors"]):
        copy = converted_copy(path, os.path.join(workdir, f"{name}-converted"))
        if copy:
            r["converted"] = render_seeds(args, f"{name}-converted", copy, width, height, workdir, r.get("ref_mean"))
    return r


def render_seeds(args, name, path, width, height, workdir, ref_mean):
    """Renders with seeds 1..--seeds: the first is timed and shown, the mean of all is compared with
    the reference, and their spread says how much of a mean ratio is the noise of a short render."""
    runs = [run_penumbra(args, name, path, width, height, seed, workdir) for seed in range(1, args.seeds + 1)]
    first = runs[0]
    r = {k: first[k] for k in ("status", "wall_s", "peak_mib", "warnings", "errors", "exr")}
    if all(x["exr"] for x in runs):
        means = [finite_mean(read_rgb(x["exr"])) for x in runs]
        r["mean"] = np.mean([m[0] for m in means], axis=0).tolist()
        r["nonfinite"] = sum(m[1] for m in means)
        lum = np.array([float(np.dot(LUMINANCE, m[0])) for m in means])
        r["seed_means"] = lum.tolist()
        if len(lum) > 1 and lum.mean() > 0:
            r["seed_rse"] = float(lum.std(ddof=1) / np.sqrt(len(lum)) / lum.mean())
    if r.get("mean") and ref_mean:
        r["ratio"] = [m / q if q > 0 else float("nan") for m, q in zip(r["mean"], ref_mean)]
    return r


CONVERT = {".tga": ".png", ".pfm": ".exr"}


def converted_copy(path, folder):
    """A copy of the pbrt file in folder: every quoted name of an existing file made absolute, and
    .tga/.pfm files converted to PNG/EXR beside it. None when nothing was converted."""
    os.makedirs(folder, exist_ok=True)
    base = os.path.dirname(os.path.abspath(path))
    converted = 0

    def replace(m):
        nonlocal converted
        name = m.group(1)
        src = os.path.join(base, name)
        if not os.path.isfile(src):
            return m.group(0)
        stem, ext = os.path.splitext(name)
        if ext.lower() not in CONVERT:
            return f'"{src}"'
        dst = os.path.join(folder, stem.replace("/", "_") + CONVERT[ext.lower()])
        if not os.path.exists(dst):
            buf = oiio.ImageBuf(src)
            if not buf.write(dst):
                log(f"cannot convert {src}: {buf.geterror()}")
                return f'"{src}"'
        converted += 1
        return f'"{dst}"'

    text = re.sub(r'"([^"\n]+\.[A-Za-z0-9]{2,4})"', replace, open(path, errors="replace").read())
    if not converted:
        return None
    out = os.path.join(folder, os.path.basename(path))
    with open(out, "w") as f:
        f.write(text)
    return out


LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def finite_mean(img):
    """Per-channel mean over the pixels whose three values are finite, and how many pixels are not."""
    ok = np.isfinite(img).all(axis=-1)
    return img[ok].mean(axis=0), int((~ok).sum())


def run_penumbra(args, name, path, width, height, seed, workdir):
    out = os.path.join(workdir, f"{name}-seed{seed}.exr")
    timing = os.path.join(workdir, f"{name}-seed{seed}.time")
    for f in (out, timing):
        if os.path.exists(f):
            os.remove(f)
    cmd = [args.binary, "render", path, "-o", out, "--res", f"{width}x{height}", "--spp", str(args.spp),
           "--seed", str(seed), "--threads", str(args.threads), "-q", "--film", "beauty", "--no-display"]
    log(f"{name}: {width}x{height}, {args.spp} spp, seed {seed}")
    t0 = time.time()
    try:
        proc = subprocess.run(["/usr/bin/time", "-v", "-o", timing] + cmd, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True, errors="replace", timeout=args.timeout)
        rc, stderr = proc.returncode, proc.stdout + proc.stderr
    except subprocess.TimeoutExpired as e:
        rc = "timeout"
        stderr = "".join(x.decode(errors="replace") if isinstance(x, bytes) else x for x in (e.stdout, e.stderr) if x)
    elapsed = time.time() - t0
    with open(os.path.join(workdir, f"{name}-seed{seed}.log"), "w") as f:
        f.write(stderr)
    wall, rss = parse_time_v(timing) if os.path.exists(timing) and os.path.getsize(timing) else (elapsed, None)
    if rc != "timeout" and rc < 0:
        rc = f"signal {-rc}"
    warnings, errors = parse_stderr(stderr)
    if rc == 0 and not os.path.exists(out):
        errors.insert(0, "no EXR written")
        rc = "no EXR"
    if rc != 0 and not errors:
        tail = [l for l in stderr.splitlines() if l.strip() and not l.startswith("penumbra: warning: ")]
        errors.append(tail[-1] if tail else f"exit status {rc}")
    return {"status": rc, "wall_s": wall, "peak_mib": rss, "warnings": warnings, "errors": errors,
            "exr": out if rc == 0 else None}


def tonemap(img):
    img = np.nan_to_num(np.clip(img, 0, None), nan=0, posinf=0)
    lum = (img @ LUMINANCE).mean()
    if lum > 0:
        img = img * (0.18 / lum)
    return np.clip(img, 0, 1) ** (1 / 2.2)


def contact_sheet(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    pairs_per_row = 2
    rows = (len(results) + pairs_per_row - 1) // pairs_per_row
    fig, axes = plt.subplots(rows, 2 * pairs_per_row, figsize=(2.6 * 2 * pairs_per_row, 2.2 * rows),
                             squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    for i, r in enumerate(results):
        w, h = r["resolution"]
        ax_r, ax_q = axes[i // pairs_per_row][2 * (i % pairs_per_row)], axes[i // pairs_per_row][2 * (i % pairs_per_row) + 1]
        shown = r if r["exr"] else r.get("converted") if r.get("converted", {}).get("exr") else None
        if shown:
            ax_r.imshow(tonemap(read_rgb(shown["exr"])), interpolation="nearest")
            ratio = shown.get("ratio")
            sub = "mean ratio " + "/".join(f"{v:.2f}" for v in ratio) if ratio else ""
            label = "penumbra" if shown is r else "penumbra, images converted"
            ax_r.set_title(f"{r['name']}: {label}\n{sub}", fontsize=7)
        else:
            ax_r.imshow(np.full((h, w, 3), 0.25))
            ax_r.text(w / 2, h / 2, f"failed\n({r['status']})", ha="center", va="center", color="white", fontsize=8)
            ax_r.set_title(f"{r['name']}: penumbra", fontsize=7)
        if r["reference"]:
            buf = oiio.ImageBufAlgo.resize(oiio.ImageBuf(os.path.join(DATA, r["reference"])),
                                           roi=oiio.ROI(0, w, 0, h, 0, 1, 0, 3))
            ax_q.imshow(tonemap(np.asarray(buf.get_pixels(oiio.FLOAT), dtype=np.float64)[:, :, :3]),
                        interpolation="nearest")
            ax_q.set_title(f"{r['name']}: reference (Tungsten)", fontsize=7)
    fig.suptitle("pbrt-v4 scenes: penumbra (left; a scene stopped by a .tga/.pfm image: its copy with "
                 "converted images) and Tungsten's reference (right),\neach scaled to mean luminance 0.18, gamma 2.2", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=72)
    plt.close(fig)


def fmt(v, spec):
    return format(v, spec) if v is not None else "-"


def is_clean(r):
    return r["status"] == 0 and not any(not is_benign(k) for k in r["warnings"])


def table_row(r, name, placeholder_cell):
    status = "ok" if r["status"] == 0 else f"FAILED ({r['status']})"
    ratio = "/".join(f"{v:.2f}" for v in r["ratio"]) if r.get("ratio") else "-"
    if r.get("nonfinite"):
        ratio += f" ({r['nonfinite']} non-finite pixels left out)"
    if r.get("ref_nonfinite") and r.get("ratio"):
        ratio += f" (reference: {r['ref_nonfinite']} non-finite pixel{'s' if r['ref_nonfinite'] > 1 else ''} left out)"
    diff = f"{100 * r['seed_rse']:.1f}%" if r.get("seed_rse") is not None else "-"
    warns = "; ".join(f"{k} ({n})" for k, n in sorted(r["warnings"].items()) if not is_benign(k))
    benign = sum(n for k, n in r["warnings"].items() if is_benign(k))
    if benign:
        warns += f"{'; ' if warns else ''}+{benign} (b)"
    return (f"| {name} | {status} | {fmt(r['wall_s'], '.2f')} | {fmt(r['peak_mib'], '.0f')} | {ratio} | {diff} | "
            f"{placeholder_cell} | {warns.replace('|', '/') or '-'} |")


def write_report(meta, results, path):
    holders = placeholders()
    n_clean = sum(1 for r in results if is_clean(r))
    summary = f"{n_clean} of {len(results)} scenes rendered without a feature warning"
    n_ok = sum(1 for r in results if r["status"] == 0)
    lines = ["# pbrt-v4 scene coverage", "",
             f"Measured {meta['date']} on {meta['machine']}; load average {meta['load_before']} before, "
             f"{meta['load_after']} after; {meta['total_s']:.0f} s in all. Binary `{meta['binary']}` "
             f"(tree at {meta['commit']}).", "",
             f"Command: `{meta['command']}`", "",
             f"Every pbrt-v4 scene under `../shared/data`, {meta['width']} pixels wide (the file's aspect), "
             f"{meta['spp']} spp, {meta['threads']} threads, `--film beauty --no-display`. Time and peak memory: the "
             "whole `penumbra render` process under `/usr/bin/time -v`. Mean ratio: each channel's mean over the "
             "same channel's mean in Tungsten's full-size reference (means do not depend on resolution or filter; "
             "they do on a short render's noise, on placeholder textures and on where the pbrt-v4 conversion differs "
             f"from Tungsten's scene), of {meta['seeds']} renders with seeds 1 to {meta['seeds']}; pixels with a "
             "non-finite value are left out of a mean. ± (seeds): the relative standard error of the mean "
             "luminance over those renders, the noise in the ratio (a guide only: one directly visible small "
             "light or a rare caustic path can hold most of an image's mean); time and memory are the first "
             "render's. Warning kinds: file:line and numbers dropped, paths reduced to their extension; "
             "(b) counts the two kinds that do not change the image in expectation (sampler, Film file name); "
             "the rest are feature warnings.", "",
             f"**{summary}**; {n_ok} of {len(results)} rendered at all.", "",
             "| scene | status | time s | peak MiB | mean ratio R/G/B | ± (seeds) | placeholders | warning kinds (count) |",
             "|---|---|---|---|---|---|---|---|"]
    for r in results:
        lines.append(table_row(r, r["name"], ", ".join(f"`{p}`" for p in holders.get(r["name"], [])) or "-"))
    failed = [r for r in results if r["status"] != 0]
    if failed:
        lines += ["", "First error line of each failed scene:", ""]
        lines += [f"- {r['name']}: `{r['errors'][0] if r['errors'] else '?'}`".replace(DATA + "/", "")
                  for r in failed]
    conv = [r for r in results if r.get("converted")]
    if conv:
        n_conv_clean = sum(1 for r in results if is_clean(r.get("converted", r)))
        lines += ["", f"The {len(conv)} scenes stopped by a .tga or .pfm image, rendered again from a copy of the file "
                  "whose .tga and .pfm files are converted to PNG and EXR (OpenImageIO, into the work folder; the "
                  "copy is not the data set's file, it shows what lies behind the error). With those copies, "
                  f"{n_conv_clean} of {len(results)} scenes render without a feature warning.", "",
                  "| scene (converted images) | status | time s | peak MiB | mean ratio R/G/B | ± (seeds) | "
                  "placeholders | warning kinds (count) |", "|---|---|---|---|---|---|---|---|"]
        for r in conv:
            c = dict(r["converted"], ref_nonfinite=r.get("ref_nonfinite"))
            lines.append(table_row(c, r["name"], ", ".join(f"`{p}`" for p in holders.get(r["name"], [])) or "-"))
            if c["status"] != 0:
                lines[-1] += f" first error: `{(c['errors'] or ['?'])[0]}`".replace(DATA + "/", "")
    # Kinds across scenes: errors (fatal) and warnings, ranked by the scenes they touch.
    kinds = {}

    def add(what, k, scene, n):
        e = kinds.setdefault((what, k), [set(), 0])
        e[0].add(scene)
        e[1] += n

    for r in results:
        for tag, x in ((r["name"], r), (r["name"] + "*", r.get("converted"))):
            if not x:
                continue
            for k, n in x["warnings"].items():
                if tag.endswith("*") and k in r["warnings"]:
                    continue   # seen in the original file already
                add("warning (b)" if is_benign(k) else "warning", k, tag, n)
            if x["status"] != 0 and x["errors"]:
                add("error (scene fails)", normalise(x["errors"][0])[0], tag, 1)
    ranked = sorted(kinds.items(), key=lambda kv: (kv[0][0] == "warning (b)", -len(kv[1][0]),
                                                   kv[0][0] != "error (scene fails)", -kv[1][1], kv[0][1]))
    lines += ["", "Error and feature-warning kinds across all scenes, ranked by how many scenes they touch (an "
              "error stops the scene; a failed scene's warnings are those printed before its error; `*`: seen only "
              "in the copy with converted images); the (b) kinds last:", "",
              "| scenes | occurrences | what | kind | which scenes |", "|---|---|---|---|---|"]
    for (what, k), (scenes, n) in ranked:
        lines.append(f"| {len(scenes)} | {n} | {what} | {k.replace('|', '/')} | {', '.join(sorted(scenes))} |")
    lines += ["", "Contact sheet: `pbrt-coverage.png` (penumbra's render beside the reference, each scaled to "
              "mean luminance 0.18, gamma 2.2; a scene stopped by an image shows its copy with converted images).", ""]
    with open(path, "w") as f:
        f.write("\n".join(lines))
    return summary, ranked


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--binary", default=os.path.join(REPO, "build", "tools", "penumbra"))
    ap.add_argument("--res-width", type=int, default=192)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--seeds", type=int, default=4, help="renders per scene, seeds 1..N (the mean's noise)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--no-convert", dest="convert", action="store_false",
                    help="do not render a copy with converted images of a scene that fails on a .tga/.pfm")
    ap.add_argument("--timeout", type=float, default=300, help="seconds a scene may take")
    ap.add_argument("--scenes", default="", help="comma-separated scene names (folder names); default all")
    ap.add_argument("--out", default=os.path.join(REPO, "build", "pbrt-coverage"), help="work folder for images and logs")
    ap.add_argument("--results", default=RESULTS, help="where pbrt-coverage.md and .png go")
    args = ap.parse_args()

    scenes = find_scenes()
    if args.scenes:
        wanted = args.scenes.split(",")
        unknown = set(wanted) - {s[0] for s in scenes}
        if unknown:
            raise SystemExit(f"unknown scenes: {', '.join(sorted(unknown))} (have: {', '.join(s[0] for s in scenes)})")
        scenes = [s for s in scenes if s[0] in wanted]
    os.makedirs(args.out, exist_ok=True)
    os.makedirs(args.results, exist_ok=True)
    try:
        commit = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"], stdout=subprocess.PIPE,
                                text=True).stdout.strip()
    except OSError:
        commit = "?"
    meta = {"date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"), "machine": machine_description(),
            "load_before": [round(x, 2) for x in os.getloadavg()], "binary": os.path.relpath(args.binary, REPO),
            "commit": commit, "width": args.res_width, "spp": args.spp, "seeds": args.seeds, "threads": args.threads,
            "command": " ".join(["/usr/bin/python3", "bench/pbrt_coverage.py"] + sys.argv[1:])}
    t0 = time.time()
    results = [render_scene(args, name, path, ref, args.out) for name, path, ref in scenes]
    meta["total_s"] = time.time() - t0
    meta["load_after"] = [round(x, 2) for x in os.getloadavg()]
    md = os.path.join(args.results, "pbrt-coverage.md")
    summary, ranked = write_report(meta, results, md)
    contact_sheet(results, os.path.join(args.results, "pbrt-coverage.png"))
    print(summary)
    for (what, k), (sc, n) in ranked:
        print(f"{len(sc):3d} scenes  {n:4d}x  {what}: {k}")
    print(f"wrote {md} and pbrt-coverage.png")


if __name__ == "__main__":
    main()
