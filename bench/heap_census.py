#!/usr/bin/python3
"""Names the allocations of a heap_census file (bench/heap_census.cpp) and sums them by
call site: resident and allocated MiB, count, and the first cdm frames of the stack.

    heap_census.py CENSUS [--depth N]
"""
import argparse
import collections
import subprocess
import sys


def parse(path):
    rss, rows = None, []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            fields = line.split()
            if n == 1:
                if len(fields) != 2 or fields[0] != 'rss':
                    sys.exit(f'{path}:1: expected "rss BYTES", got {line.strip()!r}')
                rss = int(fields[1])
                continue
            if len(fields) < 2:
                sys.exit(f'{path}:{n}: expected "BYTES RESIDENT FRAME...", got {line.strip()!r}')
            frames = []
            for fr in fields[2:]:
                off, _, obj = fr.partition('@')
                frames.append((obj, int(off, 16)))
            rows.append((int(fields[0]), int(fields[1]), frames))
    if rss is None:
        sys.exit(f'{path}: empty')
    return rss, rows


def names(rows):
    """{(object, offset): function name} through one addr2line call per object file."""
    by_obj = collections.defaultdict(set)
    for _, _, frames in rows:
        for obj, off in frames:
            by_obj[obj].add(off)
    out = {}
    for obj, offs in by_obj.items():
        offs = sorted(offs)
        # The return address points after the call: look up the byte before it.
        r = subprocess.run(['addr2line', '-f', '-C', '-e', obj] + [hex(max(o - 1, 0)) for o in offs],
                           capture_output=True, text=True)
        lines = r.stdout.split('\n')
        for k, off in enumerate(offs):
            name = lines[2 * k] if 2 * k < len(lines) else '??'
            out[(obj, off)] = name.split('(')[0] if name != '??' else f'{obj.rsplit("/", 1)[-1]}+{off:x}'
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('census')
    ap.add_argument('--depth', type=int, default=3, help='cdm frames that name a call site (default 3)')
    a = ap.parse_args()
    rss, rows = parse(a.census)
    name = names(rows)
    sites = collections.defaultdict(lambda: [0, 0, 0])
    for size, res, frames in rows:
        own = [name[f] for f in frames if name[f].startswith('cdm::')]
        key = ' < '.join(own[:a.depth]) if own else (name[frames[2]] if len(frames) > 2 else '?')
        s = sites[key]
        s[0] += res
        s[1] += size
        s[2] += 1
    mib = 1 << 20
    print(f'resident at the census: {rss / mib:.1f} MiB; in the allocations below: '
          f'{sum(s[0] for s in sites.values()) / mib:.1f} MiB')
    print(f'{"resident MiB":>12} {"allocated MiB":>13} {"count":>5}  call site')
    for key, (res, size, count) in sorted(sites.items(), key=lambda kv: -kv[1][0]):
        print(f'{res / mib:12.1f} {size / mib:13.1f} {count:5d}  {key}')


if __name__ == '__main__':
    main()
