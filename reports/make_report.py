#!/usr/bin/python3
"""Build the cdm verification report from the harness's plain tables alone.

    /usr/bin/python3 reports/make_report.py --in verification-out --out report

Reads IN/summary.dat, IN/provenance.dat and per case IN/<case>/errors.dat, series/,
and (after `cdm verify --sweep`) errors_sweep.dat and work_precision.dat; the physics
text, the parameters and the tolerances' reasons come from each case's folder in
verification/cases/ (README.md, case.toml, tolerances.toml, scene.toml). Writes
OUT/index.html with PNG figures in OUT/fig/ and copies of the error tables in OUT/data/.
Uses Debian's python3-matplotlib (call /usr/bin/python3).

A case whose tables are missing is skipped with a note; a figure whose series are
missing is skipped with a note; a case this script has no special figures for gets the
generic treatment (parameters, convergence and work-precision plots, error table). A
figure that fails to draw for any other reason is noted in the page and on stderr as
"could not draw", and the exit status is 3 (the report is still written).
"""
import argparse
import html
import math
import re
import shutil
import sys
import tomllib
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter, NullLocator  # noqa: E402

HERE = Path(__file__).resolve().parent


class Missing(Exception):
    """A table or series the figure needs is not there: the figure is skipped with a note."""


# ------------------------------------------------------------------------------ tables
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
        if len(vals) == len(cols):  # a short row is a table still being written: left out
            rows.append(dict(zip(cols, vals)))
    return rows


def read_series(path):
    """A numeric series table: (column names, list of columns)."""
    path = Path(path)
    if not path.exists():
        raise Missing(f"series {path.name} not found")
    cols, data = None, []
    for line in path.read_text().splitlines():
        if line.startswith("#"):
            cols = line[1:].split()
            continue
        if line.strip():
            data.append([float(x) for x in line.split()])
    return cols, list(zip(*data)) if data else []


def series(path):
    """A numeric series table as {column name without unit: numpy array}."""
    cols, d = read_series(path)
    if not d:
        raise Missing(f"series {Path(path).name} is empty")
    return {re.sub(r"\[.*\]$", "", c): np.array(col) for c, col in zip(cols, d)}


