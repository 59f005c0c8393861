#!/usr/bin/python3
"""penumbra's cameras against pbrt-v4's, on the same pbrt-v4 files: what each pixel sees and how
much light reaches it. Run with Debian's Python (python3-numpy, python3-openimageio) and a pbrt-v4
built by ../shared/peers/build-pbrt-v4.sh:

    /usr/bin/python3 bench/pbrt_cameras.py [--binary build/tools/penumbra]
        --pbrt OUT_DIR/build/pbrt [--threads 2] [--out build/pbrt-cameras]

Writes the scenes below to --out, renders each with both programs (--threads each, one after the
other) and writes bench/results/pbrt-cameras.md:
  - furnace: a uniform white sky through the double Gauss (scenes/lenses/dgauss.50mm.dat) at an
    8 mm stop, focused at 10 m: the image's mean and its radial fall-off (bands of 6 x 4 pixels
    along the middle rows), penumbra's over pbrt-v4's;
  - bokeh: three small emitters 6 m away through the same lens wide open, focused at 1 m: each
    blur's centroid, flux and rms extent radially and tangentially (the cat's eye);
  - spherical-equirectangular, spherical-equalarea, orthographic: small emitters of distinct
    colours in known directions around the camera (for the orthographic, at known offsets at
    two depths): each one's centroid, which says whether the pixel-to-direction conventions agree.
Every emitter is a pbrt `sphere` with a `diffuse` area light; the integrator stops at the first
hit (maxdepth 1), the filter is a box of one pixel, so the images are the direct view of the lights.
"""
import argparse
import os
import shutil
import subprocess
import sys
from collections import deque

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

COMMON = """Sampler "stratified" "integer xsamples" {s} "integer ysamples" {s}
Integrator "path" "integer maxdepth" 1
PixelFilter "box" "float xradius" 0.5 "float yradius" 0.5
"""


def emitter(x, y, z, radius, rgb):
    return (f'AttributeBegin\n  Material "diffuse" "rgb reflectance" [0 0 0]\n'
            f'  AreaLightSource "diffuse" "rgb L" [{rgb[0]} {rgb[1]} {rgb[2]}]\n'
            f'  Translate {x} {y} {z}\n  Shape "sphere" "float radius" {radius}\nAttributeEnd\n')


def direction(azimuth, elevation, distance):
    a, e = np.radians(azimuth), np.radians(elevation)
    return (distance * np.cos(e) * np.sin(a), distance * np.sin(e), -distance * np.cos(e) * np.cos(a))


COLOURS = [(40, 4, 4), (4, 40, 4), (4, 4, 40), (30, 30, 4), (4, 30, 30), (30, 4, 30)]


def scenes():
    look = 'LookAt 0 0 0  0 0 -1  0 1 0\n'
    lens = 'Camera "realistic" "string lensfile" "dgauss.50mm.dat" '
    out = {}
    out["furnace"] = (look + lens + '"float aperturediameter" 8 "float focusdistance" 10\n'
                      'Film "rgb" "integer xresolution" 96 "integer yresolution" 64 "string filename" "pbrt.exr"\n'
                      + COMMON.format(s=16) + 'WorldBegin\nLightSource "infinite" "rgb L" [1 1 1]\n')
    bokeh = ''.join(emitter(x, y, -6, 0.04, (50, 50, 50)) for x, y in [(0, 0), (0.9, 0.45), (1.8, 1.05)])
    out["bokeh"] = (look + lens + '"float aperturediameter" 17.1 "float focusdistance" 1\n'
                    'Film "rgb" "integer xresolution" 192 "integer yresolution" 128 "float diagonal" 43.27 '
                    '"string filename" "pbrt.exr"\n' + COMMON.format(s=32) + 'WorldBegin\n' + bokeh)
    around = [(-150, 30), (-60, -20), (0, 0), (45, 60), (100, -45), (170, 10)]
    sky = ''.join(emitter(*direction(a, e, 10), 0.25, COLOURS[i]) for i, (a, e) in enumerate(around))
    for mapping, res in (("equirectangular", (192, 96)), ("equalarea", (128, 128))):
        out["spherical-" + mapping] = (
            look + f'Camera "spherical" "string mapping" "{mapping}"\n'
            f'Film "rgb" "integer xresolution" {res[0]} "integer yresolution" {res[1]} "string filename" "pbrt.exr"\n'
            + COMMON.format(s=16) + 'WorldBegin\n' + sky)
    offsets = [(-1.5, 0.8, -5), (1.0, -0.6, -5), (0.4, 1.1, -20), (-0.9, -1.2, -20)]
    ortho = ''.join(emitter(x, y, z, 0.08, COLOURS[i]) for i, (x, y, z) in enumerate(offsets))
    out["orthographic"] = (look + 'Camera "orthographic" "float screenwindow" [-3 3 -2 2]\n'
                           'Film "rgb" "integer xresolution" 150 "integer yresolution" 100 "string filename" "pbrt.exr"\n'
                           + COMMON.format(s=16) + 'WorldBegin\n' + ortho)
    return out


def read(path):
    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)[:, :, :3].astype(np.float64)


def blobs(image):
    """Connected regions above 2% of the peak (eight-neighbour), as lists of pixels."""
    lum = image.mean(axis=2)
    mask = lum > lum.max() * 0.02
    seen = np.zeros(mask.shape, bool)
    found = []
    h, w = mask.shape
    for y0, x0 in zip(*np.nonzero(mask)):
        if seen[y0, x0]:
            continue
        queue, pixels = deque([(y0, x0)]), []
        seen[y0, x0] = True
        while queue:
            y, x = queue.popleft()
            pixels.append((y, x))
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    ny, nx = y + dy, x + dx
                    if 0 <= ny < h and 0 <= nx < w and mask[ny, nx] and not seen[ny, nx]:
                        seen[ny, nx] = True
                        queue.append((ny, nx))
        if len(pixels) >= 4:
            found.append(pixels)
    return found


