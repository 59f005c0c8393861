"""penumbra's subsurface material beside pbrt-v4's and Cycles' on one scene, written to
bench/results/subsurface-peers.md:

    /usr/bin/python3 bench/subsurface_peers.py [--pbrt PATH] [--blender PATH] [--spp N]

The scene: a slab (a box 200 x 200 wide, 100 deep, its top face z = 0) of a subsurface material
under a uniform sky of radiance 1, seen straight down by an orthographic camera 2 units wide,
32 x 32 pixels. Every pixel sees the slab's albedo for light leaving along the normal (by
reciprocity, what it reflects of light arriving along the normal): one number per channel, with
its standard error from the pixels' spread (each pixel's paths are independent of the others').

Two cases:
  artist: the parameters an artist gives, "reflectance" (0.2, 0.5, 0.8), mean free path 1, eta
     1.33: penumbra and pbrt-v4 take them as they are (pbrt-v4 inverts its photon beam diffusion
     profile for the albedo, penumbra the classical dipole), Cycles as its subsurface node's Color
     and Radius, with its random walk (RANDOM_WALK_FIXED_RADIUS: the radius is the mean free path;
     RANDOM_WALK: Cycles scales it by a fit of the colour). Each renders what its own model makes of
     "reflectance 0.5": the colour asked for against the colour got.
  physical: the same medium in all, sigma_t 1 and single-scattering albedo 0.5, 0.9 or 0.99 (grey:
     one render per albedo, so that pbrt-v4's spectral rendering and penumbra's RGB see the same
     medium; a chromatic medium's channels mix over wavelengths in pbrt-v4), eta 1.33: penumbra's
     subsurface (random walk, diffuse exit), pbrt-v4's subsurface (its BSSRDF), and the exact
     transport in both (a dielectric around the medium: penumbra's volumetric path tracer,
     pbrt-v4's volpath). The two exact renders check each other; the others' differences from them
     are their models' (penumbra's diffuse exit, pbrt-v4's diffusion profile).

pbrt-v4 (--pbrt, built by ../shared/peers/build-pbrt-v4.sh) and Cycles (--blender, Debian's
Blender 3.4) are optional: a peer that is not given is left out of the table.
"""
import argparse, json, os, shutil, subprocess, sys, tempfile, time

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PENUMBRA = os.path.join(ROOT, "build", "tools", "penumbra")
SIZE = 32
ETA = 1.33
REFLECTANCE = [0.2, 0.5, 0.8]
MFP = [1.0, 1.0, 1.0]
ALBEDOS = [0.5, 0.9, 0.99]

CORNERS = [[100.0 if v & 1 else -100.0, 100.0 if v & 2 else -100.0, 0.0 if v & 4 else -100.0] for v in range(8)]
# Each face's two triangles counter-clockwise seen from outside (vertex v = x + 2 y + 4 z).
TRIANGLES = [0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2,
             1, 3, 7, 1, 7, 5]


def channel_means(path):
    """Per channel: the image's mean and its standard error over the pixels."""
    pixels = oiio.ImageBuf(path).get_pixels(oiio.FLOAT)[..., :3].reshape(-1, 3).astype(np.float64)
    return pixels.mean(axis=0), pixels.std(axis=0, ddof=1) / np.sqrt(len(pixels))


def penumbra_scene(material, inside=None, media=None):
    shape = {"type": "triangle_mesh", "positions": CORNERS, "indices": TRIANGLES, "material": "slab"}
    if inside:
        shape["inside"] = inside
    scene = {
        "camera": {"type": "orthographic", "height": 2, "look_from": [0, 0, 5], "look_at": [0, 0, 0],
                   "up": [0, 1, 0]},
        "film": {"resolution": [SIZE, SIZE], "filter": {"type": "box"}},
        "integrator": {"max_depth": 1024},
        "background": 1,
        "materials": {"slab": material},
        "shapes": [shape],
    }
    if media:
        scene["media"] = media
    return scene


def render_penumbra(scene, folder, name, spp):
    scene_path = os.path.join(folder, name + ".json")
    with open(scene_path, "w") as f:
        json.dump(scene, f)
    out = os.path.join(folder, name + ".exr")
    start = time.time()
    subprocess.run([PENUMBRA, "render", scene_path, "--spp", str(spp), "--threads", "2", "-o", out,
                    "--film", "beauty", "--no-display"], check=True, capture_output=True)
    return out, time.time() - start


