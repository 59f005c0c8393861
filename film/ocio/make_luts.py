#!/usr/bin/env python3
"""Writes the 1D LUTs of penumbra's OpenColorIO config (film/ocio/config.ocio) into this folder.

Run it after changing a curve: /usr/bin/python3 film/ocio/make_luts.py
The LUTs are inputs of the config, read by OpenColorIO's FileTransform (.spi1d, Sony Imageworks'
1D format, which OpenColorIO 2.1 reads); the transforms around them are in the config.

filmic.spi1d (view "Filmic"): the input is log2 encoded by the config over 16.5 stops,
log2(value) from -12.47393 to 4.026069 (AgX's range, Sobotka 2022), so that middle grey 0.18
sits at x = 0.606 and comes out at 0.497, 1.0 at 0.787, 16 (4 stops over 1) at 0.998. The curve is the 6th-degree polynomial fit of AgX's default sigmoid
(Wrensch 2023, as used by several real-time AgX implementations):
    y = 15.5 x^6 - 40.14 x^5 + 31.96 x^4 - 6.868 x^3 + 0.4298 x^2 + 0.1191 x - 0.00232,
clamped to [0, 1]; its output is display-encoded (taken as sRGB code values).

false-color.spi1d (view "False Color"): the input is the luminance (Rec.709 weights), log2
encoded by the config over 13 stops centred on middle grey (x = 0.5 at 0.18, one stop = 1/13);
each band of stops gets a colour (RGB, display-encoded).
"""

import os

HERE = os.path.dirname(os.path.abspath(__file__))
SIZE = 4096


def agx_sigmoid(x):
    x2 = x * x
    x4 = x2 * x2
    y = 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x - 0.00232
    return min(1.0, max(0.0, y))


# (stops above middle grey where the band ends, colour); the last band runs to the end.
FALSE_COLOR_BANDS = [
    (-6.0, (0.0, 0.0, 0.0)),     # below 6 stops under: black (crushed)
    (-4.0, (0.35, 0.0, 0.55)),   # deep shadow: purple
    (-2.0, (0.0, 0.25, 0.9)),    # shadow: blue
    (-0.5, (0.0, 0.65, 0.75)),   # dark: cyan
    (0.5, (0.5, 0.5, 0.5)),      # middle grey +- half a stop: grey
    (2.0, (0.25, 0.75, 0.2)),    # light: green
    (4.0, (0.95, 0.85, 0.0)),    # bright: yellow
    (6.0, (1.0, 0.45, 0.0)),     # very bright: orange
    (None, (1.0, 0.0, 0.0)),     # 6 stops over and more: red (clipping in most views)
]


def false_color(x):
    stops = (x - 0.5) * 13.0
    for end, colour in FALSE_COLOR_BANDS:
        if end is None or stops < end:
            return colour
    raise AssertionError


def write_spi1d(name, rows, components):
    with open(os.path.join(HERE, name), "w", encoding="ascii") as f:
        f.write(f"Version 1\nFrom 0.0 1.0\nLength {len(rows)}\nComponents {components}\n{{\n")
        for row in rows:
            f.write(" " + " ".join(f"{v:.6f}" for v in row) + "\n")
        f.write("}\n")


def main():
    xs = [i / (SIZE - 1) for i in range(SIZE)]
    filmic = [agx_sigmoid(x) for x in xs]
    assert all(b >= a for a, b in zip(filmic, filmic[1:])), "the sigmoid must be monotonic"
    write_spi1d("filmic.spi1d", [(y,) for y in filmic], 1)
    write_spi1d("false-color.spi1d", [false_color(x) for x in xs], 3)


if __name__ == "__main__":
    main()
