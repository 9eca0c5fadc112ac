#!/usr/bin/env python3
"""Turn the results.json of `gvr bench` into report.md and plots/*.png.

Usage: python3 bench_report.py RESULTS_DIR

Missing or failed measurements never stop the report: they show as "—" or
"failed: message". Without matplotlib the report is still written.
"""
import csv
import json
import math
import os
import re
import sys
import tempfile

try:
    import matplotlib
    matplotlib.use("Agg")  # no display on benchmark machines
    import matplotlib.pyplot as plt
    from matplotlib import ticker
except ImportError as error:
    plt = None
    PLOTS_UNAVAILABLE = str(error)

KNOWN_METHODS = ["gvr", "gvr+bound", "A1", "A2", "A3", "A4", "A5", "zfp-accuracy", "zfp-rate",
                 "vdb-blosc", "vdb-half", "down2", "down3", "down4"]
LABELS = {"zfp-accuracy": "ZFP fixed-accuracy", "zfp-rate": "ZFP fixed-rate", "gvr+bound": "gvr with an error bound"}
EQUAL_SIZE = 0.05  # zfp-accuracy's tolerance search aims within 5 % of gvr's bytes
TIE_DB = 0.005     # smaller gaps print as 0.00 dB, so call them ties
DASH = "—"
DPI = 110
METHOD_COLUMNS = [("Bytes", "bytes", None), ("Ratio vs raw", "ratio_raw", 1), ("PSNR dB", "psnr", 2),
                  ("FG PSNR dB", "fg_psnr", 2), ("SSIM", "ssim", 4), ("MS-SSIM", "ms_ssim", 4),
                  ("Max error", "max_error", 4), ("Render PSNR dB", "render_psnr", 2),
                  ("Render SSIM", "render_ssim", 4), ("Compress s", "compress_s", 2), ("Decompress s", "decompress_s", 2),
                  ("Peak RSS MiB", "peak_rss_mib", 0), ("FPS", "render_fps", 1)]
DATASET_COLUMNS = [("Achieved ratio", "ratio_raw", 1), ("PSNR dB", "psnr", 2), ("FG PSNR dB", "fg_psnr", 2),
                   ("SSIM", "ssim", 4), ("MS-SSIM", "ms_ssim", 4), ("Render PSNR dB", "render_psnr", 2),
                   ("Render SSIM", "render_ssim", 4), ("FPS", "render_fps", 1), ("Fit s", "compress_s", 1)]
ABLATION_COLUMNS = [("PSNR dB", "psnr", 2), ("FG PSNR dB", "fg_psnr", 2), ("SSIM", "ssim", 4), ("MS-SSIM", "ms_ssim", 4),
                    ("Render PSNR dB", "render_psnr", 2)]


# --- reading -------------------------------------------------------------------------------------

def number(value):
    """A float, or None when not measured (load_results() puts back the infinities)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        return None
    try:
        return float(value)
    except ValueError:
        return None


def load_results(results_dir):
    with open(os.path.join(results_dir, "results.json"), encoding="utf-8") as file:
        data = json.load(file)
    if not isinstance(data, dict):
        raise ValueError("the top level is not a JSON object")
    rows = [row for row in data.get("rows") or [] if isinstance(row, dict)]
    for row in rows:  # JSON has no infinity: the bench writes null and names the column
        infinite = row.get("infinite")
        for column in infinite if isinstance(infinite, list) else []:
            if isinstance(column, str) and row.get(column) is None:
                row[column] = math.inf
    return str(data.get("manifest", "")), rows


def load_runs(results_dir):
    """run.json's runs (one per shard): the machine, its load, the jobs and the fit budgets; [] when absent."""
    try:
        with open(os.path.join(results_dir, "run.json"), encoding="utf-8") as file:
            runs = json.load(file).get("runs")
    except (OSError, ValueError, AttributeError):
        return []
    return [run for run in runs if isinstance(run, dict)] if isinstance(runs, list) else []


def load_codecs(results_dir):
    """codecs.json: each external codec's commands, programs and version; {} when absent or unreadable."""
    try:
        with open(os.path.join(results_dir, "codecs.json"), encoding="utf-8") as file:
            codecs = json.load(file)
    except (OSError, ValueError):
        return {}
    return codecs if isinstance(codecs, dict) else {}


