#!/usr/bin/python3
"""The tables of bench/run_bench.sh, from its runs file (bench/README.md).

    bench/summarise.py RUNS

RUNS has one line per run: code problem N steps loop_s rss_kb segments, where code is
cdm, lammps or liggghts (one core) or the same with a 2 (two cores: cdm on two OpenMP
threads, a peer on two MPI ranks), or cdmmpi2 (cdm on two MPI ranks of one thread), rss_kb is 0 where it was not measured, and segments
are the loop times of the run's segments, comma-separated. Prints Markdown:

- per problem and code: loop time (median and each repetition), particle-steps per
  second per core, peak memory per particle, cdm's speed against the code on as many
  cores, and two cores against one for the same code;
- per segment, for a problem timed in several (settle1e4);
- the cost per particle-step against N, one core, each code against its own cost at
  N = 1e4 (issue #7's target: within 1.25x at 1e6), on the same first 1000 steps
  (settle1e4early, the window settle1e6 is timed on) and on settle1e4's first segment.

A malformed line stops it with the line named, and nothing printed.
"""
import statistics
import sys
from collections import defaultdict

CODES = ("cdm", "cdm2", "cdmmpi2", "lammps", "lammps2", "liggghts", "liggghts2")


def one_core(code):
    if code == "cdmmpi2":  # cdm on two MPI processes of one thread
        return "cdm"
    return code[:-1] if code.endswith("2") else code


def label(code):
    return "cdm, 2 MPI ranks" if code == "cdmmpi2" else one_core(code)


def cores(code):
    return 2 if code.endswith("2") else 1


def cdm_beside(code):
    """The cdm run a peer's run is compared with (on as many cores), or None for cdm's own."""
    if one_core(code) == "cdm":
        return None
    return "cdm2" if cores(code) == 2 else "cdm"


def read(path):
    runs = defaultdict(list)  # (problem, code) -> [(loop, rss_kb, n, steps, [segments])]
    with open(path) as f:
        for k, line in enumerate(f, 1):
            if not line.strip():
                continue
            try:
                code, prob, n, steps, loop, rss, seg = line.split()
                if code not in CODES:
                    raise ValueError(f"unknown code {code!r} (one of {', '.join(CODES)})")
                row = (float(loop), int(rss), int(n), int(steps), [float(x) for x in seg.split(",")])
                if row[2] <= 0 or row[3] <= 0 or row[0] <= 0:
                    raise ValueError("N, steps and the loop time must be positive")
            except ValueError as e:
                sys.exit(f"{path}:{k}: {line.strip()!r}: expected 'code problem N steps loop_s rss_kb "
                         f"seg_s[,seg_s...]': {e}")
            runs[(prob, code)].append(row)
    return runs


def fmt_ratio(x):
    return f"{x:.2f}×"