def measure(image, pixels):
    h, w = image.shape[:2]
    ys = np.array([p[0] for p in pixels]) + 0.5
    xs = np.array([p[1] for p in pixels]) + 0.5
    rgb = np.array([image[p] for p in pixels])
    weight = rgb.mean(axis=1)
    cx, cy = (weight * xs).sum() / weight.sum(), (weight * ys).sum() / weight.sum()
    rx, ry = cx - w / 2, cy - h / 2
    r = np.hypot(rx, ry)
    ux, uy = (rx / r, ry / r) if r > 1 else (1.0, 0.0)
    radial = (xs - cx) * ux + (ys - cy) * uy
    tangential = -(xs - cx) * uy + (ys - cy) * ux
    return {"x": cx, "y": cy, "flux": weight.sum(), "colour": int(np.argmax(rgb.sum(axis=0))),
            "radial": np.sqrt((weight * radial**2).sum() / weight.sum()),
            "tangential": np.sqrt((weight * tangential**2).sum() / weight.sum())}


def match(a, b):
    """Pairs each blob of a with the nearest blob of b."""
    pairs = []
    for p in a:
        q = min(b, key=lambda q: (q["x"] - p["x"]) ** 2 + (q["y"] - p["y"]) ** 2)
        pairs.append((p, q))
    return pairs


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "build/tools/penumbra"))
    parser.add_argument("--pbrt", default=os.environ.get("PENUMBRA_PBRT_PEER"), required="PENUMBRA_PBRT_PEER" not in os.environ,
                        help="pbrt-v4's binary, OUT_DIR/build/pbrt of ../shared/peers/build-pbrt-v4.sh OUT_DIR "
                             "(default: $PENUMBRA_PBRT_PEER)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--out", default=os.path.join(ROOT, "build/pbrt-cameras"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    shutil.copy(os.path.join(ROOT, "scenes/lenses/dgauss.50mm.dat"), args.out)
    lines = ["# penumbra's cameras against pbrt-v4's", "",
             "`/usr/bin/python3 bench/pbrt_cameras.py --pbrt PBRT` (the scenes are in its docstring); both programs render the",
             f"same pbrt-v4 file with {args.threads} threads. Positions in pixels, ratios penumbra / pbrt-v4.", ""]
    for name, text in scenes().items():
        folder = os.path.join(args.out, name)
        os.makedirs(folder, exist_ok=True)
        scene = os.path.join(folder, "scene.pbrt")
        with open(scene, "w") as f:
            f.write(text)
        if name in ("furnace", "bokeh"):
            shutil.copy(os.path.join(args.out, "dgauss.50mm.dat"), folder)
        subprocess.run([args.pbrt, "--nthreads", str(args.threads), "--quiet", "scene.pbrt"], cwd=folder,
                       check=True, stdout=subprocess.DEVNULL)
        subprocess.run([args.binary, "render", "scene.pbrt", "-o", "penumbra.exr", "--threads", str(args.threads),
                        "-q", "--no-display", "--film", "beauty"], cwd=folder, check=True,
                       stderr=subprocess.DEVNULL)
        ours, theirs = read(os.path.join(folder, "penumbra.exr")), read(os.path.join(folder, "pbrt.exr"))
        lines += [f"## {name}", ""]
        if name == "furnace":
            h, w = ours.shape[:2]
            lines += [f"Mean: penumbra {ours.mean():.5f}, pbrt-v4 {theirs.mean():.5f}, ratio "
                      f"{ours.mean() / theirs.mean():.4f}.", "",
                      "| band (columns) | penumbra | pbrt-v4 | ratio |", "|---|---|---|---|"]
            for x0 in range(w // 2, w, 6):
                a = ours[h // 2 - 2:h // 2 + 2, x0:x0 + 6].mean()
                b = theirs[h // 2 - 2:h // 2 + 2, x0:x0 + 6].mean()
                lines.append(f"| {x0}-{x0 + 5} | {a:.5f} | {b:.5f} | {a / b:.4f} |")
        else:
            pairs = match([measure(ours, p) for p in blobs(ours)], [measure(theirs, p) for p in blobs(theirs)])
            lines += ["| emitter | penumbra (x, y) | pbrt-v4 (x, y) | distance | flux ratio | radial / tangential rms, "
                      "penumbra | pbrt-v4 |", "|---|---|---|---|---|---|---|"]
            for i, (p, q) in enumerate(sorted(pairs, key=lambda pq: (pq[0]["y"], pq[0]["x"]))):
                lines.append(f"| {i + 1} | {p['x']:.2f}, {p['y']:.2f} | {q['x']:.2f}, {q['y']:.2f} | "
                             f"{np.hypot(p['x'] - q['x'], p['y'] - q['y']):.3f} | {p['flux'] / q['flux']:.4f} | "
                             f"{p['radial']:.2f} / {p['tangential']:.2f} | {q['radial']:.2f} / {q['tangential']:.2f} |")
            lines.append("")
            lines.append(f"Emitters found: penumbra {len(pairs)}, pbrt-v4 {len(blobs(theirs))}.")
        lines.append("")
        print(f"{name}: done", file=sys.stderr)
    with open(os.path.join(HERE, "results", "pbrt-cameras.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
