#!/usr/bin/python3
"""Build the cdm verification report from the harness's plain tables alone.

    /usr/bin/python3 reports/make_report.py --in verification-out --out report

Reads IN/summary.dat, IN/provenance.dat and per case IN/<case>/errors.dat, series/,
and (after `cdm verify --sweep`) errors_sweep.dat and work_precision.dat; the physics
text comes from each case's README in verification/cases/. Writes OUT/index.html with
PNG figures in OUT/fig/. Uses Debian's python3-matplotlib (call /usr/bin/python3).
"""
import argparse
import html
import math
import re
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = Path(__file__).resolve().parent


def read_table(path):
    """Rows of a whitespace table as dicts keyed by the last '#' header's column names."""
    cols, rows = None, []
    for line in Path(path).read_text().splitlines():
        if line.startswith("#"):
            words = line[1:].split()
            if words and words[0] in ("case", "t[s]", "bounce[-]"):
                cols = words
            continue
        if not line.strip() or cols is None:
            continue
        vals = line.split()
        rows.append(dict(zip(cols, vals)))
    return rows


def read_series(path):
    cols, data = None, []
    for line in Path(path).read_text().splitlines():
        if line.startswith("#"):
            cols = line[1:].split()
            continue
        if line.strip():
            data.append([float(x) for x in line.split()])
    return cols, list(zip(*data)) if data else []


