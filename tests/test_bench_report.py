"""Tests the rate-distortion tables and crossovers of bench/bench_report.py on made-up rows.

Usage: test_bench_report.py REPORT_SCRIPT
"""
import importlib.util
import sys


def load(path):
    spec = importlib.util.spec_from_file_location("bench_report", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def row(method, ratio, psnr, achieved=None):
    return {"volume": "v", "method": method, "ratio": ratio, "status": "ok", "psnr": psnr,
            "fg_psnr": psnr - 1, "bytes": 1000 / ratio, "ratio_raw": achieved or ratio}


def main():
    report = load(sys.argv[1])
    failures = []

    def expect(name, got, want):
        ok = got == want
        print(f"{'PASS' if ok else 'FAIL'} {name}: got {got!r}, want {want!r}")
        if not ok:
            failures.append(name)

    def verdicts(rows):
        """{codec label: the crossover table's verdict cell} for volume v."""
        out = {}
        for line in report.crossover_table(report.group_sections(rows)).splitlines()[2:]:
            cells = [c.strip() for c in line.strip("|").split("|")]
            out[cells[1]] = cells[3]
        return out

    # gvr loses at 10 and 20, wins from 40 up.
    rows = [row("gvr", 10, 30), row("zfp-accuracy", 10, 35), row("gvr", 20, 28), row("zfp-accuracy", 20, 29),
            row("gvr", 40, 26), row("zfp-accuracy", 40, 24), row("gvr", 80, 24), row("zfp-accuracy", 80, 20)]
    expect("crossover where gvr wins from 40:1 up", verdicts(rows), {"ZFP fixed-accuracy": "from 40.0:1 (target 40:1)"})

    # A win at 20 that is lost again at 40 does not count: the crossover needs every higher ratio.
    rows = [row("gvr", 20, 30), row("zfp-accuracy", 20, 29), row("gvr", 40, 26), row("zfp-accuracy", 40, 27),
            row("gvr", 80, 24), row("zfp-accuracy", 80, 20)]
    expect("a later loss moves the crossover up", verdicts(rows), {"ZFP fixed-accuracy": "from 80.0:1 (target 80:1)"})

    rows = [row("gvr", 10, 20), row("zfp-accuracy", 10, 35)]
    expect("no crossover", verdicts(rows), {"ZFP fixed-accuracy": "none"})

    # Every external codec gets its own verdict; a win that a higher ratio takes back is named as such.
    rows = [row("gvr", 10, 30), row("gvr", 20, 28), row("gvr", 40, 25),
            row("sz3", 10, 31), row("sz3", 20, 27), row("sz3", 40, 26),
            row("sperr", 10, 40), row("sperr", 20, 35), row("sperr", 40, 30),
            row("zfp-accuracy", 10, 25), row("zfp-accuracy", 20, 20), row("zfp-accuracy", 40, 10)]
    expect("one verdict per codec", verdicts(rows),
           {"ZFP fixed-accuracy": "from 10.0:1 (target 10:1)", "sperr": "none", "sz3": "at 20.0:1 (target 20:1) only"})
    skipped = dict(row("sz3", 80, 0), status="skipped", message="codec sz3: program 'sz3' not found on PATH")
    table = report.rate_distortion_table(report.group_sections(rows + [row("gvr", 80, 24), skipped]))
    expect("the rate-distortion table has a column per codec",
           table.splitlines()[0], "| Volume | Target ratio | gvr | ZFP fixed-accuracy | sperr | sz3 |")
    expect("a skipped codec says so in its cell", "skipped: codec sz3: program 'sz3' not found" in table, True)
    # Labelled by the target alone, an MRI row "at 10:1" had been measured at 42:1.
    rows = [row("gvr", 10, 30, achieved=42.04), row("zfp-accuracy", 10, 44, achieved=41.5)]
    sections = report.group_sections(rows)
    expect("a section is named by gvr's ratio, the target beside it",
           report.section_title("v", 10, sections[0][2]), "v at 42.0:1 (target 10:1)")
    expect("so is its verdict", report.verdict_list(sections).startswith("- v at 42.0:1 (target 10:1): gvr 30.00 dB"),
           True)
    expect("and its crossover", verdicts(rows), {"ZFP fixed-accuracy": "none"})
    expect("a section where gvr failed keeps its target",
           report.section_title("v", 10, {"gvr": dict(row("gvr", 10, 30), status="failed")}), "v at target 10:1")

    # A log axis within a decade once showed no numbers at all.
    if report.plt is not None:
        fig, ax = report.plt.subplots()
        ax.plot([31, 45], [30, 32], label="gvr")
        report.finish_axes(ax, "ratio", "short span")
        fig.canvas.draw()
        labels = [t.get_text() for t in ax.xaxis.get_ticklabels(which="both") if t.get_text()]
        expect("a log axis within a decade has numbers", len(labels) >= 2, True)
        report.plt.close(fig)

    print(f"{len(failures)} failed" if failures else "OK")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