def num(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return math.nan


def fmt_div(div):
    """A dt divisor as the harness spells it in file names (printf %g)."""
    return f"{float(div):g}"


def natural_key(s):
    """Sort key that orders grid16 < grid32 < grid128 and St0.002 < St0.2 < St2 < St20."""
    return [(0, float(t), "") if re.fullmatch(r"\d+(\.\d*)?", t) else (1, 0.0, t)
            for t in re.split(r"(\d+(?:\.\d*)?)", s) if t]


def physics_text(case_dir):
    readme = case_dir / "README.md"
    if not readme.exists():
        return "", ""
    text = readme.read_text()
    title = text.splitlines()[0].lstrip("# ").strip()
    m = re.search(r"\*\*Physics\.\*\*(.*?)(\n\n|$)", text, re.S)
    phys = " ".join(re.sub(r"\n\s*-\s+", " ", m.group(1)).split()) if m else ""  # list items run on
    # Sentence ends: a full stop before a capital, not after "et al." or "e.g.".
    sentences = re.split(r"(?<!\bal\.)(?<!e\.g\.)(?<!i\.e\.)(?<=[.!?])\s+(?=[A-Z(])", phys)
    return title, " ".join(sentences[:2])


def load_toml(path):
    try:
        return tomllib.loads(path.read_text()) if path.exists() else {}
    except tomllib.TOMLDecodeError as e:
        print(f"make_report: warning: {path}: {e}", file=sys.stderr)
        return {}


class CaseMeta:
    """What the case folder says about a case: sweep, variants, grid families, tolerances."""

    def __init__(self, case_dir, errors_path):
        self.dir = case_dir
        self.toml = load_toml(case_dir / "case.toml")
        sweep = self.toml.get("sweep", {})
        self.integrators = list(sweep.get("integrators", []))
        self.dt_divisors = sorted(float(d) for d in sweep.get("dt_divisors", []))
        self.sweep_divisors = sorted(float(d) for d in sweep.get("sweep_dt_divisors", []))
        self.variants = [v for v in self.toml.get("variants", []) if "name" in v]
        self.family = {v["name"]: v.get("family", "") for v in self.variants}
        self.h = {v["name"]: float(v["h"]) for v in self.variants if "h" in v}
        self.oracle = {v["name"]: v.get("oracle", {}) for v in self.variants}
        self.families = sorted({f for f in self.family.values() if f}, key=natural_key)
        self.tolerances = load_toml(case_dir / "tolerances.toml").get("tolerance", [])
        self.scene = load_toml(case_dir / "scene.toml")
        self.title, self.physics = physics_text(case_dir)
        # What the dt_divisor column means: the table's own header first, then case.toml.
        self.divisor = ""
        if errors_path.exists():
            for line in errors_path.read_text().splitlines()[:8]:
                m = re.match(r"#\s*dt_divisor N:\s*(.*)", line)
                if m:
                    self.divisor = m.group(1).strip()
        self.divisor = self.divisor or sweep.get("divisor", "") or "dt = t_col/N"
        m = re.search(r"dt\s*=\s*([^\s,;]+?)\s*/\s*N\b", self.divisor)
        self.symbol = m.group(1) if m else "t_col"

    def dt_label(self, div):
        return f"{self.symbol}/{fmt_div(div)}"

    def group_of(self, variant):
        """The grid family of a variant; a variant without one joins the family its name starts with."""
        if self.family.get(variant):
            return self.family[variant]
        for f in sorted(self.families, key=len, reverse=True):
            if variant.startswith(f + "_"):
                return f
        return ""

    def integrator_index(self, integ):
        if integ not in self.integrators:
            self.integrators.append(integ)
        return self.integrators.index(integ)


INTEG_STYLES = ["o-", "s--", "^-.", "d:", "v-", "x--"]


def clip_reference(ax, xs, anchor, orders):
    """Reference slopes through `anchor` (x, e) over xs, without stretching the data's y range."""
    lo, hi = ax.get_ylim()
    styles = {1: ":", 2: "-.", 3: "--", 4: (0, (1, 3))}
    x0, e0 = anchor
    for p in orders:
        ys = [e0 * (x / x0) ** p for x in xs]
        ax.loglog(xs, ys, color="k", ls=styles.get(p, ":"), lw=0.8, label=f"slope {p}")
    ax.set_ylim(lo, hi)


def tidy_log(ax):
    """On log axes showing at most one power of ten, minor tick labels at 2 and 5 only (the
    default labels overlap or leave a single labelled tick); none on longer axes."""
    def label(x, _):
        if x <= 0:
            return ""
        mant = x / 10 ** math.floor(math.log10(x) + 1e-9)
        return f"{x:.0e}".replace("e-0", "e-").replace("e+0", "e") if round(mant) in (2, 5) else ""

    for axis, lim in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        if axis.get_scale() != "log" or lim[0] <= 0:
            continue
        lo, hi = sorted(lim)
        if math.floor(math.log10(hi)) - math.ceil(math.log10(lo)) + 1 <= 1:
            axis.set_minor_formatter(FuncFormatter(label))
            ax.tick_params(axis="x" if axis is ax.xaxis else "y", which="minor", labelsize=7)
        else:
            axis.set_minor_formatter(NullFormatter())


def symlog_index_axis(ax, bottom):
    """A clustering-index axis: linear within +-0.5 (where random points fall), logarithmic above."""
    ax.set_yscale("symlog", linthresh=0.5, linscale=1.0)
    top = 1.6 * ax.get_ylim()[1]
    ax.set_ylim(bottom, top)
    ticks = [t for t in (-0.2, 0, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500) if bottom <= t <= top]
    ax.yaxis.set_major_locator(FixedLocator(ticks))
    ax.yaxis.set_minor_locator(NullLocator())
    ax.set_yticklabels([f"{t:g}" for t in ticks])


def legend_below(ax, ncol=2):
    """A legend under the axes (for panels with many lines)."""
    ax.legend(fontsize=6, ncol=ncol, loc="upper center", bbox_to_anchor=(0.5, -0.16), frameon=False)


# ------------------------------------------------------------------------------ report
class Report:
    def __init__(self, src, out, cases_dir):
        self.src, self.out, self.cases_dir = src, out, cases_dir
        self.fig_dir = out / "fig"
        self.fig_dir.mkdir(parents=True, exist_ok=True)
        self.parts = []
        self.failures = 0
        self.meta = None

    # ------------------------------------------------------------------ html pieces
    def figure(self, fig, name, caption, rect=None):
        path = self.fig_dir / f"{name}.png"
        fig.tight_layout(rect=rect)
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

    def p(self, text, raw=False):
        body = text if raw else re.sub(r"`([^`]+)`", r"<code>\1</code>", html.escape(text))
        self.parts.append(f"<p>{body}</p>")

    @staticmethod
    def table_html(header, rows, classes=None):
        def cell(c):
            return c[1] if isinstance(c, tuple) and c[0] == "raw" else html.escape(str(c))

        out = ["<table><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr>"]
        for k, r in enumerate(rows):
            cls = f' class="{classes[k]}"' if classes and classes[k] else ""
            out.append(f"<tr{cls}>" + "".join(f"<td>{cell(c)}</td>" for c in r) + "</tr>")
        out.append("</table>")
        return "\n".join(out)

    def table(self, header, rows, classes=None):
        self.parts.append(self.table_html(header, rows, classes))

    def details(self, summary, inner):
        self.parts.append(f"<details><summary>{html.escape(summary)}</summary>\n{inner}\n</details>")

    def guarded(self, what, fn, *args):
        """Draw one figure; a missing series becomes a note, any other failure a loud note."""
        try:
            fn(*args)
        except Missing as e:
            plt.close("all")
            self.note(f"{what}: skipped, {e}.")
        except Exception as e:  # a broken figure must not cost the rest of the report
            plt.close("all")
            self.failures += 1
            msg = f"{what}: could not draw ({type(e).__name__}: {e})"
            self.note(msg)
            print(f"make_report: warning: {msg}", file=sys.stderr)

    # ------------------------------------------------------------------ per-case parts
    def series_path(self, case, variant, integ, div, suffix=""):
        return self.src / case / "series" / f"{variant}_{integ}_dt{fmt_div(div)}{suffix}.dat"

    def parameters(self, case):
        m = self.meta
        if not m.toml:
            if m.dir.exists():
                self.note(f"{case}: no readable case.toml in {m.dir}: parameters not shown.")
            return
        divs = ", ".join(fmt_div(d) for d in m.dt_divisors)
        sweep = ", ".join(fmt_div(d) for d in m.sweep_divisors)
        self.p(f"Integrators: {', '.join(m.integrators)}. Time step: {m.divisor}; N = {divs}"
               + (f" (`cdm verify --sweep`: N = {sweep})." if sweep else "."))
        if not m.variants:
            return
        keys = []
        for v in m.variants:
            for k in v.get("oracle", {}):
                if k not in keys:
                    keys.append(k)
        common = {k: m.oracle[m.variants[0]["name"]].get(k) for k in keys
                  if all(m.oracle[v["name"]].get(k) == m.oracle[m.variants[0]["name"]].get(k) for v in m.variants)}
        varying = [k for k in keys if k not in common]
        if common:
            self.p("Oracle parameters (SI, every variant): " + ", ".join(f"{k} = {v:g}" if isinstance(v, (int, float))
                                                                        else f"{k} = {v}" for k, v in common.items()) + ".")
        has_family = any(v.get("family") for v in m.variants)
        header = ["variant"] + (["grid family", "h [m]"] if has_family else []) + ["scene overrides"] + varying
        rows = []
        for v in m.variants:
            row = [v["name"] + (" (sweep only)" if v.get("sweep_only") else "")]
            if has_family:
                row += [v.get("family", "-"), f'{v["h"]:g}' if "h" in v else "-"]
            row.append("; ".join(v.get("set", [])) or "-")
            row += [f'{m.oracle[v["name"]].get(k, "-"):.5g}' if isinstance(m.oracle[v["name"]].get(k), (int, float))
                    else str(m.oracle[v["name"]].get(k, "-")) for k in varying]
            rows.append(row)
        self.table(header, rows)

    def tolerance_table(self):
        m = self.meta
        if not m.tolerances:
            return
        rows = []
        for t in m.tolerances:
            where = ", ".join(f"{k} {t[k]}" for k in ("variant", "integrator", "dt_divisor") if k in t) or "all runs"
            if t.get("report_only"):
                bound = "reported only"
            elif "min_order" in t:
                bound = f">= {t['min_order']:g} (order)"
            elif "min" in t:
                bound = f">= {t['min']:g}"
            elif "max" in t:
                bound = f"<= {t['max']:g}"
                if "order" in t:
                    bound += f" x ({t.get('ref_divisor', '?'):g}/N)^{t['order']:g}" if isinstance(
                        t.get("ref_divisor"), (int, float)) else f" (scaled as dt^{t['order']:g})"
            else:
                bound = "-"
            rows.append([where, t.get("quantity", "-"), t.get("norm", "-"), bound, t.get("reason", "")])
        self.details(f"Tolerances and their reasons ({len(rows)} entries of tolerances.toml; the first match wins)",
                     self.table_html(["applies to", "quantity", "norm", "bound", "reason"], rows))

    def run_points(self, rows, quantity, norm, xkey):
        """{(variant, integrator): [(x, error)]} for one quantity and norm over the dt sweep."""
        runs = defaultdict(list)
        for r in rows:
            if r["quantity"] == quantity and r["norm"] == norm and r["dt_divisor[-]"] != "all":
                e, x = num(r["error"]), num(r[xkey])
                if e > 0 and x > 0 and math.isfinite(e):
                    runs[(r["variant"], r["integrator"])].append((x, e))
        return runs

    def panel_plot(self, runs, xlabel, ylabel, title, slopes=(), hlines=(), top=None):
        """Log-log lines per (variant, integrator), one panel per grid family; returns the figure."""
        m = self.meta
        groups = defaultdict(dict)
        for key, pts in runs.items():
            groups[m.group_of(key[0])][key] = sorted(pts)
        names = sorted(groups, key=natural_key)
        cols = 1 if len(names) == 1 else 2
        nrow = math.ceil(len(names) / cols)

        def short(v, g):  # the variant without its family prefix: the same legend in every panel
            return v[len(g) + 1:] if g and v.startswith(g + "_") else v

        labels = [sorted((short(v, g), i) for v, i in groups[g]) for g in names]
        shared = len(names) > 1 and all(lab == labels[0] for lab in labels)
        extra = len(slopes) + sum(1 for hl in hlines if hl[1])
        entries = len(labels[0]) + extra
        many = not shared and max(len(lab) for lab in labels) + extra > 6
        legend_rows = math.ceil(entries / 4) if shared else 0
        fig, axes = plt.subplots(nrow, cols, figsize=(7.5 if cols == 1 else 12,
                                                      (4.6 if nrow == 1 else 4.1 * nrow) + 0.2 * legend_rows
                                                      + (0.12 * math.ceil(entries / 2) if many else 0)),
                                 squeeze=False)
        for ax, g in zip(axes.flat, names):
            variants = sorted({short(v, g) for v, _ in groups[g]}, key=natural_key)
            for (v, integ), pts in sorted(groups[g].items(), key=lambda kv: (natural_key(short(kv[0][0], g)), kv[0][1])):
                style = INTEG_STYLES[m.integrator_index(integ) % len(INTEG_STYLES)]
                ax.loglog(*zip(*pts), style, color=f"C{variants.index(short(v, g)) % 10}", ms=3, lw=1,
                          label=f"{short(v, g) if shared else v}, {integ}")
            for y, label, color in hlines:
                ax.axhline(y, color=color, ls=":", lw=1, label=label)
            xs = sorted({p[0] for pts in groups[g].values() for p in pts})
            if slopes and len(xs) > 1:
                at_max = [pts[-1][1] for pts in groups[g].values() if pts[-1][0] == xs[-1]]
                anchor = (xs[-1], 0.3 * min(at_max) if at_max else 0.3 * min(p[1] for pts in groups[g].values() for p in pts))
                clip_reference(ax, [xs[0], xs[-1]], anchor, slopes)
            if top:
                c, ticks, label = top
                sec = ax.secondary_xaxis("top", functions=(lambda x: c / np.clip(x, 1e-300, None),
                                                            lambda n: c / np.clip(n, 1e-300, None)))
                sec.xaxis.set_major_locator(FixedLocator(ticks))
                sec.xaxis.set_minor_locator(NullLocator())
                sec.set_xticklabels([fmt_div(t) for t in ticks], fontsize=7)
                sec.set_xlabel(label, fontsize=8)
            tidy_log(ax)
            ax.set_xlabel(xlabel)
            ax.set_ylabel(ylabel)
            ax.set_title(f"{title}: {g}" if g else title, fontsize=10)
            ax.grid(True, which="major", alpha=0.3)
            if many:
                legend_below(ax)
            elif not shared:
                ax.legend(fontsize=6)
        for ax in list(axes.flat)[len(names):]:
            ax.set_visible(False)
        rect = None
        if shared:
            h, lab = axes.flat[0].get_legend_handles_labels()
            fig.legend(h, lab, loc="lower center", ncol=4, fontsize=7, frameon=False)
            rect = (0, (0.22 * legend_rows + 0.1) / fig.get_figheight(), 1, 1)
        return fig, rect

    def top_axis(self, rows, divisors):
        """(dt * N, ticks, label) when every run shares one time scale (dt = scale/N), else None."""
        scales = {round(num(r["dt[s]"]) * num(r["dt_divisor[-]"]), 12) for r in rows
                  if r["dt_divisor[-]"] != "all" and math.isfinite(num(r["dt[s]"]))}
        if len(scales) != 1:
            return None
        short = self.meta.divisor.split(",")[0]
        return scales.pop(), divisors, f"N ({short})"

    def convergence_plot(self, case, rows, conv):
        m = self.meta
        runs = self.run_points(rows, conv["quantity"], conv["norm"], "dt[s]")
        if not runs:
            raise Missing(f"no {conv['quantity']} ({conv['norm']}) rows in errors.dat")
        fig, rect = self.panel_plot(runs, "time step dt [s]", conv["ylabel"], f"{case}: {conv['quantity']} against dt",
                              conv.get("slopes", (1, 2)), conv.get("hlines", ()),
                              self.top_axis(rows, sorted({num(r["dt_divisor[-]"]) for r in rows
                                                          if r["dt_divisor[-]"] != "all"})))
        self.figure(fig, f"{case}_convergence",
                    f"{case}: {conv['quantity']} ({conv['norm']}) against the time step, every variant and integrator "
                    f"({m.divisor}); black lines: reference slopes.", rect)

    def grid_plot(self, case, rows, grid):
        """Error against the cell size h per grid family, at the finest and coarsest dt."""
        m = self.meta
        q, norm = grid["quantity"], grid["norm"]
        pts = defaultdict(list)
        for r in rows:
            v = r["variant"]
            if r["quantity"] == q and r["norm"] == norm and v in m.h and r["dt_divisor[-]"] != "all":
                e = num(r["error"])
                if e > 0 and math.isfinite(e):
                    pts[(r["integrator"], m.family[v], num(r["dt_divisor[-]"]))].append((m.h[v], e))
        pts = {k: sorted(v) for k, v in pts.items() if len(v) >= 2}
        if not pts:
            raise Missing(f"no grid family with two grids for {q} ({norm})")
        orders = {(r["integrator"], r["variant"][:-len("_grids")], num(r["dt_divisor[-]"])): (num(r["error"]), r["pass"])
                  for r in rows if r["norm"] == norm + "_grid_order" and r["quantity"] == q}
        integs = sorted({k[0] for k in pts}, key=m.integrator_index)
        cols = min(len(integs), 3)
        n_lines = max(len({k[1] for k in pts if k[0] == i}) for i in integs) * 2 + 2
        fig, axes = plt.subplots(1, cols, figsize=(5.2 * cols if cols > 1 else 7.5,
                                                   4.6 + (0.16 * math.ceil(n_lines / 2) if n_lines > 6 else 0)),
                                 squeeze=False)
        for ax, integ in zip(axes.flat, integs):
            fams = sorted({k[1] for k in pts if k[0] == integ}, key=natural_key)
            for j, fam in enumerate(fams):
                divs = sorted({k[2] for k in pts if k[0] == integ and k[1] == fam})
                for div, ls in ((divs[-1], "o-"), (divs[0], "s--")) if len(divs) > 1 else ((divs[-1], "o-"),):
                    o = orders.get((integ, fam, div))
                    label = f"{fam}, {m.dt_label(div)}" + (f" (order {o[0]:.2f})" if o else "")
                    ax.loglog(*zip(*pts[(integ, fam, div)]), ls, color=f"C{j % 10}", ms=4, lw=1, label=label)
            hs = sorted({p[0] for k, v in pts.items() if k[0] == integ for p in v})
            finest = [v[0][1] for k, v in pts.items() if k[0] == integ]
            clip_reference(ax, [hs[0], hs[-1]], (hs[0], 0.5 * min(finest)), (1, 2))
            tidy_log(ax)
            ax.set_xlabel("cell size h [m]")
            ax.set_ylabel(grid["ylabel"])
            ax.set_title(f"{case}: {q} against h, {integ}", fontsize=10)
            ax.grid(True, which="major", alpha=0.3)
            if len(ax.get_legend_handles_labels()[1]) > 6:
                legend_below(ax)
            else:
                ax.legend(fontsize=6)
        for ax in list(axes.flat)[len(integs):]:
            ax.set_visible(False)
        self.figure(fig, f"{case}_grid_convergence",
                    f"{case}: {q} ({norm}) against the cell size per grid family, at the finest (solid) and coarsest "
                    f"(dashed) step of the sweep, with the observed grid order from errors.dat; "
                    f"{integs[0] if len(integs) == 1 else 'one panel per integrator'}.")

    def work_precision_plot(self, case, conv):
        m = self.meta
        path = self.src / case / "errors_sweep.dat"
        if not path.exists():
            self.note(f"{case}: no errors_sweep.dat (run `cdm verify --sweep`): work-precision plot skipped.")
            return
        quantity, norm = conv["quantity"], conv["norm"]
        runs = self.run_points(read_table(path), quantity, norm, "wall[s]")
        if not runs:
            raise Missing(f"no {quantity} ({norm}) rows in errors_sweep.dat")
        pct = "pct" in norm
        fig, rect = self.panel_plot(runs, "solver wall time per run [s]", conv["ylabel"], f"{case}: work-precision",
                                    hlines=[(lvl, None, "grey") for lvl in (1, 0.1, 0.01)] if pct else conv.get("hlines", ()))
        self.figure(fig, f"{case}_work_precision", rect=rect, caption=
                    f"{case}: {quantity} error against solver wall time over the dense dt sweep (N = "
                    f"{', '.join(fmt_div(d) for d in m.sweep_divisors)}); dotted: 1 %, 0.1 %, 0.01 %" if pct else
                    f"{case}: {quantity} error against solver wall time over the dense dt sweep")
        wp = self.src / case / "work_precision.dat"
        if wp.exists():
            wrows = read_table(wp)
            norms = [n for n in dict.fromkeys(r["norm"] for r in wrows if r["quantity"] == quantity)]
            use = norm if norm in norms else (norms[0] if norms else None)
            wrows = [r for r in wrows if r["quantity"] == quantity and r["norm"] == use]
            if wrows:
                self.p(f"Cheapest run of the sweep reaching each target ({quantity}, {use}):")
                self.table(
                    ["variant", "integrator", "target [%]", "cheapest dt", "error [%]", "wall [s]"],
                    [[r["variant"], r["integrator"], r["target[%]"],
                      m.dt_label(r["dt_divisor[-]"]) if r["reached"] == "yes" else "not reached",
                      r["error[%]"], r["wall[s]"]] for r in wrows])

    def error_table(self, case, rows):
        m = self.meta

        def div_text(r):
            d = r["dt_divisor[-]"]
            return "order in dt" if d == "all" else m.dt_label(d)

        def line(r):
            return [r["variant"], r["integrator"], div_text(r), r["quantity"], r["norm"], f'{num(r["error"]):.4g}',
                    r["tolerance"], r["pass"], f'{num(r["wall[s]"]):.3g}' if r["wall[s]"] != "-" else "-"]

        header = ["variant", "integrator", "dt", "quantity", "norm", "error", "tolerance", "pass", "wall [s]"]
        cls = {"yes": "pass", "no": "fail"}
        # Shown: per series the checked row at its coarsest checked step (the hardest), every
        # checked order in dt or h, and every failure wherever it is.
        first = {}
        for r in rows:
            if r["pass"] not in ("yes", "no") or r["dt_divisor[-]"] == "all" or r["norm"].endswith("_order"):
                continue
            key = (r["variant"], r["integrator"], r["quantity"], r["norm"])
            if key not in first or num(r["dt_divisor[-]"]) < num(first[key]["dt_divisor[-]"]):
                first[key] = r
        keep = [r for r in rows if r["pass"] == "no" or (r["pass"] == "yes" and (
            r["norm"].endswith("_order") or first.get((r["variant"], r["integrator"], r["quantity"], r["norm"])) is r))]
        n_checked = sum(r["pass"] in ("yes", "no") for r in rows)
        n_fail = sum(r["pass"] == "no" for r in rows)
        self.h(3, "Error table")
        self.p(f"{n_checked} checks against tolerance, {n_fail} failed. Shown: each checked series at its coarsest "
               f"checked step, every checked order (norm ..._order: in dt over the sweep; ..._grid_order: in h over "
               f"the grid family, at the dt given), and every failure. '>=' marks a lower bound. dt: {m.divisor}.")
        self.table(header, [line(r) for r in keep], [cls.get(r["pass"], "") for r in keep])
        sweep = self.src / case / "errors_sweep.dat"
        if sweep.exists():
            bad = [r for r in read_table(sweep) if r["pass"] == "no"]
            if bad:
                self.p(f"The dense dt sweep (errors_sweep.dat) fails {len(bad)} check(s):")
                self.table(header, [line(r) for r in bad], ["fail"] * len(bad))
        self.details(f"All {len(rows)} rows of errors.dat (including those only reported)",
                     self.table_html(header, [line(r) for r in rows], [cls.get(r["pass"], "") for r in rows]))
        data = self.out / "data" / case
        data.mkdir(parents=True, exist_ok=True)
        links = []
        for name in ("errors.dat", "errors_sweep.dat", "work_precision.dat"):
            if (self.src / case / name).exists():
                shutil.copyfile(self.src / case / name, data / name)
                links.append(f'<a href="data/{html.escape(case)}/{name}">{name}</a>')
        self.p("The tables themselves: " + ", ".join(links) + ".", raw=True)

    # ------------------------------------------------------------------ paper figures: DEM
    def fig_free_fall(self, case):
        _, d = read_series(self.series_path(case, "kn5e7_en0.9", "paper_euler", 50))
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

        if not any(apex(v) for v in ("kn5e7_en1.0", "kn5e7_en0.9", "kn5e7_en0.7", "kn5e7_en0.5")):
            raise Missing("no *_paper_euler_dt50_apex.dat series")
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
        if not any(self.series_path(case, v, "paper_euler", 50).exists() for v in ("en1.0", "en0.8")):
            raise Missing("no en1.0/en0.8 paper_euler series at t_col/50")
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
        drawn = 0
        for v, mu in (("mu0.2", 0.2), ("mu0.4", 0.4), ("mu0.6", 0.6), ("mu0.8", 0.8)):
            s = self.series_path(case, v, "paper_euler", 50)
            if not s.exists():
                continue
            _, d = read_series(s)
            v0, g, R = 0.1, 9.81, 5e-4
            tn = [mu * g * t / v0 for t in d[0]]
            line, = ax.plot(tn, [x / v0 for x in d[1]], "-", lw=1, label=f"v/v0, mu = {mu}")
            ax.plot(tn, [w * R / v0 for w in d[3]], "--", color=line.get_color(), lw=1)
            drawn += 1
        if not drawn:
            plt.close(fig)
            raise Missing("no mu*_paper_euler_dt50 series")
        ax.axvline(2 / 7, color="k", ls=":", lw=1, label="t' = 2/7")
        ax.axhline(5 / 7, color="k", ls="-.", lw=1, label="5/7")
        ax.set_xlim(0, 0.6)
        ax.set_xlabel("t' = mu g t / v0 [-]")
        ax.set_ylabel("v/v0 (solid), omega R/v0 (dashed) [-]")
        ax.set_title("Fig 10: slipping ball, all mu collapse onto the exact solution")
        ax.legend(fontsize=6)
        self.figure(fig, "fig10", "Fig 10: non-dimensional velocity and spin; slip ends at t' = 2/7 with v' = omega' R/v0 = 5/7")

    # ------------------------------------------------------------------ paper figures: gas
    def family_runs(self, case, prefer_family, prefer_integ):
        """The variants of the preferred grid family (coarse to fine), an integrator and the divisors."""
        m = self.meta
        fam = prefer_family if prefer_family in m.families else (m.families[0] if m.families else "")
        variants = sorted((v for v in m.h if m.family[v] == fam), key=lambda v: -m.h[v])
        integ = prefer_integ if prefer_integ in m.integrators else (m.integrators[-1] if m.integrators else "")
        if not variants or not integ or not m.dt_divisors:
            raise Missing(f"case.toml of {case} names no grid family, integrator or dt divisors")
        return fam, variants, integ

    def fig_vortex_positions(self, case, three_d):
        """Fig 12: the tracers at T/2 (largest deformation), cdm and the exact-field oracle, and the t = 0 shell."""
        m = self.meta
        fam, variants, integ = self.family_runs(case, "lagrange2", "rk4")
        div = m.dt_divisors[-1]
        present = [v for v in variants if self.series_path(case, v, integ, div, "_half_period").exists()]
        if not present:
            raise Missing(f"no {fam} {integ} {m.dt_label(div)} _half_period series")
        shells = m.scene.get("shells", [{}])
        centre, radius = shells[0].get("center"), shells[0].get("shell_radius")
        period = m.oracle[present[0]].get("period", 0.25)
        coarse, fine = present[0], present[-1]
        sc, sf = (series(self.series_path(case, v, integ, div, "_half_period")) for v in (coarse, fine))
        planes = (("x", "y"), ("x", "z")) if three_d else (("x", "y"),)
        fig, axes = plt.subplots(1, len(planes) + 1, figsize=(5.2 * (len(planes) + 1), 5.6), squeeze=False)
        axes = axes[0]
        for ax, (a, b) in zip(axes, planes):
            if not three_d:
                # The shape of eq 43's field (its amplitude is cos(pi t/T): full at t = 0, zero at T/2).
                gx, gy = np.meshgrid(np.linspace(0.025, 0.975, 20), np.linspace(0.025, 0.975, 20))
                u = 2 * np.sin(np.pi * gx) ** 2 * np.sin(2 * np.pi * gy)
                v = -np.sin(2 * np.pi * gx) * np.sin(np.pi * gy) ** 2
                ax.quiver(gx, gy, u, v, color="0.75", width=0.003, scale=25, label="gas velocity at t = 0 (eq 43)")
            if centre and radius:
                th = np.linspace(0, 2 * np.pi, 200)
                ia, ib = "xyz".index(a), "xyz".index(b)
                ax.plot(centre[ia] + radius * np.cos(th), centre[ib] + radius * np.sin(th), "k:", lw=1,
                        label="tracers at t = 0" + (" (sphere outline)" if three_d else ""))
            ax.plot(sf[a + "_oracle"], sf[b + "_oracle"], "o", mfc="none", mec="k", ms=5, lw=0,
                    label="oracle at T/2 (exact field, CVODE)")
            ax.plot(sc[a], sc[b], ".", color="C3", ms=4, label=f"cdm at T/2, {coarse}")
            ax.plot(sf[a], sf[b], "+", color="C0", ms=5, label=f"cdm at T/2, {fine}")
            ax.set_xlim(sf[a].min() - 0.08, sf[a].max() + 0.08)
            ax.set_ylim(sf[b].min() - 0.08, sf[b].max() + 0.08)
            ax.set_aspect("equal")
            ax.set_xlabel(f"{a} [m]")
            ax.set_ylabel(f"{b} [m]")
            ax.set_title(f"tracers at t = T/2 = {period / 2:g} s ({integ}, {m.dt_label(div)})", fontsize=9)
            legend_below(ax)
        ax = axes[-1]
        for j, v in enumerate(present):
            s = series(self.series_path(case, v, integ, div, "_half_period"))
            d = np.max(np.abs(np.stack([s["x"] - s["x_oracle"], s["y"] - s["y_oracle"], s["z"] - s["z_oracle"]])), axis=0)
            ax.semilogy(s["id"], d, "-", color=f"C{j}", lw=1, label=f"{v} (h = {m.h[v]:g} m)")
        ax.set_xlabel("tracer index (along the initial " + ("Fibonacci lattice" if three_d else "circle") + ") [-]")
        ax.set_ylabel("|x_cdm - x_oracle| at T/2, max over axes [m]")
        ax.set_title(f"distance from the exact-field path at T/2: the grid error ({fam})", fontsize=9)
        ax.grid(True, which="major", alpha=0.3)
        legend_below(ax)
        name = "Fig 12 analogue (3D)" if three_d else "Fig 12"
        self.figure(fig, f"{case}_fig12",
                    f"{name}: tracer positions at T/2 on the coarsest and finest {fam} grids ({integ}, "
                    f"{m.dt_label(div)}) against the exact-field oracle, with the initial "
                    f"{'sphere (projections)' if three_d else 'circle'}; right: each tracer's distance from its exact "
                    f"path at T/2 on every grid (falls as h^2).")

    def fig_vortex_return(self, case, three_d):
        """Fig 13: L-infinity return distance against the number of cycles, with the paper's bound."""
        m = self.meta
        fam, variants, integ = self.family_runs(case, "lagrange2", "rk4")
        fine = variants[-1]
        bound = 2.5e-5
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(14, 4.6))
        drawn = 0
        for i, integ_i in enumerate(m.integrators):
            for j, div in enumerate(m.dt_divisors):
                p = self.series_path(case, fine, integ_i, div)
                if p.exists():
                    s = series(p)
                    a1.semilogy(s["cycle"], np.maximum(s["return_Linf"], 1e-16), INTEG_STYLES[i % 6], color=f"C{j}",
                                ms=3, lw=1, label=f"{integ_i}, {m.dt_label(div)}")
                    drawn += 1
        if not drawn:
            plt.close(fig)
            raise Missing(f"no return series for {fine}")
        integ0 = m.integrators[0]
        div0 = m.dt_divisors[-2] if len(m.dt_divisors) > 1 else m.dt_divisors[-1]
        k = 0
        for f in m.families:
            for v in sorted((v for v in m.h if m.family[v] == f), key=lambda v: -m.h[v]):
                p = self.series_path(case, v, integ0, div0)
                if p.exists():
                    s = series(p)
                    a2.semilogy(s["cycle"], np.maximum(s["return_Linf"], 1e-16), "o-" if f == fam else "s--",
                                color=f"C{k % 10}", ms=3, lw=1, label=v)
                    k += 1
        label = "paper: < 2.5e-5 after 15 cycles" + (" (2D)" if three_d else "")
        for ax in (a1, a2):
            ax.axhline(bound, color="k", ls="--", lw=1.2, label=label)
            ax.set_xlabel("number of cycles n (t = nT, T = 0.25 s) [-]")
            ax.set_ylabel("L-inf distance of the tracers from their start [m]")
            ax.grid(True, which="major", alpha=0.3)
            ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        a1.set_title(f"{fine}: every integrator and step", fontsize=9)
        a2.set_title(f"every grid, {integ0} at {m.dt_label(div0)}: the grid does not matter", fontsize=9)
        self.figure(fig, f"{case}_fig13",
                    f"{'Fig 13 analogue (3D)' if three_d else 'Fig 13'}: L-inf return error against the number of "
                    f"cycles (exact answer 0), with the paper's bound 2.5e-5; left: {fine} for each integrator and dt; "
                    f"right: all grids at one step, the same curve, because the sampled field returns exactly "
                    f"and what is left is time-integration error.")

    def tg_streamlines(self, ax, U, k, xlim, ylim, scale=1e3):
        """Taylor-Green streamlines psi = (U/k) cos(kx) cos(ky), and the dividing streamlines (cell edges)."""
        gx, gy = np.meshgrid(np.linspace(*xlim, 300), np.linspace(*ylim, 300))
        psi = (U / k) * np.cos(k * gx) * np.cos(k * gy)
        ax.contour(gx * scale, gy * scale, psi, levels=np.linspace(-U / k, U / k, 13)[1:-1], colors="0.72",
                   linewidths=0.6, linestyles="solid")
        n0, n1 = math.floor(k * xlim[0] / math.pi - 0.5), math.ceil(k * xlim[1] / math.pi - 0.5)
        for n in range(n0, n1 + 1):
            x = (math.pi / 2 + n * math.pi) / k
            if xlim[0] <= x <= xlim[1]:
                ax.axvline(x * scale, color="0.45", lw=0.6, ls="--")
        n0, n1 = math.floor(k * ylim[0] / math.pi - 0.5), math.ceil(k * ylim[1] / math.pi - 0.5)
        for n in range(n0, n1 + 1):
            y = (math.pi / 2 + n * math.pi) / k
            if ylim[0] <= y <= ylim[1]:
                ax.axhline(y * scale, color="0.45", lw=0.6, ls="--")

    def fig_taylor_green(self, case):
        """Fig 14 as trajectories: the followed particles against the exact-field oracle, one panel per St."""
        m = self.meta
        integ = "exponential_midpoint" if "exponential_midpoint" in m.integrators else m.integrators[-1]
        div = m.dt_divisors[-1]
        picks = []
        for fam in m.families:
            grids = sorted((v for v in m.h if m.family[v] == fam), key=lambda v: -m.h[v])
            v = next((g for g in grids if g.endswith("grid32")), grids[len(grids) // 2] if grids else None)
            if v and self.series_path(case, v, integ, div).exists():
                picks.append(v)
        if not picks:
            raise Missing(f"no {integ} {m.dt_label(div)} trajectory series")
        cols = 2 if len(picks) > 1 else 1
        rows_n = math.ceil(len(picks) / cols)
        fig, axes = plt.subplots(rows_n, cols, figsize=(5.6 * cols, 5.2 * rows_n), squeeze=False)
        for ax, v in zip(axes.flat, picks):
            s = series(self.series_path(case, v, integ, div))
            o = m.oracle[v]
            U, k, L = o.get("U", 0.05), o.get("k", 200 * math.pi), o.get("L", 0.01)
            xs = np.concatenate([s["x"], s["x_oracle"]])
            ys = np.concatenate([s["y"], s["y_oracle"]])
            xlim = (min(0.0, xs.min()) - 0.05 * L, max(L, xs.max()) + 0.05 * L)
            ylim = (min(0.0, ys.min()) - 0.05 * L, max(L, ys.max()) + 0.05 * L)
            self.tg_streamlines(ax, U, k, xlim, ylim)
            ax.add_patch(plt.Rectangle((0, 0), L * 1e3, L * 1e3, fill=False, ec="k", lw=1))
            ids = np.unique(s["id"])
            worst = 0.0
            for j, i in enumerate(ids):
                sel = s["id"] == i
                ax.plot(s["x_oracle"][sel] * 1e3, s["y_oracle"][sel] * 1e3, "k-", lw=1.6, alpha=0.5,
                        label="oracle (exact field, CVODE)" if j == 0 else None)
                ax.plot(s["x"][sel] * 1e3, s["y"][sel] * 1e3, "-", color=f"C{j % 10}", lw=0.9,
                        label="cdm" if j == 0 else None)
                ax.plot(s["x"][sel][0] * 1e3, s["y"][sel][0] * 1e3, "o", color=f"C{j % 10}", ms=3)
                worst = max(worst, np.max(np.abs(s["x"][sel] - s["x_oracle"][sel])),
                            np.max(np.abs(s["y"][sel] - s["y_oracle"][sel])))
            T_p = o.get("rho_p", 1800) * o.get("d", 1e-4) ** 2 / (18 * o.get("mu_g", 1))
            ax.set_xlim(xlim[0] * 1e3, xlim[1] * 1e3)
            ax.set_ylim(ylim[0] * 1e3, ylim[1] * 1e3)
            ax.set_aspect("equal")
            ax.set_xlabel("x [mm] (unwrapped)")
            ax.set_ylabel("y [mm] (unwrapped)")
            ax.set_title(f"St = T_p/T_g = {T_p / o.get('T_g', 0.2):.3g} ({v}): "
                         f"largest deviation {100 * worst / L:.2g} % of L", fontsize=9)
            ax.legend(fontsize=6, loc="upper right")
        for ax in list(axes.flat)[len(picks):]:
            ax.set_visible(False)
        self.figure(fig, f"{case}_fig14_trajectories",
                    f"Fig 14 as trajectories: the followed particles over 5 T_g from rest (dots), cdm ({integ}, "
                    f"{m.dt_label(div)}, the grid named) against the exact-field oracle, on the streamlines "
                    f"psi = (U/k) cos(kx) cos(ky) (grey; dashed: the cell edges); square: the periodic box.")

    def clustering_variants(self):
        """Garg's family (St = T_p/T_g) and Maxey's (St = tau U k) with both Stokes numbers per variant."""
        m = self.meta
        out = []
        for v in m.variants:
            o = m.oracle[v["name"]]
            try:
                T_p = o["rho_p"] * o["d"] ** 2 / (18 * o["mu_g"])
                st_g = T_p / o["T_g"]
                # tau = m/K at zero slip; Wen-Yu at the mean gas fraction (the case README).
                st_m = T_p * o["eps_g"] ** 2.65 * o["U"] * o["k"]
            except (KeyError, ZeroDivisionError):
                continue
            fam = "maxey" if v["name"].startswith("StMaxey") else "garg"
            out.append((v["name"], fam, st_g, st_m))
        return out

    def fig_clustering(self, case, rows):
        m = self.meta
        integ = m.integrators[0] if m.integrators else "exponential_midpoint"
        div = m.dt_divisors[-1]
        cv = self.clustering_variants()
        garg = sorted((c for c in cv if c[1] == "garg"), key=lambda c: c[2])
        if not garg:
            raise Missing("case.toml has no Stokes-number variants")
        # Snapshots (Fig 14).
        present = [c for c in garg if self.series_path(case, c[0], integ, div, "_final").exists()]
        if not present:
            raise Missing(f"no {integ} {m.dt_label(div)} _final series")
        if len(present) < len(garg):
            self.note(f"{case}: Fig 14: no {integ} {m.dt_label(div)} _final series for "
                      + ", ".join(c[0] for c in garg if c not in present) + ": those snapshots left out.")
        cols = 2 if len(present) > 1 else 1
        nrow = math.ceil(len(present) / cols)
        fig, axes = plt.subplots(nrow, cols, figsize=(5.2 * cols, 5.0 * nrow), squeeze=False)
        for ax, (v, _, st_g, st_m) in zip(axes.flat, present):
            o = m.oracle[v]
            U, k, L = o["U"], o["k"], o["L"]
            f = series(self.series_path(case, v, integ, div, "_final"))
            self.tg_streamlines(ax, U, k, (0, L), (0, L))
            crossed = f["crossed"] > 0.5
            ax.plot(f["x"][~crossed] * 1e3, f["y"][~crossed] * 1e3, ".", color="C1", ms=2.5,
                    label=f"stayed in its cell ({(~crossed).sum()})")
            ax.plot(f["x"][crossed] * 1e3, f["y"][crossed] * 1e3, ".", color="C0", ms=2.5,
                    label=f"crossed a cell edge ({crossed.sum()})")
            d_end = series(self.series_path(case, v, integ, div))["D"][-1]
            ax.set_xlim(0, L * 1e3)
            ax.set_ylim(0, L * 1e3)
            ax.set_aspect("equal")
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("y [mm]")
            ax.set_title(f"St = {st_g:g} (Maxey's tau U k = {st_m:.2g}): D = {d_end:.2f}", fontsize=9)
            ax.legend(fontsize=6, loc="upper right", framealpha=0.9)
        for ax in list(axes.flat)[len(present):]:
            ax.set_visible(False)
        n = len(f["x"])
        self.figure(fig, f"{case}_fig14",
                    f"Fig 14: the {n} particles after 10 T_g = 2 s from rest at uniformly random positions, for Garg's "
                    f"Stokes numbers, on the Taylor-Green streamlines psi = (U/k) cos(kx) cos(ky) (grey; dashed: "
                    f"the cell edges kx, ky = pi/2 + n pi); {integ}, {m.dt_label(div)}, 32^2 grid. D: box-counting "
                    f"clustering index (0 for random points).")
        # D against St, with the random-points band, and D over time.
        final = {(r["variant"], num(r["dt_divisor[-]"])): num(r["error"]) for r in rows
                 if r["quantity"] == "clustering_final" and r["norm"] == "index_D"}
        crossed = {(r["variant"], num(r["dt_divisor[-]"])): num(r["error"]) for r in rows
                   if r["quantity"] == "crossed_cells" and r["norm"] == "fraction_pct"}
        base = series(self.series_path(case, present[0][0], integ, div))
        mean, sd = float(base["D_random_mean"][0]), float(base["D_random_sd"][0])
        factor = present[0][3] / present[0][2]
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(13, 4.8))
        for fam, marker, label in (("garg", "o", "Garg's St family (Fig 14)"), ("maxey", "^", "Maxey's St family")):
            pts = sorted((c for c in cv if c[1] == fam), key=lambda c: c[2])
            for j, d in enumerate(m.dt_divisors):
                xs = [c[2] for c in pts if (c[0], d) in final]
                ys = [final[(c[0], d)] for c in pts if (c[0], d) in final]
                if xs:
                    a1.plot(xs, ys, marker + ("-" if fam == "garg" and d == div else ""), ms=6 if d == div else 9,
                            mfc=None if d == div else "none", color="C0" if fam == "garg" else "C2", lw=1,
                            label=f"{label}, {m.dt_label(d)}")
        a1.axhspan(mean - 2 * sd, mean + 2 * sd, color="0.8", label=f"random points: mean +- 2 sd ({mean:.3f} +- {2 * sd:.3f})")
        a1.axhline(mean, color="0.5", lw=0.8)
        a1.set_xscale("log")
        symlog_index_axis(a1, mean - 3 * sd)
        a1.set_xlabel("Garg's Stokes number St = T_p/T_g [-]")
        a1.set_ylabel("clustering index D = s^2/mean - 1 after 10 T_g [-]")
        sec = a1.secondary_xaxis("top", functions=(lambda x: x * factor, lambda x: x / factor))
        sec.set_xlabel("Maxey's St = tau U k [-]", fontsize=8)
        a1.set_title("clustering against St: strongest at St = O(1)", fontsize=9)
        a1.grid(True, which="major", alpha=0.3)
        a1.legend(fontsize=6, loc="center right")
        for j, (v, _, st_g, _) in enumerate(garg):
            p = self.series_path(case, v, integ, div)
            if p.exists():
                s = series(p)
                a2.plot(s["t"] / m.oracle[v]["T_g"], s["D"], "-", color=f"C{j}", lw=1.2, label=f"St = {st_g:g}")
        a2.axhspan(mean - 2 * sd, mean + 2 * sd, color="0.8", label="random points: mean +- 2 sd")
        symlog_index_axis(a2, mean - 3 * sd)
        a2.set_xlabel("t / T_g [-]")
        a2.set_ylabel("clustering index D [-]")
        a2.set_title(f"D over time, Garg's St family ({integ}, {m.dt_label(div)})", fontsize=9)
        a2.grid(True, which="major", alpha=0.3)
        a2.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        self.figure(fig, f"{case}_clustering_vs_st",
                    "Fig 14 quantified: the clustering index D over 16 x 16 boxes after 10 T_g against Garg's Stokes "
                    "number (Maxey's on the top axis), both families and both steps (open: the coarser step), with "
                    "the band D of uniformly random points falls in (the Monte Carlo oracle, mean +- 2 sd); right: D "
                    "over time. y axis linear within +-0.5, logarithmic beyond.")
        fig, ax = plt.subplots(figsize=(7.5, 4.5))
        for fam, marker, color, label in (("garg", "o", "C0", "Garg's St family"), ("maxey", "^", "C2", "Maxey's St family")):
            pts = sorted((c for c in cv if c[1] == fam), key=lambda c: c[3])
            for d in m.dt_divisors:
                xs = [c[3] for c in pts if (c[0], d) in crossed]
                ys = [crossed[(c[0], d)] for c in pts if (c[0], d) in crossed]
                if xs:
                    ax.plot(xs, ys, marker, color=color, ms=6 if d == div else 10, mfc=None if d == div else "none",
                            label=f"{label}, {m.dt_label(d)}")
        ax.axvline(0.25, color="k", ls="--", lw=1.2, label="St_c = 1/4 (Maxey 1987)")
        ax.axvspan(1e-3, 0.25, color="C1", alpha=0.08, label="overdamped at the cell corners: no crossing")
        ax.set_xscale("log")
        ax.set_xlim(min(c[3] for c in cv) / 2, max(c[3] for c in cv) * 2)
        ax.set_ylim(-5, 105)
        ax.set_xlabel("Maxey's Stokes number St = tau U k [-]")
        ax.set_ylabel("particles that left their starting vortex cell [%]")
        ax.set_title("cell crossing against St: the threshold St_c = 1/4", fontsize=10)
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7, loc="center right")
        self.figure(fig, f"{case}_crossing",
                    "The fraction of the particles that ever left the vortex cell they started in, after 10 T_g, against "
                    "Maxey's Stokes number tau U k (Garg's St converted), both steps (open: the coarser); linearised at "
                    "a hyperbolic point St lambda^2 + lambda + 1 = 0 is overdamped below St_c = 1/4.")

    def fig_terminal(self, case):
        """Fig 15: the particle velocity against CVODE on eq 48, and the error over time."""
        m = self.meta
        div = m.dt_divisors[0] if m.dt_divisors else 10
        runs = [(v["name"], i) for v in m.variants for i in m.integrators
                if self.series_path(case, v["name"], i, div).exists()]
        if not runs:
            raise Missing(f"no series at {m.dt_label(div)}")
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.6))
        first = series(self.series_path(case, *runs[0], div))
        a1.plot(first["t"], first["vy_oracle"], "k-", lw=1.5, label="oracle: CVODE on eq 48")
        vt = float(first["v_terminal"][0])
        a1.axhline(vt, color="k", ls="--", lw=1, label=f"terminal velocity (force balance) {vt:.5f} m/s")
        for j, (v, i) in enumerate(runs):
            s = series(self.series_path(case, v, i, div))
            if i == "paper_euler" or (v == "exponential" and i == "velocity_verlet"):
                a1.plot(s["t"], s["vy"], INTEG_STYLES[m.integrator_index(i) % 6][0], color=f"C{j}", ms=3,
                        markevery=max(1, len(s["t"]) // 40), label=f"cdm {v} drag, {i}")
            err = 100 * np.abs(s["vy"] - s["vy_oracle"]) / abs(vt)
            a2.semilogy(s["t"][1:], np.maximum(err[1:], 1e-12), INTEG_STYLES[m.integrator_index(i) % 6][1:],
                        color=f"C{j}", lw=1, label=f"{v} drag, {i}")
        a1.set_xlabel("t [s]")
        a1.set_ylabel("particle velocity v_y [m/s] (up > 0)")
        a1.set_title(f"Fig 15 (decoupled): falling through a 0.4 m/s upward stream, dt = {m.dt_label(div)} "
                     f"= {1e3 * (first['t'][1] - first['t'][0]):.3g} ms", fontsize=9)
        a1.grid(True, alpha=0.3)
        a1.legend(fontsize=7)
        a2.set_xlabel("t [s]")
        a2.set_ylabel("|v - v_ODE| [% of |v_t|]")
        a2.set_title(f"error over time, every drag update and integrator, {m.dt_label(div)}", fontsize=9)
        a2.grid(True, which="major", alpha=0.3)
        a2.legend(fontsize=6)
        self.figure(fig, f"{case}_fig15",
                    f"Fig 15 (decoupled): particle velocity from rest to the terminal velocity, cdm at the coarsest step "
                    f"({m.divisor}, N = {fmt_div(div)}) against the CVODE solution of eq 48 and the force-balance "
                    f"terminal velocity; right: the error over time for each drag update and integrator.")

    # ---------------------------------------------------------------- fluidisation (issue 4)
    def fig_fluidization(self, case):
        """Pressure drop against inflow (packed branch, Ergun, plateau) and its history."""
        m = self.meta
        div = m.dt_divisors[0] if m.dt_divisors else 20
        v = m.variants[0]["name"]
        i = m.integrators[0]
        s = series(self.series_path(case, v, i, div))
        h = series(self.series_path(case, v, i, div, "_history"))
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.6))
        w = float(s["buoyant_weight_per_area"][0])
        umf = float(s["U_mf_oracle"][0])
        uu = np.linspace(0, float(s["U"].max()), 200)
        a1.axhline(w, color="k", ls="--", lw=1, label=f"buoyant weight / area {w:.1f} Pa")
        a1.axvline(umf, color="k", ls=":", lw=1, label=f"U_mf from Gidaspow-Ergun at the bed's eps: {umf:.3f} m/s")
        packed = s["U"] < umf
        for col, lab, st in (("dP_ergun_at_eps_bed", "Ergun at the bed's mean eps", "C1-"),
                             ("dP_ergun_at_eps_bulk", "Ergun at the bed's bulk eps", "C2-")):
            if col in s:
                c = np.polyfit(np.r_[0.0, s["U"]], np.r_[0.0, s[col]], 2)
                a1.plot(uu[uu < umf * 1.1], np.polyval(c, uu[uu < umf * 1.1]), st, lw=1, label=lab)
        a1.errorbar(s["U"], s["dP_frictional"], yerr=s["dP_std_dev"], fmt="bo", ms=5, capsize=3,
                    label="cdm: mean over each inflow (bar: fluctuation)")
        if "dP_momentum_corrected" in s:
            a1.plot(s["U"][~packed], s["dP_momentum_corrected"][~packed], "rx", ms=8,
                    label="cdm: less the bed's momentum gain")
        a1.set_xlabel("superficial velocity U [m/s]")
        a1.set_ylabel("frictional pressure drop [Pa]")
        a1.set_title("fluidisation: packed branch and plateau", fontsize=9)
        a1.grid(True, alpha=0.3)
        a1.legend(fontsize=7)
        a2.plot(h["t"], h["dP_frictional"], "b-", lw=0.6, label="cdm")
        a2.axhline(w, color="k", ls="--", lw=1, label="buoyant weight / area")
        a2.set_xlabel("t [s]")
        a2.set_ylabel("frictional pressure drop [Pa]")
        a2.set_title("the whole run: the inflow raised in steps after settling", fontsize=9)
        a2.grid(True, alpha=0.3)
        a2.legend(fontsize=7)
        self.figure(fig, f"{case}_dp",
                    "Fluidisation: the frictional pressure drop against the superficial velocity (left), with Ergun's "
                    "packed-bed line at the settled bed's mean and bulk gas fraction, the buoyant weight per area and "
                    "the drag law's U_mf; right: the pressure drop over the whole run.")

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

    # ------------------------------------------------------------------ configuration
    # Main quantity per case for the dt-convergence and work-precision plots (a case not
    # listed uses its first quantity held to a tolerance), the grid-convergence quantity,
    # and the paper figures.
    CONV = {
        "free_fall": dict(quantity="y", norm="max_rel_pct", ylabel="error in y [%]"),
        "free_fall_bounces": dict(quantity="apex_soft", norm="max_rel_pct", ylabel="error in apex height [%]"),
        "stacked": dict(quantity="y1", norm="max_rel_pct", ylabel="error in y1 [%]"),
        "slipping_ball": dict(quantity="v", norm="max_rel_pct", ylabel="error in v [%]"),
        "circle_advection": dict(quantity="return", norm="max_abs_over_cycles", slopes=(2, 3, 4),
                                 ylabel="return distance, max over 16 cycles [m]",
                                 hlines=[(2.5e-5, "paper: < 2.5e-5", "k")]),
        "sphere_advection": dict(quantity="return", norm="max_abs_over_cycles", slopes=(2, 3, 4),
                                 ylabel="return distance, max over 16 cycles [m]",
                                 hlines=[(2.5e-5, "paper (2D): < 2.5e-5", "k")]),
        "taylor_green": dict(quantity="position", norm="max_abs_pct_of_L",
                             ylabel="position error, max over particles and 5 T_g [% of L]"),
        "taylor_green_clustering": None,
        "terminal_velocity": dict(quantity="v", norm="max_abs_pct_of_terminal",
                                  ylabel="max |v - v_ODE| over 0.5 s [% of |v_t|]"),
        "hertz_impact_wall": dict(quantity="force", norm="max_abs_pct_of_peak", ylabel="force error [% of F_max]"),
        "hertz_impact_pair": dict(quantity="force", norm="max_abs_pct_of_peak", ylabel="force error [% of F_max]"),
        "hertz_restitution": dict(quantity="e_vs_ode", norm="max_rel_pct", ylabel="restitution error vs CVODE [%]"),
        "oblique_impact": dict(quantity="omega", norm="max_abs_pct_of_peak", ylabel="rebound spin error [% of max]"),
        "rolling_resistance_spin": dict(quantity="omega", norm="max_abs_pct_of_initial",
                                        ylabel="spin error [% of initial]"),
    }
    GRID = {
        "circle_advection": dict(quantity="path", norm="max_abs_first_period",
                                 ylabel="distance from the exact path, first period [m]"),
        "sphere_advection": dict(quantity="path", norm="max_abs_first_period",
                                 ylabel="distance from the exact path, first period [m]"),
        "taylor_green": dict(quantity="position", norm="max_abs_pct_of_L",
                             ylabel="position error, max over particles and 5 T_g [% of L]"),
    }
    CONV_NOTE = {
        "taylor_green_clustering": "The clustering index and the crossing fraction are measures of the physics "
                                   "held to physical bounds, not errors against an exact solution, so there is no "
                                   "convergence or work-precision plot; their change with dt is in the error table.",
    }

    def paper_figures(self, case, rows):
        figs = {
            "free_fall": [("Fig 4", self.fig_free_fall, case)],
            "free_fall_bounces": [("Fig 5", self.fig_bounces, case)],
            "stacked": [("Figs 7-8", self.fig_stacked, case)],
            "slipping_ball": [("Fig 10", self.fig_slipping, case)],
            "circle_advection": [("Fig 12", self.fig_vortex_positions, case, False),
                                 ("Fig 13", self.fig_vortex_return, case, False)],
            "sphere_advection": [("Fig 12 analogue", self.fig_vortex_positions, case, True),
                                 ("Fig 13 analogue", self.fig_vortex_return, case, True)],
            "taylor_green": [("Fig 14 trajectories", self.fig_taylor_green, case)],
            "taylor_green_clustering": [("Fig 14", self.fig_clustering, case, rows)],
            "terminal_velocity": [("Fig 15", self.fig_terminal, case)],
            "hertz_impact_wall": [("force-time", self.fig_hertz_impact, case)],
            "hertz_impact_pair": [("force-time", self.fig_hertz_impact, case)],
            "hertz_restitution": [("restitution", self.fig_restitution, case)],
            "oblique_impact": [("oblique impact", self.fig_oblique, case)],
            "rolling_resistance": [("rolling", self.fig_rolling, case)],
            "rolling_resistance_spin": [("spinning", self.fig_rolling, case)],
            "fluidization": [("pressure drop", self.fig_fluidization, case)],
        }
        for what, fn, *args in figs.get(case, []):
            self.guarded(f"{case}: {what}", fn, *args)

    @staticmethod
    def generic_conv(rows):
        """The first quantity held to a tolerance over the dt sweep (for a case without its own settings)."""
        for r in rows:
            if r["pass"] in ("yes", "no") and r["dt_divisor[-]"] != "all" and not r["norm"].endswith("_order"):
                unit = "[%]" if "pct" in r["norm"] else ""
                return dict(quantity=r["quantity"], norm=r["norm"], ylabel=f"{r['quantity']} ({r['norm']}) {unit}")
        for r in rows:
            if r["dt_divisor[-]"] != "all" and not r["norm"].endswith("_order"):
                return dict(quantity=r["quantity"], norm=r["norm"], ylabel=f"{r['quantity']} ({r['norm']})")
        return None

    @staticmethod
    def generic_grid(rows):
        """The quantity of the first grid order held to a tolerance, else of the first grid order."""
        cands = [r for r in rows if r["norm"].endswith("_grid_order")]
        cands.sort(key=lambda r: r["pass"] not in ("yes", "no"))
        if not cands:
            return None
        r = cands[0]
        norm = r["norm"][:-len("_grid_order")]
        return dict(quantity=r["quantity"], norm=norm, ylabel=f"{r['quantity']} ({norm})")

    # ------------------------------------------------------------------ assemble
    def case_section(self, c, passed, failed):
        case_dir = self.cases_dir / c
        errors = self.src / c / "errors.dat"
        self.meta = CaseMeta(case_dir, errors)
        m = self.meta
        self.h(2, f"{m.title or c} [{'PASS' if failed == 0 else 'FAIL'}]", c)
        if m.physics:
            self.p(m.physics)
        elif not case_dir.exists():
            self.note(f"{c}: no case folder {case_dir}: physics text and parameters not shown.")
        self.parameters(c)
        if not errors.exists():
            self.note(f"{c}: {errors} not found: tables missing, case skipped.")
            return
        rows = read_table(errors)
        oracles = sorted({r["oracle"] for r in rows if r.get("oracle", "-") != "-"})
        self.p("Oracle and the accuracy it was computed to: " + ("; ".join(oracles) if oracles else "-") + ".")
        self.tolerance_table()
        self.paper_figures(c, rows)
        conv = self.CONV[c] if c in self.CONV else self.generic_conv(rows)
        if conv:
            self.h(3, "Convergence and cost")
            self.guarded(f"{c}: convergence in dt", self.convergence_plot, c, rows, conv)
            grid = self.GRID[c] if c in self.GRID else self.generic_grid(rows)
            if grid:
                self.guarded(f"{c}: convergence in h", self.grid_plot, c, rows, grid)
            self.guarded(f"{c}: work-precision", self.work_precision_plot, c, conv)
        elif c in self.CONV_NOTE:
            self.p(self.CONV_NOTE[c])
        self.guarded(f"{c}: coupling per gas step", self.evaluation_table, c, rows, conv)
        self.error_table(c, rows)

    GAS_STEP = "_gas_step"

    def evaluation_table(self, case, rows, conv):
        """Each variant run with coupling.drag_evaluation = "gas_step" (named VARIANT_gas_step)
        beside VARIANT: the main error and the solver wall time at every dt, both modes."""
        lagged = {r["variant"] for r in rows if r["variant"].endswith(self.GAS_STEP)}
        if not lagged:
            return
        quantity = conv["quantity"] if conv else None
        m = self.meta
        key = lambda r: (r["variant"], r["integrator"], r["dt_divisor[-]"], r["quantity"], r["norm"])
        by = {key(r): r for r in rows}
        out = []
        for r in rows:
            if r["variant"] not in lagged or r["dt_divisor[-]"] == "all":
                continue
            if quantity and r["quantity"] != quantity:
                continue
            base = by.get((r["variant"][:-len(self.GAS_STEP)],) + key(r)[1:])
            if not base:
                continue
            out.append([base["variant"], m.dt_label(r["dt_divisor[-]"]), r["quantity"], r["norm"],
                        f'{num(base["error"]):.4g}', base["wall[s]"], f'{num(r["error"]):.4g}', r["wall[s]"],
                        r["tolerance"], r["pass"]])
        if out:
            self.h(3, "Coupling evaluated once per gas step: accuracy against cost")
            self.p("coupling.drag_evaluation = \"every_step\" (the default) against \"gas_step\" (gas velocity, "
                   "ε_g, ∇P and the drag coefficient evaluated at the first particle step of each gas step, the "
                   "reaction deposited once per gas step): the error and the solver wall time of each run.")
            self.table(["variant", "dt", "quantity", "norm", "error, every step", "wall [s]", "error, per gas step",
                        "wall [s]", "tolerance (gas step)", "pass"], out)

    @staticmethod
    def read_summary(path):
        summ = []
        for line in path.read_text().splitlines():
            if line.startswith("#") or not line.strip():
                continue
            c, passed, failed, worst, wall = line.split()
            summ.append((c, int(passed), int(failed), float(worst), float(wall)))
        return summ

    def build(self):
        summary = self.src / "summary.dat"
        if not summary.exists():
            sys.exit(f"make_report: {summary} not found: run `cdm verify --out {self.src}` first")
        summ = self.read_summary(summary)
        sweep_path = self.src / "summary_sweep.dat"
        sweep_summ = {c: (p, f) for c, p, f, *_ in self.read_summary(sweep_path)} if sweep_path.exists() else {}
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
        sweep = [c for c, *_ in summ if (self.src / c / "errors_sweep.dat").exists()]
        self.p(f"{len(summ)} cases, {sum(s[1] for s in summ)} checks passed, {sum(s[2] for s in summ)} failed "
               f"(`cdm verify`). Worst error / tolerance: the check closest to (or past) its bound, > 1 fails; for "
               f"a lower bound it is bound / value. The dense dt sweep (`cdm verify --sweep`, for the "
               f"work-precision plots; runs coarser than the verified range are not held to the tolerances) is "
               f"present for {len(sweep)} of {len(summ)} cases"
               + (f": {sum(p for p, _ in sweep_summ.values())} checks passed, "
                  f"{sum(f for _, f in sweep_summ.values())} failed." if sweep_summ else "."))
        at_once = prov.get("cases_at_once", "1")
        if at_once != "1":
            self.p(f"The cases ran {at_once} at once (`cdm verify -j`), each in a process of its own: every wall "
                   f"time here was measured with the machine's other cores busy. `cdm verify -j 1` runs them one "
                   f"after the other.")
        header = ["case", "result", "checks passed", "failed", "worst error / tolerance", "solver wall [s]"]
        if sweep_summ:
            header.append("dense sweep: passed / failed")
        self.table(header,
                   [[("raw", f'<a href="#{html.escape(c)}">{html.escape(c)}</a>'),
                     ("PASS" if f == 0 else "FAIL") + ("; sweep FAIL" if sweep_summ.get(c, (0, 0))[1] else ""), p, f,
                     f"{w:.3g}", f"{wall:.3g}"]
                    + ([("{} / {}".format(*sweep_summ[c]) if c in sweep_summ else "not run")] if sweep_summ else [])
                    for c, p, f, w, wall in summ],
                   ["pass" if f == 0 and sweep_summ.get(c, (0, 0))[1] == 0 else "fail" for c, _, f, _, _ in summ])
        for c, passed, failed, *_ in summ:
            self.case_section(c, passed, failed)
        css = """body{font-family:sans-serif;max-width:1200px;margin:auto;padding:1em}
table{border-collapse:collapse;margin:0.5em 0;font-size:0.8em}td,th{border:1px solid #ccc;padding:2px 6px}
tr.pass td{background:#e6f5e6}tr.fail td{background:#f8d7d7}figure{margin:1em 0}img{max-width:100%}
figcaption{font-size:0.85em;color:#444}.note{color:#855}details{margin:0.5em 0}summary{cursor:pointer;color:#235}"""
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
    rep = Report(Path(a.src), Path(a.out), Path(a.cases))
    path = rep.build()
    print(path)
    if rep.failures:
        print(f"make_report: {rep.failures} figure(s) could not be drawn (see the notes in the report)", file=sys.stderr)
        sys.exit(3)


if __name__ == "__main__":
    main()
