#!/usr/bin/env python3
"""Writes the measured_bsdf fuzzer's seeds (corpus/measured_bsdf/): small valid RGL tensor files, an
isotropic RGB one, a spectral one and an anisotropic one of reduction 2, whose fields the fuzzer
mutates. The format: materials/measured_bsdf_reader.h and core/tensor_file.h.

    measured_bsdf_seeds.py CORPUS_FOLDER
"""
import math
import pathlib
import struct
import sys


def tensor_file(fields):
    header = 12 + 2 + 4 + sum(2 + len(n) + 2 + 1 + 8 + 8 * len(shape) for n, _, shape, _ in fields)
    out = bytearray(b"tensor_file\0" + bytes([1, 0]) + struct.pack("<I", len(fields)))
    offset = header
    for name, dtype, shape, data in fields:
        out += struct.pack("<H", len(name)) + name.encode() + struct.pack("<HBQ", len(shape), dtype, offset)
        out += b"".join(struct.pack("<Q", n) for n in shape)
        offset += len(data)
    for *_, data in fields:
        out += data
    return bytes(out)


def floats(name, shape, values):
    return (name, 10, shape, struct.pack(f"<{len(values)}f", *values))


def uint8(name, data):
    return (name, 1, [len(data)], data)


def seed(phi, theta=(0.0, 0.8, 1.5), n=3, spectral=False):
    p, t = len(phi), len(theta)
    cells = n * n
    fields = [uint8("description", b"seed"), uint8("jacobian", b"\x01"), floats("theta_i", [t], theta),
              floats("phi_i", [p], phi), floats("ndf", [n, n], [1.0 + i for i in range(cells)]),
              floats("sigma", [n, n], [0.5 + 0.1 * i for i in range(cells)]),
              floats("vndf", [p, t, n, n], [1.0 + (i % 5) for i in range(p * t * cells)]),
              floats("luminance", [p, t, n, n], [0.5 + (i % 3) for i in range(p * t * cells)])]
    if spectral:
        wavelengths = [400.0, 550.0, 700.0]
        fields += [floats("wavelengths", [3], wavelengths),
                   floats("spectra", [p, t, 3, n, n], [0.2 + 0.01 * (i % 7) for i in range(p * t * 3 * cells)])]
    else:
        fields.append(floats("rgb", [p, t, 3, n, n], [0.3 + 0.01 * (i % 11) for i in range(p * t * 3 * cells)]))
    return tensor_file(fields)


def main():
    folder = pathlib.Path(sys.argv[1])
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "isotropic-rgb.bsdf").write_bytes(seed([0.0]))
    (folder / "isotropic-spectral.bsdf").write_bytes(seed([0.0], spectral=True))
    (folder / "anisotropic-half.bsdf").write_bytes(seed([-math.pi, -math.pi / 2, 0.0], n=2))


if __name__ == "__main__":
    main()