PBRT_SLAB = ('Shape "trianglemesh" "point3 P" [' + " ".join(str(c) for p in CORNERS for c in p) +
             '] "integer indices" [' + " ".join(str(i) for i in TRIANGLES) + "]\n")


def render_pbrt(pbrt, world, folder, name, spp):
    out = os.path.join(folder, name + ".exr")
    text = ("LookAt 0 0 5  0 0 0  0 1 0\n"
            'Camera "orthographic" "float screenwindow" [-1 1 -1 1]\n'
            f'Film "rgb" "integer xresolution" {SIZE} "integer yresolution" {SIZE} "string filename" "{out}"\n'
            'PixelFilter "box" "float xradius" 0.5 "float yradius" 0.5\n'
            f'Sampler "independent" "integer pixelsamples" {spp}\n'
            'Integrator "volpath" "integer maxdepth" 1024\n'
            "WorldBegin\n"
            'LightSource "infinite" "rgb L" [1 1 1]\n' + world)
    scene_path = os.path.join(folder, name + ".pbrt")
    with open(scene_path, "w") as f:
        f.write(text)
    start = time.time()
    subprocess.run([pbrt, "--nthreads", "2", "--seed", "1", scene_path], check=True, capture_output=True)
    return out, time.time() - start


def render_cycles(blender, folder, name, spp, falloff):
    out = os.path.join(folder, name + ".exr")
    spec = {"color": REFLECTANCE, "radius": MFP, "ior": ETA, "falloff": falloff, "spp": spp, "seed": 1,
            "threads": 2, "size": SIZE, "output": out}
    spec_path = os.path.join(folder, name + ".spec.json")
    with open(spec_path, "w") as f:
        json.dump(spec, f)
    start = time.time()
    subprocess.run([blender, "-b", "--factory-startup", "--python", os.path.join(HERE, "subsurface_cycles.py"),
                    "--", spec_path], check=True, capture_output=True)
    return out, time.time() - start


