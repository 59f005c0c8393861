#!/usr/bin/env python3
"""Packs a NanoVDB file into the nanovdb fuzz target's input, or unpacks one: each run of zero bytes
becomes a 0 byte followed by its length as LEB128 (fuzz/nanovdb_fuzzer.cpp says why).

    nanovdb_pack.py pack FILE.nvdb OUT      e.g. the seeds of fuzz/corpus/nanovdb/
    nanovdb_pack.py unpack INPUT OUT.nvdb   e.g. a finding, to read it as a file
"""
import sys


def pack(data: bytes) -> bytes:
    out = bytearray()
    i = 0
    while i < len(data):
        if data[i] != 0:
            out.append(data[i])
            i += 1
            continue
        j = i
        while j < len(data) and data[j] == 0:
            j += 1
        out.append(0)
        count = j - i
        while True:
            byte = count & 0x7F
            count >>= 7
            out.append(byte | (0x80 if count else 0))
            if not count:
                break
        i = j
    return bytes(out)


def unpack(data: bytes) -> bytes:
    out = bytearray()
    i = 0
    while i < len(data):
        if data[i] != 0:
            out.append(data[i])
            i += 1
            continue
        i += 1
        count, shift = 0, 0
        while i < len(data) and shift < 64:
            byte = data[i]
            i += 1
            count |= (byte & 0x7F) << shift
            shift += 7
            if not byte & 0x80:
                break
        out.extend(bytes(min(count, (64 << 20) - len(out))))
    return bytes(out)


def main() -> int:
    if len(sys.argv) != 4 or sys.argv[1] not in ("pack", "unpack"):
        print(__doc__, file=sys.stderr)
        return 2
    with open(sys.argv[2], "rb") as f:
        data = f.read()
    result = pack(data) if sys.argv[1] == "pack" else unpack(data)
    with open(sys.argv[3], "wb") as f:
        f.write(result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