def read_fit_log(results_dir, relative):
    """(seconds, psnr) pairs usable on a log time axis; [] when the log is absent or unreadable."""
    if not relative:
        return []
    try:
        with open(os.path.join(results_dir, relative), encoding="utf-8") as file:
            lines = [line for line in file if line.strip() and not line.startswith("#")]
    except (OSError, ValueError):  # absent, a directory, or not text
        return []
    points = []
    for record in csv.DictReader(lines):
        seconds, psnr = number(record.get("seconds")), number(record.get("psnr_db"))
        if seconds is not None and psnr is not None and seconds > 0 and math.isfinite(psnr):
            points.append((seconds, psnr))
    return points


def is_ok(row):
    return row.get("status") == "ok"


def method_of(row):
    return str(row.get("method") or "?")


def is_ablation(method):
    return re.fullmatch(r"A\d+", method) is not None


def method_order(method):
    return (KNOWN_METHODS.index(method) if method in KNOWN_METHODS else len(KNOWN_METHODS), method)


def group_sections(rows):
    """[(volume, ratio, {method: row})] in manifest order. Ratio-independent baselines join every
    ratio section of their volume, so that each section lists every alternative to gvr."""
    sections = []
    for volume in dict.fromkeys(str(row.get("volume")) for row in rows):
        own = [row for row in rows if str(row.get("volume")) == volume]
        ratios = sorted({number(row.get("ratio")) for row in own} - {None}) or [None]
        for ratio in ratios:
            members = {}
            for row in own:  # a later row (a --merge re-run) replaces an earlier one
                if number(row.get("ratio")) in (ratio, None):
                    members[method_of(row)] = row
            sections.append((volume, ratio, dict(sorted(members.items(), key=lambda m: method_order(m[0])))))
    return sections


# --- formatting ----------------------------------------------------------------------------------

def fmt(value, digits, signed=False):
    x = number(value)
    if x is None or math.isnan(x):
        return DASH
    if math.isinf(x):
        return ("+∞" if signed else "∞") if x > 0 else "−∞"
    if digits is None:
        return f"{int(x):,}"
    return f"{x:+.{digits}f}" if signed else f"{x:.{digits}f}"


def fmt_ratio(ratio):
    return f"{ratio:g}"


def achieved_ratio(members):
    """gvr's ratio against the raw source in a section: what the section was measured at,
    since ZFP and the codecs match gvr's bytes."""
    gvr = members.get("gvr")
    achieved = number(gvr.get("ratio_raw")) if gvr is not None and is_ok(gvr) else None
    return achieved if achieved is not None and math.isfinite(achieved) else None


def ratio_label(target, achieved):
    """'42.1:1 (target 10:1)': where a section was measured, with what was asked beside it.
    (Labelled by the target alone, an MRI row "at 10:1" had been measured at 42:1.)"""
    if achieved is None:
        return f"target {fmt_ratio(target)}:1"
    return f"{achieved:.1f}:1 (target {fmt_ratio(target)}:1)"


def section_title(volume, ratio, members):
    if ratio is None:
        return f"{volume} (ratio-independent)"
    return f"{volume} at {ratio_label(ratio, achieved_ratio(members))}"


def safe_name(text):
    return re.sub(r"[^A-Za-z0-9.+-]+", "_", text).strip("._") or "unnamed"


def plot_name(volume, ratio, kind):
    tag = f"r{fmt_ratio(ratio)}" if ratio is not None else "ratio-independent"
    return f"{safe_name(volume)}_{safe_name(tag)}_{kind}.png"


def failure(row):
    status = "skipped" if row.get("status") == "skipped" else "failed"
    return f"{status}: {row.get('message') or 'no message'}"


def md_cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def md_table(header, body):
    if not body:
        return "_No data._\n"
    lines = ["| " + " | ".join(map(md_cell, header)) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(map(md_cell, line)) + " |" for line in body]
    return "\n".join(lines) + "\n"


def measured_cells(row, columns):
    if row is None:
        return ["not run"] + [DASH] * (len(columns) - 1)
    if not is_ok(row):
        return [failure(row)] + [DASH] * (len(columns) - 1)
    return [fmt(row.get(key), digits) for _, key, digits in columns]


# --- comparisons -----------------------------------------------------------------------------------