def rgb(values):
    return " ".join(f"{v:g}" for v in values)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pbrt", help="pbrt-v4's binary")
    parser.add_argument("--blender", default=shutil.which("blender"), help="Blender (Cycles)")
    parser.add_argument("--spp", type=int, default=1024)
    parser.add_argument("--output", default=os.path.join(HERE, "results", "subsurface-peers.md"))
    args = parser.parse_args()
    folder = tempfile.mkdtemp(prefix="subsurface-peers-")
    rows = {"artist": [], "physical": []}

    def add(case, who, how, rendered):
        path, seconds = rendered
        mean, error = channel_means(path)
        rows[case].append((who, how, mean, error, seconds))
        print(case, who, how, mean, error, f"{seconds:.1f} s", flush=True)

    def add_grey(who, how, render):
        """One render per albedo; each cell the image's mean over the channels (all equal in RGB)."""
        means, errors, seconds = [], [], 0.0
        for albedo in ALBEDOS:
            path, took = render(albedo)
            mean, error = channel_means(path)
            means.append(mean.mean())
            errors.append(error.mean())
            seconds += took
        rows["physical"].append((who, how, means, errors, seconds))
        print("physical", who, how, means, errors, f"{seconds:.1f} s", flush=True)

    def medium(albedo):
        return [1.0 - albedo] * 3, [albedo] * 3

    artist = {"type": "subsurface", "reflectance": REFLECTANCE, "mfp": MFP, "eta": ETA}
    add("artist", "penumbra", "subsurface: random walk, diffuse exit",
        render_penumbra(penumbra_scene(artist), folder, "artist-penumbra", args.spp))

    def penumbra_subsurface(albedo):
        sigma_a, sigma_s = medium(albedo)
        scene = penumbra_scene({"type": "subsurface", "sigma_a": sigma_a, "sigma_s": sigma_s, "eta": ETA})
        return render_penumbra(scene, folder, f"physical-penumbra-{albedo}", args.spp)

    def penumbra_exact(albedo):
        sigma_a, sigma_s = medium(albedo)
        scene = penumbra_scene({"type": "dielectric", "eta": ETA}, inside="inner",
                               media={"inner": {"type": "homogeneous", "sigma_a": sigma_a, "sigma_s": sigma_s}})
        return render_penumbra(scene, folder, f"physical-penumbra-exact-{albedo}", args.spp)

    add_grey("penumbra", "subsurface: random walk, diffuse exit", penumbra_subsurface)
    add_grey("penumbra", "exact: dielectric around the medium", penumbra_exact)
    if args.pbrt:
        add("artist", "pbrt-v4", "subsurface: photon beam diffusion BSSRDF",
            render_pbrt(args.pbrt, f'Material "subsurface" "rgb reflectance" [{rgb(REFLECTANCE)}] '
                        f'"rgb mfp" [{rgb(MFP)}] "float eta" {ETA}\n' + PBRT_SLAB, folder, "artist-pbrt",
                        args.spp))

        def pbrt_subsurface(albedo):
            sigma_a, sigma_s = medium(albedo)
            return render_pbrt(args.pbrt, f'Material "subsurface" "rgb sigma_a" [{rgb(sigma_a)}] '
                               f'"rgb sigma_s" [{rgb(sigma_s)}] "float eta" {ETA}\n' + PBRT_SLAB, folder,
                               f"physical-pbrt-{albedo}", args.spp)

        def pbrt_exact(albedo):
            sigma_a, sigma_s = medium(albedo)
            return render_pbrt(args.pbrt, f'MakeNamedMedium "inner" "string type" "homogeneous" '
                               f'"rgb sigma_a" [{rgb(sigma_a)}] "rgb sigma_s" [{rgb(sigma_s)}] "float scale" 1\n'
                               'MediumInterface "inner" ""\n'
                               f'Material "dielectric" "float eta" {ETA}\n' + PBRT_SLAB, folder,
                               f"physical-pbrt-exact-{albedo}", args.spp)

        add_grey("pbrt-v4", "subsurface: photon beam diffusion BSSRDF", pbrt_subsurface)
        add_grey("pbrt-v4", "exact: dielectric around the medium (volpath)", pbrt_exact)
    if args.blender:
        for falloff in ("RANDOM_WALK_FIXED_RADIUS", "RANDOM_WALK"):
            add("artist", "Cycles (Blender 3.4)", f"subsurface node, {falloff}",
                render_cycles(args.blender, folder, "artist-cycles-" + falloff.lower(), args.spp, falloff))

    lines = ["# Subsurface scattering beside pbrt-v4 and Cycles", "",
             f"Measured {time.strftime('%Y-%m-%d %H:%M')} by `/usr/bin/python3 bench/subsurface_peers.py"
             + (" --pbrt PBRT" if args.pbrt else "") + (" --blender BLENDER" if args.blender else "")
             + f" --spp {args.spp}` (its docstring describes the scene).", "",
             f"A slab under a uniform sky of 1, seen along its normal, {SIZE} x {SIZE} pixels at {args.spp} spp, "
             "2 threads: each channel's image mean ± its standard error over the pixels. Time: the whole process.", ""]
    lines += [f"## artist: reflectance {REFLECTANCE} asked for, mean free path 1, eta {ETA}", "",
              "| renderer | model | R | G | B | time s |", "|---|---|---|---|---|---|"]
    for who, how, mean, error, seconds in rows["artist"]:
        cells = " | ".join(f"{m:.4f} ± {e:.4f}" for m, e in zip(mean, error))
        lines.append(f"| {who} | {how} | {cells} | {seconds:.1f} |")
    lines += ["", f"## physical: sigma_t 1, grey single-scattering albedo {ALBEDOS[0]}, {ALBEDOS[1]} or "
              f"{ALBEDOS[2]} (a render each), eta {ETA}", "",
              "| renderer | model | " + " | ".join(f"albedo {a}" for a in ALBEDOS) + " | time s (all three) |",
              "|---|---|---|---|---|---|"]
    for who, how, mean, error, seconds in rows["physical"]:
        cells = " | ".join(f"{m:.4f} ± {e:.4f}" for m, e in zip(mean, error))
        lines.append(f"| {who} | {how} | {cells} | {seconds:.1f} |")
    lines.append("")
    with open(args.output, "w") as f:
        f.write("\n".join(lines))
    print("wrote", args.output)


if __name__ == "__main__":
    sys.exit(main())
