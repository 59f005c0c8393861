# Makes declared_9000x9000.exr from flipped_sums.exr (a 16x12 film): the same headers, but with
# windows, penumbra:resolution and penumbra:crop declaring 9000x9000 pixels, and chunk offset
# tables of that size, pointing past the end: the file holds none of the rows it declares.
# OpenEXR opens it; only a check of the declared size against the file stops a 19 GiB film.
import struct

N = 9000
LINES_PER_CHUNK = {0: 1, 1: 1, 2: 1, 3: 16}  # none, RLE, ZIPS, ZIP


def read_headers(data):
    pos, headers = 8, []
    while data[pos] != 0:
        attributes = []
        while data[pos] != 0:
            name_end = data.index(b"\0", pos)
            type_end = data.index(b"\0", name_end + 1)
            (size,) = struct.unpack_from("<i", data, type_end + 1)
            value = data[type_end + 5:type_end + 5 + size]
            attributes.append([data[pos:name_end], data[name_end + 1:type_end], value])
            pos = type_end + 5 + size
        headers.append(attributes)
        pos += 1
    return data[:8], headers


def write_attribute(name, type_name, value):
    return name + b"\0" + type_name + b"\0" + struct.pack("<i", len(value)) + value


source = open("flipped_sums.exr", "rb").read()
prefix, headers = read_headers(source)
out = bytearray(prefix)
chunk_counts = []
for attributes in headers:
    compression = 1
    for a in attributes:
        if a[0] in (b"dataWindow", b"displayWindow"):
            a[2] = struct.pack("<4i", 0, 0, N - 1, N - 1)
        elif a[0] == b"penumbra:resolution":
            a[2] = f"{N}x{N}".encode()
        elif a[0] == b"penumbra:crop":
            a[2] = f"0,{N},0,{N}".encode()
        elif a[0] == b"compression":
            compression = a[2][0]
    chunks = -(-N // LINES_PER_CHUNK[compression])
    for a in attributes:
        if a[0] == b"chunkCount":
            a[2] = struct.pack("<i", chunks)
    chunk_counts.append(chunks)
    for a in attributes:
        out += write_attribute(*a)
    out += b"\0"
out += b"\0"
end = len(out) + 8 * sum(chunk_counts)
for chunks in chunk_counts:
    for k in range(chunks):
        out += struct.pack("<Q", end + 1000 * k)  # every chunk lies past the end of the file
open("declared_9000x9000.exr", "wb").write(out)
