#!/usr/bin/env python3
"""Write a copy of a cdm checkpoint (format 12) with one value of its state changed and
its checksum recomputed, as a corrupted or hand-edited checkpoint would be.
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
assert raw[:8] == b"CDMCKPT\n" and struct.unpack_from("<I", raw, 8)[0] == 12, "not a format 12 checkpoint"
body = raw[header:]
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
struct.pack_into("<Q", raw, 20, fnv1a64(body))
raw[header:] = body
open(dst, "wb").write(raw)
