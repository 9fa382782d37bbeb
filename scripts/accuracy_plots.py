#!/usr/bin/python3
"""Draws docs/accuracy/*.png from the JSON that bench_accuracy wrote and writes docs/accuracy.md.

Run by scripts/accuracy.sh with Debian's python3 and python3-matplotlib (/usr/bin/python3: a
python3 earlier on PATH may lack matplotlib). Every number on the page comes from the JSON:
tables, fitted convergence orders (least-squares slope of log10 error against log10 step) and
the Pareto verdicts (which method gives the fastest run for each accuracy).

usage: accuracy_plots.py DOCS_DIR [--timing TEXT]
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter  # noqa: E402

FLOOR = 1e-17  # an exact zero error is drawn here on the log axis


def load(path):
    with open(path) as f:
        return json.load(f)


def fmt(x, unit=""):
    if x == 0:
        return "0" + (" " + unit if unit else "")
    return f"{x:.3g}" + (" " + unit if unit else "")


def fit_order(hs, errs):
    """Least-squares slope of log10(err) against log10(h) over the points with err > 0."""
    pts = [(math.log10(h), math.log10(e)) for h, e in zip(hs, errs) if h > 0 and e > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    sxy = sum((p[0] - mx) * (p[1] - my) for p in pts)
    return sxy / sxx


# ----------------------------------------------------------------------------------- Pareto

def pareto_front(points):
    """points: dicts with err, time. Returns the non-dominated ones, by increasing error."""
    front, best = [], math.inf
    for p in sorted(points, key=lambda p: (p["err"], p["time"])):
        if p["time"] < best:
            front.append(p)
            best = p["time"]
    return front


def verdict(points, err_unit, time_unit="us"):
    """Pareto verdict in words: each method on the front (the fastest run for each accuracy) with
    the errors and times of its front points, cheapest first, and the methods never on it."""
    front = pareto_front(points)
    order, seen = [], {}
    for p in reversed(front):  # largest error (cheapest) first
        if p["method"] not in seen:
            seen[p["method"]] = []
            order.append(p["method"])
        seen[p["method"]].append(p)
    parts = []
    for m in order:
        pts = seen[m]
        e_hi, e_lo = max(p["err"] for p in pts), min(p["err"] for p in pts)
        t_lo, t_hi = min(p["time"] for p in pts), max(p["time"] for p in pts)
        errs = fmt(e_hi, err_unit) if e_hi == e_lo else f"{fmt(e_hi)} to {fmt(e_lo, err_unit)}"
        times = fmt(t_lo, time_unit) if t_lo == t_hi else f"{fmt(t_lo)}-{fmt(t_hi, time_unit)}"
        parts.append(f"**{m}** ({errs}, {times})")
    text = "Fastest run for each accuracy (Pareto front), cheapest first: " + "; ".join(parts) + "."
    off = [m for m in dict.fromkeys(p["method"] for p in points) if m not in seen]
    if off:
        text += " Never on the front: " + ", ".join(off) + "."
    return text


def gap_against_fixed(rs):
    """Gap against fixed stepping at equal settings (kind, step_mm, tolerance): run-time ratios
    and how often the contact instant is the same."""
    key = lambda r: (r["kind"], r["step_mm"], r["toc_tolerance_s"])
    fixed = {key(r): r for r in rs if r.get("stepping") == "fixed"}
    pairs = [(r, fixed[key(r)]) for r in rs if r.get("stepping") == "gap" and key(r) in fixed]
    if not pairs:
        return ""
    ratios = sorted(g["wall_us_median"] / f["wall_us_median"] for g, f in pairs)
    same = sum(1 for g, f in pairs if abs(g["time_s"] - f["time_s"]) <= 1e-12)
    within = sum(1 for g, f in pairs if abs(g["time_s"] - f["time_s"]) <= max(g["toc_tolerance_s"], 1e-12)
                 and g["kind"] != "plain")
    bis = sum(1 for g, f in pairs if g["kind"] != "plain")
    mid = ratios[len(ratios) // 2]
    return (f"*Gap against fixed stepping* at equal settings ({len(pairs)} pairs): run time x{ratios[0]:.2f} to "
            f"x{ratios[-1]:.2f} (median x{mid:.2f}); the same contact instant in {same} of {len(pairs)}, "
            f"and within toc_tolerance_s in {within} of the {bis} bisected pairs.")


# ----------------------------------------------------------------------------------- contact

METHOD_STYLE = {}


def style(method):
    if method not in METHOD_STYLE:
        markers = "osD^v<>"
        METHOD_STYLE[method] = {"marker": markers[len(METHOD_STYLE) % len(markers)],
                                "linestyle": "--" if method.startswith("gap") else "-"}
    return METHOD_STYLE[method]


def label_time_axis(ax):
    """Run times span less than two decades: label 1, 2, 5 x 10^k, in plain numbers."""
    ax.yaxis.set_major_locator(LogLocator(base=10, subs=(1, 2, 5)))
    ax.yaxis.set_major_formatter(ScalarFormatter())
    ax.yaxis.set_minor_formatter(NullFormatter())


def setting_label(r):
    if r["kind"] in ("plain", "bisection-step"):
        return f"step {r['step_mm']:g} mm"
    if r["kind"] == "bisection":
        return f"tol {r['toc_tolerance_s']:g} s"
    return f"step {r['step_mm']:g} mm, tol {r['toc_tolerance_s']:g} s"


def contact_section(docs, data):
    out = []
    runs = data["runs"]
    for scene in data["scenes"]:
        name = scene["name"]
        rs = [r for r in runs if r["scene"] == name]
        methods = list(dict.fromkeys(r["method"] for r in rs))
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
        for ax, key, xlabel in ((axes[0], "abs_time_error_s", "|contact instant error| [s]"),
                                (axes[1], "point_error_mm", "contact point error [mm]")):
            for m in methods:
                mr = [r for r in rs if r["method"] == m]
                xs = [max(r[key], FLOOR) for r in mr]
                ys = [r["wall_us_median"] for r in mr]
                ax.plot(xs, ys, label=m, **style(m))
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel(xlabel)
            ax.set_ylabel("median run time [us]")
            label_time_axis(ax)
            ax.grid(True, which="major", alpha=0.4)
            ax.grid(True, which="minor", alpha=0.1)
        axes[0].legend(fontsize=8)
        fig.suptitle(f"{name}: first contact of {scene['moving_body']} with {scene['static_body']} ({scene['motion']})")
        fig.tight_layout()
        png = f"contact_{name}.png"
        fig.savefig(os.path.join(docs, "accuracy", png), dpi=90)
        plt.close(fig)

        p = scene["point_star_mm"]
        out.append(f"### {name}\n")
        out.append(f"Analytic first contact: t* = {scene['t_star_s']:.9f} s, point ({p[0]:.4f}, {p[1]:.4f}, {p[2]:.4f}) mm, "
                   f"{scene['moving_body']} against {scene['static_body']}.\n")
        out.append(f"![{name}](accuracy/{png})\n")
        for key, unit, what in (("abs_time_error_s", "s", "Contact instant"), ("point_error_mm", "mm", "Contact point")):
            pts = [{"err": r[key], "time": r["wall_us_median"], "method": r["method"], "label": setting_label(r)} for r in rs]
            out.append(f"*{what}.* " + verdict(pts, unit) + "\n")
        g = gap_against_fixed(rs)
        if g:
            out.append(g + "\n")
        inside = sum(1 for r in rs if r["t_star_outside_bracket_s"] <= 1e-9)
        pair = sum(1 for r in rs if r["expected_pair"])
        out.append(f"t* lies inside the reported bracket [time_free_s, time_s] (to 1e-9 s) in {inside} of {len(rs)} runs; "
                   f"the expected pair is reported in {pair} of {len(rs)}.\n")
        out.append("<details><summary>Data</summary>\n")
        out.append("| method | step_mm | toc_tolerance_s | time error [s] | bracket [s] | point error [mm] | poses | bisection checks | median [us] |")
        out.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
        for r in rs:
            out.append(f"| {r['method']} | {r['step_mm']:g} | {r['toc_tolerance_s']:g} | {r['time_error_s']:.3e} | "
                       f"{r['bracket_s']:.3e} | {r['point_error_mm']:.3e} | {r['poses_checked']} | {r['bisection_checks']} | "
                       f"{r['wall_us_median']:.1f} |")
        out.append("\n</details>\n")
    return out


# -------------------------------------------------------------------------------------- path

def path_section(docs, data):
    out = []
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    orders = []
    for line in data["lines"]:
        for kind, ls in (("uniform", "-"), ("planned", "--")):
            pts = line[kind]
            hs = [p["h_mm"] for p in pts]
            for ax, key in ((axes[0], "position_mm"), (axes[1], "orientation_deg")):
                ys = [max(p[key], FLOOR) for p in pts]
                k = fit_order(hs, [p[key] for p in pts])
                label = f"{line['line']}, {'uniform h' if kind == 'uniform' else 'plan_line samples'} (order {k:.2f})"
                ax.plot(hs, ys, linestyle=ls, marker="o" if kind == "uniform" else "s", label=label)
                orders.append((line["line"], kind, key, k))
    for ax, ylabel in ((axes[0], "max position deviation [mm]"), (axes[1], "max orientation deviation [deg]")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("interpolation step h (tool travel between samples) [mm]")
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"Straight lines of the {data['robot']}: joint-interpolated path against the exact line")
    fig.tight_layout()
    fig.savefig(os.path.join(docs, "accuracy", "path_deviation.png"), dpi=90)
    plt.close(fig)
    out.append("![path deviation](accuracy/path_deviation.png)\n")
    out.append("Fitted convergence orders (least-squares slope of log10 deviation against log10 h):\n")
    out.append("| line | samples | position order | orientation order |")
    out.append("|---|---|---:|---:|")
    for line in data["lines"]:
        for kind in ("uniform", "planned"):
            po = next(o[3] for o in orders if o[0] == line["line"] and o[1] == kind and o[2] == "position_mm")
            oo = next(o[3] for o in orders if o[0] == line["line"] and o[1] == kind and o[2] == "orientation_deg")
            out.append(f"| {line['line']} | {'uniform h' if kind == 'uniform' else 'plan_line (step_mm swept)'} | {po:.2f} | {oo:.2f} |")
    out.append("")
    verdicts = []
    for line in data["lines"]:
        d = next((p for p in line["planned"] if p["step_mm"] == 1.0), None)
        if d:
            verdicts.append(f"{line['line']}: at the default step_mm 1 the simulator's samples are at most "
                            f"{d['h_mm']:.3g} mm apart and the joint-interpolated path leaves the line by at most "
                            f"{d['position_mm']:.2e} mm / {d['orientation_deg']:.2e} deg")
    all_orders = [o[3] for o in orders]
    mean_order = sum(all_orders) / len(all_orders)
    out.append(f"*Verdict.* Fitted orders {min(all_orders):.2f} to {max(all_orders):.2f}: the deviation shrinks as "
               f"h^{mean_order:.1f} (mean order). "
               + "; ".join(verdicts) + ".\n")
    out.append("<details><summary>Data</summary>\n")
    out.append("| line | samples | step_mm | h [mm] | samples | position [mm] | orientation [deg] |")
    out.append("|---|---|---:|---:|---:|---:|---:|")
    for line in data["lines"]:
        for kind in ("uniform", "planned"):
            for p in line[kind]:
                out.append(f"| {line['line']} | {kind} | {p.get('step_mm', '')} | {p['h_mm']:.4g} | {p['samples']} | "
                           f"{p['position_mm']:.3e} | {p['orientation_deg']:.3e} |")
    out.append("\n</details>\n")
    return out


# ---------------------------------------------------------------------------------------- IK

def ik_section(docs, data):
    out = []
    cf = data["puma_closed_form"]
    fig, ax = plt.subplots(figsize=(7, 3.8))
    for key, label in (("position_hist", "position [mm]"), ("rotation_hist", "rotation [rad]")):
        h = cf[key]
        edges = [h["log10_lo"] + i * h["width"] for i in range(len(h["counts"]) + 1)]
        centers = [(a + b) / 2 for a, b in zip(edges, edges[1:])]
        ax.step(centers, h["counts"], where="mid", label=f"{label}; exact 0: {h['exact_zero']}")
    used = [h["log10_lo"] + i * h["width"] for key in ("position_hist", "rotation_hist")
            for h in [cf[key]] for i, c in enumerate(h["counts"]) if c]
    ax.set_xlim(min(used) - 0.5, max(used) + 1)
    ax.set_xlabel("log10 residual")
    ax.set_ylabel("poses")
    ax.set_title(f"PUMA 560 closed-form IK: residual of {cf['poses']} random poses")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(docs, "accuracy", "ik_puma_residuals.png"), dpi=90)
    plt.close(fig)
    out.append("### Closed-form PUMA solver\n")
    out.append("![PUMA IK residuals](accuracy/ik_puma_residuals.png)\n")
    out.append("| residual | median | p90 | p99 | max |")
    out.append("|---|---:|---:|---:|---:|")
    for key, unit in (("position_mm", "mm"), ("rotation_rad", "rad")):
        s = cf[key]
        out.append(f"| {key.split('_')[0]} [{unit}] | {s['median']:.2e} | {s['p90']:.2e} | {s['p99']:.2e} | {s['max']:.2e} |")
    out.append("")
    out.append(f"*Verdict.* {cf['poses'] - cf['not_solved']} of {cf['poses']} poses solved in the true configuration; "
               f"worst residual {cf['position_mm']['max']:.1e} mm / {cf['rotation_rad']['max']:.1e} rad"
               + (" (rounding level: below 1e-9 mm / 1e-9 rad)" if cf['position_mm']['max'] < 1e-9 and cf['rotation_rad']['max'] < 1e-9 else "")
               + f", at {cf['solve_us_median']:.2f} us median per solve.\n")

    nm = data["numeric_generic6"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    pts = []
    for s in nm["series"]:
        it = [p["max_iterations"] for p in s["points"]]
        med = [max(p["position_mm"]["median"], FLOOR) for p in s["points"]]
        p90 = [max(p["position_mm"]["p90"], FLOOR) for p in s["points"]]
        us = [p["solve_us_median"] for p in s["points"]]
        line = axes[0].plot(it, med, marker="o", label=f"{s['seed']}, median")[0]
        axes[0].plot(it, p90, marker="x", linestyle="--", color=line.get_color(), label=f"{s['seed']}, p90")
        axes[1].plot(med, us, marker="o", color=line.get_color(), label=s["seed"])
        for p in s["points"]:
            pts.append({"err": p["position_mm"]["median"], "time": p["solve_us_median"], "method": s["seed"],
                        "label": f"{p['max_iterations']} iterations"})
    axes[0].set_xlabel("iterations (one descent, no restart)")
    axes[0].set_ylabel("position residual [mm]")
    axes[0].set_yscale("log")
    axes[1].set_xscale("log")
    axes[1].set_yscale("log")
    axes[1].set_xlabel("median position residual [mm]")
    axes[1].set_ylabel("median time per solve [us]")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"Numeric IK (Levenberg-Marquardt) on generic6.urdf, {nm['poses']} random poses")
    fig.tight_layout()
    fig.savefig(os.path.join(docs, "accuracy", "ik_numeric.png"), dpi=90)
    plt.close(fig)
    out.append("### Numeric solver on the URDF arm\n")
    out.append("![numeric IK](accuracy/ik_numeric.png)\n")
    words = []
    for s in nm["series"]:
        first = next((p for p in s["points"] if p["position_mm"]["median"] <= 1e-6), None)
        last = s["points"][-1]
        if first:
            words.append(f"{s['seed']}: median residual <= 1e-6 mm after {first['max_iterations']} iterations "
                         f"({first['solve_us_median']:.1f} us), {100 * last['within_1e-6mm_1e-9rad']:.1f} % of the poses within "
                         f"1e-6 mm / 1e-9 rad after {last['max_iterations']}")
        else:
            words.append(f"{s['seed']}: median residual never <= 1e-6 mm")
    d = nm["defaults_from_ready"]
    out.append("*Verdict.* " + verdict(pts, "mm") + " " + "; ".join(words) +
               f". With the simulator's defaults (restarts, 1e-6 mm / 1e-9 rad) from READY: {100 * d['success']:.1f} % solved, "
               f"{d['solve_us_median']:.1f} us median, residual max {d['position_mm']['max']:.1e} mm. A descent from a far "
               "seed stalls in local minima; the restarts recover those.\n")
    out.append("<details><summary>Data</summary>\n")
    out.append("| seed | iterations | position median [mm] | p90 [mm] | rotation median [rad] | within 1e-6 mm / 1e-9 rad | median [us] |")
    out.append("|---|---:|---:|---:|---:|---:|---:|")
    for s in nm["series"]:
        for p in s["points"]:
            out.append(f"| {s['seed']} | {p['max_iterations']} | {p['position_mm']['median']:.2e} | {p['position_mm']['p90']:.2e} | "
                       f"{p['rotation_rad']['median']:.2e} | {100 * p['within_1e-6mm_1e-9rad']:.1f} % | {p['solve_us_median']:.2f} |")
    out.append("\n</details>\n")
    return out


# -------------------------------------------------------------------------------------- page

def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 1
    docs = sys.argv[1]
    timing = sys.argv[sys.argv.index("--timing") + 1] if "--timing" in sys.argv else ""
    contact = load(os.path.join(docs, "accuracy", "contact.json"))
    path = load(os.path.join(docs, "accuracy", "path.json"))
    ik = load(os.path.join(docs, "accuracy", "ik.json"))
    with open(os.path.join(docs, "accuracy", "intro.md")) as f:
        intro = f.read().rstrip("\n")
    if intro.startswith("<!--"):  # the template's own note
        intro = intro[intro.index("-->") + 3:].lstrip("\n")
    intro = ("<!-- Generated by scripts/accuracy.sh from docs/accuracy/intro.md and docs/accuracy/*.json: "
             "edit those, not this file. -->\n" + intro)
    page = [intro.replace("@TIMING@", timing or "(not timed)").replace("@GENERATED@", contact["machine"]["generated_utc"]), ""]
    page.append("## 1. Contact instant and contact point\n")
    page += contact_section(docs, contact)
    page.append("## 2. Straight-line path deviation\n")
    page += path_section(docs, path)
    page.append("## 3. Inverse kinematics\n")
    page += ik_section(docs, ik)
    with open(os.path.join(docs, "accuracy.md"), "w") as f:
        f.write("\n".join(page).rstrip("\n") + "\n")
    print(f"wrote {os.path.join(docs, 'accuracy.md')} and {len([n for n in os.listdir(os.path.join(docs, 'accuracy')) if n.endswith('.png')])} plots")
    return 0


if __name__ == "__main__":
    sys.exit(main())
