"""Tests the rate-distortion crossover of bench/bench_report.py on made-up rows.

Usage: test_bench_report.py REPORT_SCRIPT
"""
import importlib.util
import sys


def load(path):
    spec = importlib.util.spec_from_file_location("bench_report", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def row(method, ratio, psnr):
    return {"volume": "v", "method": method, "ratio": ratio, "status": "ok", "psnr": psnr,
            "fg_psnr": psnr - 1, "bytes": 1000 / ratio}


def main():
    report = load(sys.argv[1])
    failures = []

    def expect(name, got, want):
        ok = got == want
        print(f"{'PASS' if ok else 'FAIL'} {name}: got {got!r}, want {want!r}")
        if not ok:
            failures.append(name)

    # gvr loses at 10 and 20, wins from 40 up.
    rows = [row("gvr", 10, 30), row("zfp-accuracy", 10, 35), row("gvr", 20, 28), row("zfp-accuracy", 20, 29),
            row("gvr", 40, 26), row("zfp-accuracy", 40, 24), row("gvr", 80, 24), row("zfp-accuracy", 80, 20)]
    sections = report.group_sections(rows)
    expect("crossover where gvr wins from 40:1 up", report.crossover(report.crossover_rows(sections)["v"]), 40)
    table = report.crossover_table(sections)
    expect("the table names the crossover", "from 40:1" in table, True)
    expect("the table shows foreground PSNR", "gvr FG PSNR dB" in table, True)

    # A win at 20 that is lost again at 40 does not count: the crossover needs every higher ratio.
    rows = [row("gvr", 20, 30), row("zfp-accuracy", 20, 29), row("gvr", 40, 26), row("zfp-accuracy", 40, 27),
            row("gvr", 80, 24), row("zfp-accuracy", 80, 20)]
    expect("a later loss moves the crossover up",
           report.crossover(report.crossover_rows(report.group_sections(rows))["v"]), 80)

    rows = [row("gvr", 10, 20), row("zfp-accuracy", 10, 35)]
    expect("no crossover", "none up to 10:1" in report.crossover_table(report.group_sections(rows)), True)
    print(f"{len(failures)} failed" if failures else "OK")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