def psnr_gap(row, reference):
    """row's PSNR minus reference's; two lossless (∞) results tie instead of giving NaN."""
    a, b = number(row.get("psnr")), number(reference.get("psnr"))
    if a is None or b is None or math.isnan(a) or math.isnan(b):
        return None
    return 0.0 if a == b else a - b


def english_list(items):
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def unusable(name, row):
    """Why a row cannot enter a comparison, or None when it can."""
    if row is None:
        return f"{name} not run"
    return None if is_ok(row) else f"{name} {failure(row)}"


def size_clause(gvr, other, label):
    gvr_bytes, other_bytes = number(gvr.get("bytes")), number(other.get("bytes"))
    if not gvr_bytes or other_bytes is None:
        return "(sizes unknown)"
    change = other_bytes / gvr_bytes - 1
    if abs(change) <= EQUAL_SIZE:
        return f"at equal size ({label} {change:+.1%} bytes, within 5 %)"
    return f"at unequal size ({label} {change:+.1%} bytes vs gvr, outside 5 %: not like-for-like)"


def baseline_verdict(title, members, method):
    label = LABELS.get(method, method)
    gvr, other = members.get("gvr"), members[method]
    reasons = [reason for reason in (unusable("gvr", gvr), unusable(method, other)) if reason]
    if reasons:
        return f"{title}: no gvr vs {label} comparison ({'; '.join(reasons)})."
    gap = psnr_gap(gvr, other)
    if gap is None:
        outcome = "PSNR missing, no winner"
    elif abs(gap) < TIE_DB:
        outcome = "a tie"
    else:
        outcome = f"{'gvr' if gap > 0 else label} wins by {fmt(abs(gap), 2)} dB"
    return (f"{title}: gvr {fmt(gvr.get('psnr'), 2)} dB vs {label} {fmt(other.get('psnr'), 2)} dB "
            f"{size_clause(gvr, other, label)}: {outcome}.")


def ablation_verdict(title, members):
    gvr, reason = members.get("gvr"), unusable("gvr", members.get("gvr"))
    if reason:
        return f"{title}: no ablation verdict, {reason}."
    groups = {"beats": [], "loses to": [], "ties": [], "cannot be compared with": []}
    for method in filter(is_ablation, members):
        gap = psnr_gap(gvr, members[method]) if is_ok(members[method]) else None
        verb = ("cannot be compared with" if gap is None else "ties" if abs(gap) < TIE_DB
                else "beats" if gap > 0 else "loses to")
        groups[verb].append(f"{method} (by {fmt(-gap, 2)} dB)" if verb == "loses to" else method)
    clauses = [f"{verb} {english_list(names)}" for verb, names in groups.items() if names]
    return f"{title}: MC sampling + curriculum (gvr, {fmt(gvr.get('psnr'), 2)} dB) {'; '.join(clauses)}."


def competitors(methods):
    """The lossy codecs gvr is measured against at equal bytes, in report order: ZFP's
    accuracy mode and every external codec (any method gvr does not know)."""
    return [m for m in sorted(set(methods), key=method_order) if m == "zfp-accuracy" or m not in KNOWN_METHODS]


def section_verdicts(title, members):
    verdicts = [baseline_verdict(title, members, m) for m in ["zfp-rate"] + competitors(members) if m in members]
    if any(map(is_ablation, members)):
        verdicts.append(ablation_verdict(title, members))
    return verdicts


# --- report ----------------------------------------------------------------------------------------

def method_table(members):
    # ratio-independent rows (†) have other sizes, so they compete for bold only in their own section
    rated = any(number(r.get("ratio")) is not None for r in members.values())

    def competes(row):
        return is_ok(row) and (number(row.get("ratio")) is not None or not rated)

    psnrs = [number(r.get("psnr")) for r in members.values() if competes(r)]
    best = max((p for p in psnrs if p is not None and math.isfinite(p)), default=None)
    body = []
    for method, row in members.items():
        cells = measured_cells(row, METHOD_COLUMNS)
        if competes(row) and best is not None and number(row.get("psnr")) == best:
            cells[2] = f"**{cells[2]}**"
        dagger = " †" if number(row.get("ratio")) is None else ""
        body.append([method + dagger, row.get("detail") or DASH] + cells)
    return md_table(["Method", "Detail"] + [c[0] for c in METHOD_COLUMNS], body)


def ratio_cell(ratio):
    return fmt_ratio(ratio) if ratio is not None else DASH


