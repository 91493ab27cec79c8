#!/usr/bin/env python3
"""Re-encodes a PNG written by examples/c/png.h (stored deflate) with zlib level 9, for the
pictures committed under docs/. Usage: shrink_png.py IN.png OUT.png"""
import struct
import sys
import zlib


def chunks(data):
    pos = 8
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        yield data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)


src = open(sys.argv[1], "rb").read()
parts = list(chunks(src))
idat = zlib.decompress(b"".join(body for kind, body in parts if kind == b"IDAT"))
out = src[:8] + chunk(b"IHDR", dict(parts)[b"IHDR"]) + chunk(b"IDAT", zlib.compress(idat, 9)) + chunk(b"IEND", b"")
open(sys.argv[2], "wb").write(out)
