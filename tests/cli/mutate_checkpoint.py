#!/usr/bin/env python3
"""Write a copy of a cdm checkpoint (format 13) with one value of its state changed and
its checksums recomputed (each block's, then the header's over the blocks' table), as a
corrupted or hand-edited checkpoint would be.
Usage: mutate_checkpoint.py IN OUT FIELD VALUE
FIELD: time, steps, x0 (particle 0's x, in the stored order) or vx0."""
import math
import struct
import sys


def fnv1a64(data):
    h = 14695981039346656037
    for b in data:
        h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h


src, dst, field, value = sys.argv[1:5]
raw = bytearray(open(src, "rb").read())
header = 8 + 4 + 8 + 8
assert raw[:8] == b"CDMCKPT\n" and struct.unpack_from("<I", raw, 8)[0] == 13, "not a format 13 checkpoint"
length = struct.unpack_from("<Q", raw, 12)[0]
body = raw[header:header + length]
BLOCK = 1 << 16
at = 0


def u64():
    global at
    v = struct.unpack_from("<Q", body, at)[0]
    at += 8
    return v


def skip_bytes():
    global at
    length = u64()
    at += length


skip_bytes()  # scene name
skip_bytes()  # scene text
for _ in range(u64()):  # overrides: path, value
    skip_bytes()
    skip_bytes()
at += 1 + 8 + 1 + 8 + 8 + 8 + 1 + 8  # output marks: table, VTK, log
monitor_tables = u64()
at += 8 * monitor_tables  # their lengths
at += 1 + 8  # outlets.dat
u64()  # the state's length; the state follows
n = u64()
where = {"steps": at, "time": at + 8}
at += 8 + 8 + 1  # steps, time, forces valid
assert body[at] == 0, "a scene with insertions or outlets (not handled here)"
at += 1  # no population section
order = u64()
at += order * 4  # particle order
at += 8  # last sort
assert u64() == n
where["x0"] = at
at += 8 * n
for _ in range(2):  # y, z
    at += 8 + 8 * n
assert u64() == n
where["vx0"] = at
if field == "steps":
    struct.pack_into("<Q", body, where[field], int(value))
else:
    struct.pack_into("<d", body, where[field], float(value))
table = b"".join(struct.pack("<Q", fnv1a64(body[b:b + BLOCK])) for b in range(0, len(body), BLOCK))
assert len(raw) == header + length + len(table), "the file is not one body and its blocks' table"
struct.pack_into("<Q", raw, 20, fnv1a64(table))
raw[header:] = body + table
open(dst, "wb").write(raw)