def link_line(links):
    present = [f"[{label}](plots/{name})" for label, name in links if name]
    return "Plots: " + " · ".join(present) + "\n" if present else ""


def dataset_table(sections):
    body = [[volume, fmt_ratio(ratio)] + measured_cells(members.get("gvr"), DATASET_COLUMNS)
            for volume, ratio, members in sections if ratio is not None]
    return md_table(["Volume", "Target ratio"] + [c[0] for c in DATASET_COLUMNS], body)


def method_sections(sections, plots):
    if not sections:
        return ["_No data._\n"]
    out = ["† = ratio-independent method, repeated in every ratio section of its volume. "
           "Bold: best finite PSNR among the methods run at the section's ratio.\n"]
    for volume in dict.fromkeys(v for v, _, _ in sections):
        out += [f"### {volume}\n", link_line([("rate–distortion", plots.get((volume, "rd")))])]
        for ratio, members in ((r, m) for v, r, m in sections if v == volume):
            out += [f"#### {section_title(volume, ratio, members)}\n",
                    link_line([("PSNR vs time", plots.get((volume, ratio, "time"))),
                               ("contact sheet", plots.get((volume, ratio, "sheet")))]),
                    method_table(members)]
    return out


def ablation_table(sections):
    body = []
    for volume, ratio, members in sections:
        if not any(map(is_ablation, members)):
            continue
        gvr = members.get("gvr")
        for method in (m for m in members if m == "gvr" or is_ablation(m)):
            row = members[method]
            comparable = method != "gvr" and gvr is not None and is_ok(gvr) and is_ok(row)
            delta = fmt(psnr_gap(row, gvr), 2, signed=True) if comparable else DASH
            body.append([volume, ratio_cell(ratio), method] + measured_cells(row, ABLATION_COLUMNS) + [delta])
    return md_table(["Volume", "Target ratio", "Method"] + [c[0] for c in ABLATION_COLUMNS] + ["ΔPSNR vs gvr dB"], body)


def crossover(points):
    """The label of the lowest ratio from which gvr beats the codec at every measured ratio
    above it; points are (ratio, label, gap), the ratio gvr's achieved one where known."""
    lowest = None
    for _, label, gap in sorted(points, reverse=True):
        if gap is None or gap <= 0:
            break
        lowest = label
    return lowest


def crossover_verdict(points):
    wins = [label for _, label, gap in sorted(points) if gap is not None and gap > 0]
    lowest = crossover(points)
    if lowest is not None:
        return f"from {lowest}"
    if not wins:
        return "none"
    return "at " + english_list(wins) + " only"


def codec_cell(row):
    if row is None:
        return "not run"
    if not is_ok(row):
        return failure(row)
    return f"{fmt(row.get('psnr'), 2)} at {fmt(row.get('ratio_raw'), 1)}:1"


def rate_distortion_table(sections):
    rated = [(v, r, m) for v, r, m in sections if r is not None]
    codecs = competitors(m for _, _, members in rated for m in members)
    body = [[volume, fmt_ratio(ratio), codec_cell(members.get("gvr"))] + [codec_cell(members.get(c)) for c in codecs]
            for volume, ratio, members in rated]
    return md_table(["Volume", "Target ratio", "gvr"] + [LABELS.get(c, c) for c in codecs], body)


def crossover_table(sections):
    """Per volume and codec: gvr's PSNR lead at each ratio where both ran, and from where it wins."""
    points = {}
    for volume, ratio, members in sections:
        gvr = members.get("gvr")
        if ratio is None or gvr is None or not is_ok(gvr):
            continue
        achieved = achieved_ratio(members)
        for codec in competitors(members):
            if is_ok(members[codec]):
                point = (achieved if achieved is not None else ratio, ratio_label(ratio, achieved), psnr_gap(gvr, members[codec]))
                points.setdefault((volume, codec), []).append(point)
    body = [[volume, LABELS.get(codec, codec),
             ", ".join(f"{label} {fmt(g, 2, signed=True)}" for _, label, g in sorted(pts)), crossover_verdict(pts)]
            for (volume, codec), pts in points.items()]
    if not body:
        return "_gvr and a codec were not both run at any ratio._\n"
    return md_table(["Volume", "Codec", "gvr PSNR minus the codec's, dB, at gvr's ratio", "gvr wins"], body)


