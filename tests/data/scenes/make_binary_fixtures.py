#!/usr/bin/env python3
"""Writes the binary and gzip mesh fixtures of tests/data/scenes/meshes (run from anywhere)."""
import gzip
import math
import pathlib
import struct

here = pathlib.Path(__file__).resolve().parent / "meshes"

SQUARE = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1)]
FACES = [(0, 1, 2, 3), (0, 1, 4)]


def binary_ply(endian, vertices, faces, with_normals):
    """A binary PLY; vertices carry an extra uchar 'red' the loader must step over."""
    mark = "<" if endian == "little" else ">"
    header = ["ply", f"format binary_{endian}_endian 1.0",
              f"element vertex {len(vertices)}", "property float x", "property float y", "property float z"]
    if with_normals:
        header += ["property float nx", "property float ny", "property float nz"]
    header += ["property uchar red", f"element face {len(faces)}",
               "property list uchar int vertex_indices", "end_header"]
    body = b""
    for v in vertices:
        body += struct.pack(mark + "3f", *v)
        if with_normals:
            body += struct.pack(mark + "3f", 0, 0, 2)  # not unit: the loader normalizes
        body += struct.pack(mark + "B", 200)
    for f in faces:
        body += struct.pack(mark + "B", len(f)) + struct.pack(mark + f"{len(f)}i", *f)
    return ("\n".join(header) + "\n").encode() + body


def write(name, data):
    (here / name).write_bytes(data)


little = binary_ply("little", SQUARE, FACES, with_normals=True)
write("square_binary_le.ply", little)
write("square_binary_be.ply", binary_ply("big", SQUARE, FACES, with_normals=False))
write("truncated_binary.ply", little[:-9])  # the last face loses most of its indices
write("nan_vertex_binary.ply",
      binary_ply("little", [(0, 0, 0), (1, 0, 0), (1, math.inf, 0)], [(0, 1, 2)], with_normals=False))
ascii_square = (here / "square_ascii.ply").read_bytes()
write("square.ply.gz", gzip.compress(ascii_square, mtime=0))
write("truncated.ply.gz", gzip.compress(ascii_square, mtime=0)[:-20])