def num(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return math.nan


def physics_text(case_dir):
    readme = case_dir / "README.md"
    if not readme.exists():
        return "", ""
    text = readme.read_text()
    title = text.splitlines()[0].lstrip("# ").strip()
    m = re.search(r"\*\*Physics\.\*\*(.*?)(\n\n|$)", text, re.S)
    phys = " ".join(m.group(1).split()) if m else ""
    sentences = re.split(r"(?<=[.!?])\s+", phys)
    return title, " ".join(sentences[:2])


class Report:
    def __init__(self, src, out, cases_dir):
        self.src, self.out, self.cases_dir = src, out, cases_dir
        self.fig_dir = out / "fig"
        self.fig_dir.mkdir(parents=True, exist_ok=True)
        self.parts = []

    def figure(self, fig, name, caption):
        path = self.fig_dir / f"{name}.png"
        fig.tight_layout()
        fig.savefig(path, dpi=110)
        plt.close(fig)
        self.parts.append(
            f'<figure><img src="fig/{name}.png" alt="{html.escape(caption)}">'
            f"<figcaption>{html.escape(caption)}</figcaption></figure>"
        )

    def note(self, text):
        self.parts.append(f'<p class="note">{html.escape(text)}</p>')

    def h(self, level, text, anchor=None):
        a = f' id="{anchor}"' if anchor else ""
        self.parts.append(f"<h{level}{a}>{html.escape(text)}</h{level}>")

    def p(self, text):
        self.parts.append(f"<p>{html.escape(text)}</p>")

    def table(self, header, rows, classes=None):
        out = ["<table><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr>"]
        for k, r in enumerate(rows):
            cls = f' class="{classes[k]}"' if classes and classes[k] else ""
            out.append(f"<tr{cls}>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>")
        out.append("</table>")
        self.parts.append("\n".join(out))

    # ---------------------------------------------------------------- per case
    def series_path(self, case, variant, integ, div):
        return self.src / case / "series" / f"{variant}_{integ}_dt{div}.dat"

    def convergence_plot(self, case, rows, quantity, norm, ylabel):
        runs = defaultdict(list)
        for r in rows:
            if r["quantity"] == quantity and r["norm"] == norm and r["dt_divisor[-]"] != "all":
                e = num(r["error"])
                if e > 0 and math.isfinite(e):
                    runs[(r["variant"], r["integrator"])].append((num(r["dt[s]"]), e))
        if not runs:
            return
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for (variant, integ), pts in sorted(runs.items()):
            pts.sort()
            ax.loglog(*zip(*pts), "o-" if integ == "paper_euler" else "s--", ms=3, label=f"{variant} {integ}")
        dts = [p[0] for v in runs.values() for p in v]
        errs = [p[1] for v in runs.values() for p in v]
        d0, e0 = min(dts), max(errs)
        for order, style in ((1, ":"), (2, "-.")):
            xs = [d0, max(dts)]
            ax.loglog(xs, [e0 * 0.3 * (x / max(dts)) ** order for x in xs], "k" + style, lw=1, label=f"slope {order}")
        ax.set_xlabel("time step dt [s]")
        ax.set_ylabel(ylabel)
        ax.set_title(f"{case}: convergence of {quantity} ({norm})")
        ax.legend(fontsize=6, ncol=2)
        self.figure(fig, f"{case}_convergence", f"{case}: {quantity} error against dt, both integrators")

    def work_precision_plot(self, case, quantity, norm):
        path = self.src / case / "errors_sweep.dat"
        if not path.exists():
            self.note(f"{case}: no errors_sweep.dat (run `cdm verify --sweep`): work-precision plot skipped.")
            return
        rows = read_table(path)
        runs = defaultdict(list)
        for r in rows:
            if r["quantity"] == quantity and r["norm"] == norm and r["dt_divisor[-]"] != "all":
                e, w = num(r["error"]), num(r["wall[s]"])
                if e > 0 and w > 0 and math.isfinite(e):
                    runs[(r["variant"], r["integrator"])].append((w, e))
        if not runs:
            return
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for (variant, integ), pts in sorted(runs.items()):
            pts.sort()
            ax.loglog(*zip(*pts), "o-" if integ == "paper_euler" else "s--", ms=3, label=f"{variant} {integ}")
        for lvl in (1, 0.1, 0.01):
            ax.axhline(lvl, color="grey", lw=0.6, ls=":")
        ax.set_xlabel("solver wall time per run [s]")
        ax.set_ylabel(f"{quantity} error [%]")
        ax.set_title(f"{case}: work-precision ({quantity})")
        ax.legend(fontsize=6, ncol=2)
        self.figure(fig, f"{case}_work_precision", f"{case}: error against wall time over the dense dt sweep")
        wp = self.src / case / "work_precision.dat"
        if wp.exists():
            wrows = [r for r in read_table(wp) if r["quantity"] == quantity and r["norm"] == norm]
            self.table(
                ["variant", "integrator", "target [%]", "cheapest dt", "error [%]", "wall [s]"],
                [[r["variant"], r["integrator"], r["target[%]"],
                  ("t_col/" + r["dt_divisor[-]"]) if r["reached"] == "yes" else "not reached",
                  r["error[%]"], r["wall[s]"]] for r in wrows])

    def error_table(self, rows):
        keep = [r for r in rows if r["dt_divisor[-]"] in ("50", "all") and r["norm"] != "count"]
        classes = ["pass" if r["pass"] == "yes" else "fail" if r["pass"] == "no" else "" for r in keep]
        self.table(
            ["variant", "integrator", "dt", "quantity", "norm", "error", "tolerance", "pass", "wall [s]"],
            [[r["variant"], r["integrator"], "t_col/" + r["dt_divisor[-]"] if r["dt_divisor[-]"] != "all" else "order",
              r["quantity"], r["norm"], f'{num(r["error"]):.4g}', r["tolerance"], r["pass"], r["wall[s]"]]
             for r in keep], classes)

    # ---------------------------------------------------------------- paper figures
    def fig_free_fall(self, case):
        s = self.series_path(case, "kn5e7_en0.9", "paper_euler", 50)
        if not s.exists():
            self.note("Fig 4a: series missing.")
            return
        cols, d = read_series(s)
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
        a1.plot(d[0], [y * 100 for y in d[2]], "k-", lw=1.5, label="oracle (App. B)")
        a1.plot(d[0], [y * 100 for y in d[1]], "r--", lw=1, label="cdm, paper scheme, t_col/50")
        a1.set_ylabel("centre height y [cm]")
        a1.legend(fontsize=8)
        a2.plot(d[0], [v * 100 for v in d[4]], "k-", lw=1.5, label="oracle")
        a2.plot(d[0], [v * 100 for v in d[3]], "r--", lw=1, label="cdm")
        a2.set_ylabel("velocity [cm/s]")
        a2.set_xlabel("t [s]")
        a1.set_title("Fig 4a: free fall, kn = 5e7 dyn/cm, en = 0.9")
        self.figure(fig, "fig4a", "Fig 4a: position and velocity of the falling sphere, cdm against the exact solution")
        fig, ax = plt.subplots(figsize=(7, 4))
        for v in ("kn5e7_en1.0", "kn5e7_en0.9", "kn1e7_en0.9", "kn5e7_en0.7"):
            sp = self.series_path(case, v, "paper_euler", 50)
            if sp.exists():
                _, d = read_series(sp)
                ax.plot(d[0], [100 * abs(a - b) / abs(a) for a, b in zip(d[2], d[1])], lw=1, label=v)
        ax.axhline(1.0, color="k", ls=":", lw=1, label="paper: < 1 %")
        ax.axhline(1.6, color="r", ls="--", lw=1, label="cdm tolerance 1.6 %")
        ax.set_ylim(0, 5)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("error in y [%] (eq 37)")
        ax.set_title("Fig 4b: percent error of y, paper scheme at t_col/50")
        ax.legend(fontsize=7)
        self.figure(fig, "fig4b", "Fig 4b: percent error of the centre height; (1e7, 0.9) exceeds it only as y approaches 0")

    def fig_bounces(self, case):
        def apex(variant):
            p = self.src / case / "series" / f"{variant}_paper_euler_dt50_apex.dat"
            return read_series(p)[1] if p.exists() else None

        fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
        for v in ("kn5e7_en1.0", "kn5e7_en0.9", "kn5e7_en0.7", "kn5e7_en0.5"):
            d = apex(v)
            if d:
                line, = a1.plot(d[0], [x * 100 for x in d[1]], "o", ms=4, label=f"cdm {v}")
                a1.plot(d[0], [x * 100 for x in d[3]], "-", color=line.get_color(), lw=1, label="hard sphere")
                a1.plot(d[0], [x * 100 for x in d[2]], "x", color=line.get_color(), ms=5)
        a1.set_xlabel("bounce k")
        a1.set_ylabel("maximum centre height [cm]")
        a1.set_title("Fig 5a: kn = 5e7 dyn/cm (x: exact soft sphere)")
        a1.legend(fontsize=6)
        for v in ("kn5e7_en0.9", "kn5e9_en0.9"):
            d = apex(v)
            if d:
                a2.plot(d[0], [100 * (c - h) / h for c, h in zip(d[1], d[3])], "o-", ms=3, label=f"cdm - hard, {v}")
        a2.set_xlabel("bounce k")
        a2.set_ylabel("difference from hard sphere [%]")
        a2.set_title("Fig 5b: en = 0.9, the difference shrinks as kn grows")
        a2.legend(fontsize=7)
        self.figure(fig, "fig5", "Fig 5: rebound heights against the hard-sphere heights (h0 - r) en^2k + r")

    def fig_stacked(self, case):
        fig, axes = plt.subplots(2, 2, figsize=(10, 6), sharex=True)
        for col, v in enumerate(("en1.0", "en0.8")):
            s = self.series_path(case, v, "paper_euler", 50)
            if not s.exists():
                continue
            _, d = read_series(s)
            t = [x * 1e3 for x in d[0]]
            ax = axes[0][col]
            ax.plot(t, [x * 100 for x in d[2]], "k-", lw=1.5, label="y1 oracle (CVODE)")
            ax.plot(t, [x * 100 for x in d[1]], "r--", lw=1, label="y1 cdm")
            ax.plot(t, [x * 100 for x in d[4]], "b-", lw=1.5, label="y2 oracle")
            ax.plot(t, [x * 100 for x in d[3]], "c--", lw=1, label="y2 cdm")
            ax.set_ylabel("centre height [cm]")
            ax.set_title(f"Fig 7: stacked particles, {v}")
            ax.legend(fontsize=6)
            ax = axes[1][col]
            ax.plot(t, [100 * (b - a) / a for a, b in zip(d[2], d[1])], "r-", lw=1, label="y1")
            ax.plot(t, [100 * (b - a) / a for a, b in zip(d[4], d[3])], "b-", lw=1, label="y2")
            for sgn in (1, -1):
                ax.axhline(0.2 * sgn, color="k", ls=":", lw=1)
            ax.set_xlabel("t [ms]")
            ax.set_ylabel("error [%] (paper bound 0.2 %)")
            ax.set_title(f"Fig 8: error, paper scheme at t_col/50, {v}")
            ax.legend(fontsize=6)
        self.figure(fig, "fig7_8", "Figs 7-8: stacked particles, cdm against the CVODE solution of App. C, and the error")

    def fig_slipping(self, case):
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for v, mu in (("mu0.2", 0.2), ("mu0.4", 0.4), ("mu0.6", 0.6), ("mu0.8", 0.8)):
            s = self.series_path(case, v, "paper_euler", 50)
            if not s.exists():
                continue
            _, d = read_series(s)
            v0, g, R = 0.1, 9.81, 5e-4
            tn = [mu * g * t / v0 for t in d[0]]
            line, = ax.plot(tn, [x / v0 for x in d[1]], "-", lw=1, label=f"v/v0, mu = {mu}")
            ax.plot(tn, [w * R / v0 for w in d[3]], "--", color=line.get_color(), lw=1)
        ax.axvline(2 / 7, color="k", ls=":", lw=1, label="t' = 2/7")
        ax.axhline(5 / 7, color="k", ls="-.", lw=1, label="5/7")
        ax.set_xlim(0, 0.6)
        ax.set_xlabel("t' = mu g t / v0")
        ax.set_ylabel("v/v0 (solid), omega R/v0 (dashed)")
        ax.set_title("Fig 10: slipping ball, all mu collapse onto the exact solution")
        ax.legend(fontsize=6)
        self.figure(fig, "fig10", "Fig 10: non-dimensional velocity and spin; slip ends at t' = 2/7 with v' = omega' R/v0 = 5/7")

    # ---------------------------------------------------------------- Hertz-Mindlin (issue 8)
    def fig_hertz_impact(self, case):
        rows = [(v, integ) for v, integ in (("v1", "velocity_verlet"), ("steel_v1", "velocity_verlet"))
                if self.series_path(case, v, integ, 50).exists()]
        if not rows:
            self.note(f"{case}: force-time series missing.")
            return
        variant, integ = rows[0]
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
        for div, style in ((50, "o"), (400, "-")):
            sp = self.series_path(case, variant, integ, div)
            if not sp.exists():
                continue
            _, d = read_series(sp)
            t = [x * 1e6 for x in d[0]]
            if div == 50:
                a1.plot(t, d[4], "k-", lw=1.5, label="oracle (CVODE of the Hertz equation)")
                a1.plot(t, d[3], "r" + style, ms=3, label="cdm, t_H/50")
            fmax = max(d[4]) or 1.0
            a2.plot(t, [100 * (b - a) / fmax for a, b in zip(d[4], d[3])], style if div == 400 else "o-", ms=2, lw=1,
                    label=f"t_H/{div}")
        a1.set_ylabel("contact force [N]")
        a1.legend(fontsize=7)
        a1.set_title(f"{case}: force on the sphere, {variant}")
        a2.set_xlabel("t [us]")
        a2.set_ylabel("error, % of F_max")
        a2.legend(fontsize=7)
        self.figure(fig, f"{case}_force", f"{case}: Hertz contact force against time, cdm and the CVODE oracle, and the error")

    def fig_restitution(self, case):
        fig, ax = plt.subplots(figsize=(7, 4.5))
        shown = False
        for variant, marker in (("exact_restitution", "o"), ("tsuji", "s")):
            for integ, div, color in (("velocity_verlet", 100, "r"), ("velocity_verlet", 800, "b")):
                sp = self.series_path(case, variant, integ, div)
                if not sp.exists():
                    continue
                _, d = read_series(sp)
                ax.plot(d[0], [100 * (m - a) / a for a, m in zip(d[0], d[2])], marker + "-", color=color, ms=4, lw=1,
                        mfc="none" if variant == "tsuji" else color, label=f"cdm {variant}, {integ} t_H/{div}")
                if div == 800:
                    ax.plot(d[0], [100 * (o - a) / a for a, o in zip(d[0], d[3])], marker + ":", color="k", ms=4,
                            mfc="none", lw=1, label=f"the rule itself (CVODE), {variant}")
                shown = True
        if not shown:
            self.note(f"{case}: series missing.")
            plt.close(fig)
            return
        for sgn in (1, -1):
            ax.axhline(0.5 * sgn, color="grey", ls="--", lw=0.8)
        ax.set_xlabel("en asked for")
        ax.set_ylabel("(e measured - en)/en [%]")
        ax.set_title("Hertz restitution: rebound/incident speed against en (issue: within 0.5 %)")
        ax.legend(fontsize=6)
        self.figure(fig, f"{case}_en", f"{case}: restitution measured against the en asked for, for both damping rules")

    def fig_oblique(self, case):
        sp = self.series_path(case, "alumina_on_glass", "velocity_verlet", 50)
        if not sp.exists():
            self.note(f"{case}: series missing.")
            return
        _, d = read_series(sp)
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
        a1.plot(d[0], d[2], "k-", lw=1.5, label="oracle: CVODE Mindlin ODE")
        a1.plot(d[0], d[3], "g--", lw=2, label="gross-sliding closed form")
        a1.plot(d[0], d[4], "c:", lw=1, label="rigid sphere 5 mu v_n/R")
        a1.plot(d[0], d[1], "ro", ms=4, label="cdm, t_H/50")
        a1.set_xlabel("incidence angle from the normal [deg]")
        a1.set_ylabel("rebound spin [rad/s]")
        a1.legend(fontsize=7)
        a2.plot(d[0], d[6], "k-", lw=1.5, label="oracle: CVODE Mindlin ODE")
        a2.plot(d[0], d[7], "g--", lw=2, label="1 - 2 mu / tan(theta)")
        a2.plot(d[0], d[5], "ro", ms=4, label="cdm, t_H/50")
        a2.set_xlabel("incidence angle from the normal [deg]")
        a2.set_ylabel("tangential restitution v_t'/v_t")
        a2.legend(fontsize=7)
        fig.suptitle("Oblique impact, alumina on glass at 3.9 m/s, mu = 0.092 (Kharaz et al. 2001 / MFIX DEM05)")
        self.figure(fig, f"{case}_angles", f"{case}: rebound spin and tangential restitution over the incidence angle")

    def fig_rolling(self, case):
        fig, ax = plt.subplots(figsize=(7, 4.2))
        shown = False
        for variant, color in (("linear", "r"), ("hertz_mindlin", "b")):
            sp = self.series_path(case, variant, "velocity_verlet", 50)
            if not sp.exists():
                continue
            cols, d = read_series(sp)
            ax.plot(d[0], d[2], "k-", lw=2.5, alpha=0.4)
            ax.plot(d[0], d[1], "--", color=color, lw=1, label=f"cdm {variant}, velocity Verlet t_col/50")
            unit = cols[1] if cols else ""
            shown = True
        if not shown:
            self.note(f"{case}: series missing.")
            plt.close(fig)
            return
        ax.plot([], [], "k-", lw=2.5, alpha=0.4, label="closed form")
        ax.set_xlabel("t [s]")
        ax.set_ylabel(unit)
        ax.set_title(f"{case}: deceleration by rolling resistance and the stop")
        ax.legend(fontsize=7)
        self.figure(fig, f"{case}_series", f"{case}: cdm against the closed form, both contact laws")

    # ---------------------------------------------------------------- assemble
    MAIN = {
        "free_fall": ("y", "max_rel_pct", "error in y [%]"),
        "free_fall_bounces": ("apex_soft", "max_rel_pct", "error in apex height [%]"),
        "stacked": ("y1", "max_rel_pct", "error in y1 [%]"),
        "slipping_ball": ("v", "max_rel_pct", "error in v [%]"),
        "hertz_impact_wall": ("force", "max_abs_pct_of_peak", "force error [% of F_max]"),
        "hertz_impact_pair": ("force", "max_abs_pct_of_peak", "force error [% of F_max]"),
        "hertz_restitution": ("e_vs_ode", "max_rel_pct", "restitution error vs CVODE [%]"),
        "oblique_impact": ("omega", "max_abs_pct_of_peak", "rebound spin error [% of max]"),
        "rolling_resistance_spin": ("omega", "max_abs_pct_of_initial", "spin error [% of initial]"),
    }
    PAPER = {"free_fall": "fig_free_fall", "free_fall_bounces": "fig_bounces", "stacked": "fig_stacked",
             "slipping_ball": "fig_slipping", "hertz_impact_wall": "fig_hertz_impact",
             "hertz_impact_pair": "fig_hertz_impact", "hertz_restitution": "fig_restitution",
             "oblique_impact": "fig_oblique", "rolling_resistance": "fig_rolling",
             "rolling_resistance_spin": "fig_rolling"}

    def build(self):
        summary = self.src / "summary.dat"
        if not summary.exists():
            sys.exit(f"make_report: {summary} not found: run `cdm verify --out {self.src}` first")
        summ = []
        for line in summary.read_text().splitlines():
            if line.startswith("#") or not line.strip():
                continue
            c, passed, failed, worst, wall = line.split()
            summ.append((c, int(passed), int(failed), float(worst), float(wall)))
        prov = {}
        pp = self.src / "provenance.dat"
        if pp.exists():
            for line in pp.read_text().splitlines():
                if not line.startswith("#") and line.strip():
                    k, _, v = line.partition(" ")
                    prov[k] = v
        self.h(1, "cdm verification report")
        self.table(["provenance", ""], [[k, v] for k, v in prov.items()])
        self.h(2, "Summary", "summary")
        self.table(["case", "result", "checks passed", "failed", "worst error / tolerance", "solver wall [s]"],
                   [[f"{c}", "PASS" if f == 0 else "FAIL", p, f, f"{w:.3g}", f"{wall:.3g}"] for c, p, f, w, wall in summ],
                   ["pass" if f == 0 else "fail" for _, _, f, _, _ in summ])
        for c, *_ in summ:
            case_dir = self.cases_dir / c
            title, phys = physics_text(case_dir)
            self.h(2, title or c, c)
            if phys:
                self.p(phys)
            case_toml = case_dir / "case.toml"
            if case_toml.exists():
                variants = re.findall(r'name = "([^"]+)"', case_toml.read_text())
                self.p("Variants: " + ", ".join(variants) + ". Integrators: paper_euler (A.1-A.3), velocity_verlet; "
                       "dt = t_col/50, /100, /200, /400.")
            rows = read_table(self.src / c / "errors.dat")
            oracles = sorted({r["oracle"] for r in rows if r.get("oracle", "-") != "-"})
            self.p("Oracle: " + "; ".join(oracles))
            if c in self.PAPER:
                getattr(self, self.PAPER[c])(c)
            if c in self.MAIN:
                q, norm, label = self.MAIN[c]
                self.convergence_plot(c, rows, q, norm, label)
                self.work_precision_plot(c, q, norm)
            self.h(3, "Errors at t_col/50 and observed orders")
            self.error_table(rows)
        css = """body{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em}
table{border-collapse:collapse;margin:0.5em 0;font-size:0.8em}td,th{border:1px solid #ccc;padding:2px 6px}
tr.pass td{background:#e6f5e6}tr.fail td{background:#f8d7d7}figure{margin:1em 0}img{max-width:100%}
figcaption{font-size:0.85em;color:#444}.note{color:#855}"""
        page = ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>cdm verification report</title>"
                f"<style>{css}</style></head><body>\n" + "\n".join(self.parts) + "\n</body></html>\n")
        (self.out / "index.html").write_text(page)
        return self.out / "index.html"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--in", dest="src", required=True, help="folder written by cdm verify")
    ap.add_argument("--out", required=True, help="report folder to write")
    ap.add_argument("--cases", default=str(HERE.parent / "verification" / "cases"), help="case folders")
    a = ap.parse_args()
    path = Report(Path(a.src), Path(a.out), Path(a.cases)).build()
    print(path)


if __name__ == "__main__":
    main()