def codecs_table(codecs):
    body = [[name, spec.get("version") or DASH, " ".join(spec.get("compress") or []),
             " ".join(spec.get("decompress") or []),
             " to ".join(f"{p:g}" for p in spec.get("param") or [] if number(p) is not None),
             ", ".join(p or "missing" for p in dict.fromkeys(spec.get("programs") or []))]
            for name, spec in codecs.items() if isinstance(spec, dict)]
    return md_table(["Codec", "Version", "Compress", "Decompress", "Parameter range", "Programs"], body)


def verdict_list(sections):
    verdicts = [verdict for v, r, m in sections for verdict in section_verdicts(section_title(v, r, m), m)]
    return "".join(f"- {verdict}\n" for verdict in verdicts) or "_No comparisons possible._\n"


def rows_with_status(rows, status):
    body = [[row.get("volume"), ratio_cell(number(row.get("ratio"))), method_of(row), row.get("message") or DASH]
            for row in rows if row.get("status") == status]
    return md_table(["Volume", "Target ratio", "Method", "Message"], body)


def budget_text(budget):
    if not isinstance(budget, dict):
        return DASH
    iterations, seconds = number(budget.get("iterations")), number(budget.get("seconds"))
    text = f"{int(iterations)} iterations" if iterations is not None else f"{seconds:g} s" if seconds is not None else DASH
    args = [str(a) for a in budget.get("args") or []]
    return text + (f" (`{' '.join(args)}`)" if args else "")


def run_lines(runs):
    """Where the times were measured: the machine, its load and the jobs of each run, and the
    fit budget of each volume (the same in every shard of one manifest)."""
    if not runs:
        return ["Machine and fit budgets: not recorded (run.json missing).\n"]
    lines = []
    for run in runs:
        machine = run.get("machine") if isinstance(run.get("machine"), dict) else {}
        load = number(machine.get("load_average_1min"))
        lines.append(f"- Shard {run.get('shard', DASH)}: {machine.get('cpu', 'unknown CPU')}, "
                     f"{machine.get('cores', DASH)} cores, load average {fmt(load, 2)} at the start; "
                     f"{run.get('jobs', DASH)} volume(s) at a time.")
    budgets = runs[0].get("fit") if isinstance(runs[0].get("fit"), dict) else {}
    if budgets:
        lines.append("- Fit budget: " + "; ".join(f"{volume} {budget_text(b)}" for volume, b in budgets.items()) + ".")
    return ["\n".join(lines) + "\n"]


def render_report(manifest, rows, sections, plots, codecs, runs):
    ok = sum(1 for row in rows if is_ok(row))
    skipped = sum(1 for row in rows if row.get("status") == "skipped")
    return "\n".join(
        ["# gvr benchmark report\n", f"Manifest: `{manifest or DASH}`  ",
         f"Rows: {ok} ok, {len(rows) - ok - skipped} failed, {skipped} skipped. Sections are named by gvr's "
         "ratio against the raw source, with the target the manifest asked beside it.\n",
         *run_lines(runs),
         "## Table 1 – gvr per dataset\n", dataset_table(sections),
         "## Table 2 – all methods\n", *method_sections(sections, plots),
         "## Table 3 – ablations\n", ablation_table(sections),
         "## Table 4 – rate–distortion: gvr against every codec\n",
         "Whole-volume PSNR in dB at the ratio each reached against the raw source. ZFP fixed-accuracy and "
         "the external codecs search their parameter to match gvr's asset size within 5 % (or the target "
         "ratio where gvr was not run). Plots: PSNR against ratio, one per volume (the rate–distortion "
         "links in Table 2).\n",
         rate_distortion_table(sections),
         "### Crossover\n",
         "Where gvr wins: from the lowest ratio (gvr's, against the raw source) at which gvr's PSNR beats the "
         "codec's at that ratio and at every higher one measured; \"none\" where it wins at no ratio.\n",
         crossover_table(sections),
         "## Codecs\n", codecs_table(codecs),
         "## Verdicts\n", verdict_list(sections),
         "## Failed runs\n", rows_with_status(rows, "failed"),
         "## Skipped runs\n", "A codec whose program was not found on this machine.\n",
         rows_with_status(rows, "skipped")])


# --- plots -----------------------------------------------------------------------------------------