def fmt_s(x):
    """A loop time: three decimals below a second (settle1e4early takes ~0.1 s), else two."""
    return f"{x:.3f}" if x < 1.0 else f"{x:.2f}"


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: summarise.py RUNS")
    runs = read(sys.argv[1])
    if not runs:
        sys.exit(f"{sys.argv[1]}: no runs")
    out = []
    med = {key: statistics.median(r[0] for r in rows) for key, rows in runs.items()}
    nrep = max(len(v) for v in runs.values())
    out.append(f"| problem | code | cores | N | steps | loop wall s (median of {nrep}) | per repetition s | "
               "particle-steps/s per core | peak RSS bytes/particle | cdm speed / code, same cores | "
               "2 cores / 1 core |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|")
    problems = sorted({p for p, _ in runs})
    for prob in problems:
        for code in CODES:
            if (prob, code) not in runs:
                continue
            rows = runs[(prob, code)]
            n, steps, c = rows[0][2], rows[0][3], cores(code)
            m = med[(prob, code)]
            rss = [r[1] for r in rows if r[1] > 0]
            rss_s = f"{statistics.median(rss) * 1024 / n:.0f}" if rss else "-"
            cdm = cdm_beside(code)
            vs = fmt_ratio(m / med[(prob, cdm)]) if (prob, cdm) in med else "-"
            scale = fmt_ratio(med[(prob, one_core(code))] / m) if c == 2 and (prob, one_core(code)) in med else "-"
            each = ", ".join(fmt_s(r[0]) for r in rows)
            out.append(f"| {prob} | {label(code)} | {c} | {n} | {steps} | {fmt_s(m)} | {each} | "
                       f"{n * steps / m / c:.3g} | {rss_s} | {vs} | {scale} |")

    # Per segment, where a problem was timed in several.
    for prob in problems:
        counts = {len(r[4]) for (p, _), rows in runs.items() if p == prob for r in rows}
        if max(counts) < 2:
            continue
        if len(counts) != 1:
            sys.exit(f"{sys.argv[1]}: {prob}'s runs have different numbers of segments: {sorted(counts)}")
        nseg = counts.pop()
        steps = next(rows[0][3] for (p, _), rows in runs.items() if p == prob)
        seg = {c: [statistics.median(r[4][k] for r in runs[(prob, c)]) for k in range(nseg)]
               for c in CODES if (prob, c) in runs}
        out.append("")
        out.append(f"{prob}, per segment of {steps // nseg} steps: loop wall s, median "
                   "(cdm speed / code, same cores)")
        out.append("")
        out.append("| code | cores | " + " | ".join(f"segment {k + 1}" for k in range(nseg)) + " |")
        out.append("|---|---|" + "---|" * nseg)
        for code, s in seg.items():
            cdm = cdm_beside(code)
            cells = [fmt_s(s[k]) + (f" ({s[k] / seg[cdm][k]:.2f})" if cdm in seg else "")
                     for k in range(nseg)]
            out.append(f"| {one_core(code)} | {cores(code)} | " + " | ".join(cells) + " |")

    # The cost per particle-step against N, one core.
    def cost(prob, code, first_segment=False):
        rows = runs.get((prob, code))
        if not rows:
            return None
        n, steps = rows[0][2], rows[0][3]
        if first_segment:
            k = len(rows[0][4])
            return statistics.median(r[4][0] for r in rows) / (n * steps / k)
        return med[(prob, code)] / (n * steps)

    columns = [("settle1e4early", False, "settle1e4, first 1000 steps"),
               ("settle1e4", True, "settle1e4, first segment"),
               ("settle1e5", False, "settle1e5"), ("settle1e6", False, "settle1e6")]
    columns = [c for c in columns if any((c[0], code) in runs for code in CODES)]
    if any(c[0] == "settle1e6" for c in columns) and any(c[0].startswith("settle1e4") for c in columns):
        out.append("")
        out.append("Cost per particle-step against N, one core: ns (median); the last columns divide settle1e6's "
                   "by the code's own at 1e4 (target for cdm: at most 1.25×)")
        out.append("")
        ratios = [c for c in columns if c[0].startswith("settle1e4")]
        out.append("| code | " + " | ".join(c[2] for c in columns) + " | " +
                   " | ".join(f"1e6 / {c[2]}" for c in ratios) + " |")
        out.append("|---|" + "---|" * (len(columns) + len(ratios)))
        for code in ("cdm", "lammps", "liggghts"):
            vals = {c[0]: cost(c[0], code, c[1]) for c in columns}
            if all(v is None for v in vals.values()):
                continue
            cells = [f"{vals[c[0]] * 1e9:.2f}" if vals[c[0]] is not None else "-" for c in columns]
            e6 = vals.get("settle1e6")
            cells += [fmt_ratio(e6 / vals[c[0]]) if e6 is not None and vals[c[0]] is not None else "-"
                      for c in ratios]
            out.append(f"| {code} | " + " | ".join(cells) + " |")
    print("\n".join(out))


if __name__ == "__main__":
    main()