def method_colours(rows):
    """One colour per method across all figures; tab20's dark shades first so neighbours differ."""
    palette = plt.get_cmap("tab20").colors
    palette = palette[0::2] + palette[1::2]
    methods = sorted({method_of(row) for row in rows}, key=method_order)
    return {method: palette[i % len(palette)] for i, method in enumerate(methods)}


def line_style(method):
    if method == "gvr":
        return {"linestyle": "-", "linewidth": 2.4}
    return {"linestyle": "--" if is_ablation(method) else "-.", "linewidth": 1.4}


def total_seconds(row):
    parts = [number(row.get(k)) for k in ("compress_s", "decompress_s")]
    parts = [p for p in parts if p is not None]
    return sum(parts) if parts else None


def finish_axes(ax, xlabel, title):
    ax.set(xscale="log", xlabel=xlabel, ylabel="PSNR (dB)", title=title)
    # plain numbers: every tick on a span within a decade (which may hold no decade tick at
    # all, and had no numbers), 2 and 5 between decades on up to three
    def minor_label(x, _):
        low, high = ax.get_xlim()
        decades = math.log10(high / low)
        return f"{x:g}" if decades <= 1 or (f"{x:.0e}"[0] in "25" and decades <= 3) else ""
    ax.xaxis.set_major_formatter(ticker.FormatStrFormatter("%g"))
    ax.xaxis.set_minor_formatter(ticker.FuncFormatter(minor_label))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8)


def psnr_vs_time_figure(results_dir, title, members, colours):
    fig, ax = plt.subplots(figsize=(8, 5))
    notes = []
    for method, row in ((m, r) for m, r in members.items() if is_ok(r)):
        curve = read_fit_log(results_dir, row.get("fit_log"))
        seconds, psnr = total_seconds(row), number(row.get("psnr"))
        if curve:
            ax.plot(*zip(*curve), color=colours[method], label=f"{method} (fit log)",
                    marker="o" if len(curve) == 1 else None, **line_style(method))  # one point: no line
        elif psnr is not None and math.isinf(psnr):
            notes.append(f"{method}: ∞ dB, not drawn")
        elif seconds and seconds > 0 and psnr is not None:
            ax.plot([seconds], [psnr], "o", color=colours[method], markersize=7, label=method)
            ax.annotate(method, (seconds, psnr), xytext=(5, 4), textcoords="offset points", fontsize=8)
    if not ax.lines:
        plt.close(fig)
        return None
    finish_axes(ax, "run time (s, log scale; fit log, or encode + decode)", f"{title}: PSNR against run time")
    if notes:
        fig.text(0.01, -0.02, "; ".join(notes), fontsize=8, va="top")
    return fig


def rate_distortion_figure(volume, rows, colours):
    points, swept = {}, set()
    for row in (r for r in rows if str(r.get("volume")) == volume and is_ok(r)):
        ratio, psnr = number(row.get("ratio_raw")), number(row.get("psnr"))
        if ratio and 0 < ratio < math.inf and psnr is not None:
            points.setdefault(method_of(row), []).append((ratio, psnr))
            if number(row.get("ratio")) is not None:
                swept.add(method_of(row))
    if not points:
        return None
    finite = [p for pts in points.values() for _, p in pts if math.isfinite(p)]
    top = max(finite, default=40.0) + 3  # the height that stands for ∞ (lossless)
    fig, ax = plt.subplots(figsize=(8, 5))
    for method in sorted(points, key=method_order):
        xs, ys = zip(*sorted(points[method]))
        style = dict(marker="o", **line_style(method)) if method in swept else dict(marker="s", linestyle="")
        ax.plot(xs, [min(y, top) for y in ys], color=colours[method], label=method, **style)
        for x in (x for x, y in zip(xs, ys) if math.isinf(y)):
            ax.plot([x], [top], "^", color=colours[method], markersize=11)
            ax.annotate(f"{method}: ∞ dB (lossless)", (x, top), xytext=(8, -4), textcoords="offset points", fontsize=8)
    ax.set_ylim(top=top + 2)
    finish_axes(ax, "compression ratio vs raw source (log scale)", f"{volume}: rate–distortion")
    return fig


def load_image(results_dir, relative):
    try:
        return plt.imread(os.path.join(results_dir, relative)) if relative else None
    except Exception:  # any unreadable or truncated PNG is shown as missing, not fatal
        return None


def contact_sheet_figure(results_dir, title, members):
    truth = next((r.get("truth_views") for r in members.values() if r.get("truth_views")), None) or []
    columns = [("ray-marched original", truth)] + [
        (f"{m}\n{fmt(r.get('render_psnr'), 2)} dB", r.get("views"))
        for m, r in members.items() if is_ok(r) and r.get("views")]
    views = max(len(paths) for _, paths in columns)
    if len(columns) < 2 or views == 0:  # the originals alone compare nothing
        return None
    fig, axes = plt.subplots(views, len(columns), squeeze=False, layout="constrained",
                             figsize=(max(1.8 * len(columns), 6), 1.8 * views + 0.9))
    for c, (label, paths) in enumerate(columns):
        axes[0][c].set_title(label, fontsize=8)
        for r in range(views):
            ax = axes[r][c]
            ax.set_xticks([])
            ax.set_yticks([])
            image = load_image(results_dir, paths[r]) if r < len(paths) else None
            if image is None:
                ax.text(0.5, 0.5, "missing", ha="center", va="center", color="grey", transform=ax.transAxes)
            else:
                ax.imshow(image, cmap="gray" if image.ndim == 2 else None)
    for r in range(views):
        axes[r][0].set_ylabel(f"view {r + 1}", fontsize=8)
    fig.suptitle(f"{title}: shear-warp renders (render PSNR vs ray-marched original)", fontsize=10)
    return fig


def save_plot(plots_dir, name, draw):
    """Writes the figure atomically; returns the name, or None when there was nothing to draw."""
    fig = None
    try:
        fig = draw()
        if fig is not None:
            write_atomically(os.path.join(plots_dir, name),
                             lambda file: fig.savefig(file, format="png", dpi=DPI, bbox_inches="tight"))
            return name
    except Exception as error:  # one bad figure must not cost the report and the other plots
        print(f"bench_report: plot {name} failed: {error}", file=sys.stderr)
    finally:
        if fig is not None:
            plt.close(fig)
    return None


def make_plots(results_dir, rows, sections):
    plots_dir = os.path.join(results_dir, "plots")
    os.makedirs(plots_dir, exist_ok=True)
    colours = method_colours(rows)
    plots = {}
    for volume in dict.fromkeys(v for v, _, _ in sections):
        plots[volume, "rd"] = save_plot(plots_dir, f"{safe_name(volume)}_rate_distortion.png",
                                        lambda: rate_distortion_figure(volume, rows, colours))
    for volume, ratio, members in sections:
        title = section_title(volume, ratio, members)
        plots[volume, ratio, "time"] = save_plot(plots_dir, plot_name(volume, ratio, "psnr_vs_time"),
                                                 lambda: psnr_vs_time_figure(results_dir, title, members, colours))
        plots[volume, ratio, "sheet"] = save_plot(plots_dir, plot_name(volume, ratio, "contact_sheet"),
                                                  lambda: contact_sheet_figure(results_dir, title, members))
    return plots


def write_atomically(path, write):
    """Readers never see a half-written file, and a failed write leaves the old one intact.
    The temporary's name cannot be foreseen (mkstemp), so no link planted beside the
    output can redirect the write."""
    folder, name = os.path.split(path)
    descriptor, temporary = tempfile.mkstemp(prefix=f".{name}.", dir=folder or ".")
    try:
        with os.fdopen(descriptor, "wb") as file:
            write(file)
        umask = os.umask(0)  # mkstemp's 0600, made what open() would have given
        os.umask(umask)
        os.chmod(temporary, 0o666 & ~umask)
        os.replace(temporary, path)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)


def main(argv):
    if len(argv) != 2:
        print("usage: bench_report.py RESULTS_DIR", file=sys.stderr)
        return 2
    results_dir = argv[1]
    try:
        manifest, rows = load_results(results_dir)
    except (OSError, ValueError) as error:
        print(f"bench_report: cannot read {results_dir}/results.json: {error}", file=sys.stderr)
        return 1
    sections = group_sections(rows)
    plots = make_plots(results_dir, rows, sections) if plt else {}
    report = render_report(manifest, rows, sections, plots, load_codecs(results_dir), load_runs(results_dir))
    write_atomically(os.path.join(results_dir, "report.md"), lambda file: file.write(report.encode("utf-8")))
    if plt is None:
        print(f"bench_report: plots skipped: matplotlib unavailable ({PLOTS_UNAVAILABLE})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
