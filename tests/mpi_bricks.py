"""gvr fit --bricks under mpirun, as on a cluster but with two ranks on localhost.

Usage: python3 mpi_bricks.py GVR WORK

- Two ranks give the same asset, byte for byte, as one process fitting the same
  bricks with the same seed and iterations, and rank 0 reports every brick with
  the rank that fitted it.
- The ranks share the dense measurement of the saved asset, and their report's
  PSNR figures equal one process's to the last bit.
- A brick that fails is named with its rank, the exit code is not zero, and no
  asset is written.
"""
import json
import os
import subprocess
import sys

GVR, WORK = sys.argv[1:3]
CH2 = "/usr/share/mricron/templates/ch2.nii.gz"
FIT = ["fit", "-q", CH2, "--bricks", "4", "--ratio", "60", "--iterations", "15", "--seed", "9", "--batch", "4096",
       "--held-out", "4096", "--solve-iterations", "2"]
# mpirun refuses root unless told twice; --oversubscribe allows two ranks on one core.
MPIRUN = ["mpirun", "--oversubscribe", "-np", "2"]
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def run(command, env=ENV):
    return subprocess.run(command, capture_output=True, text=True, env=env)


def main():
    os.makedirs(WORK, exist_ok=True)
    alone, ranked = os.path.join(WORK, "alone.gvr"), os.path.join(WORK, "ranked.gvr")
    for path in (alone, ranked):
        if os.path.exists(path):
            os.remove(path)

    single = run([GVR, *FIT, "-o", alone, "--json"])
    assert single.returncode == 0, single.stderr
    alone_report = json.loads(single.stdout)
    spread = run([*MPIRUN, GVR, *FIT, "-o", ranked, "--json"])
    assert spread.returncode == 0, spread.stderr
    report = json.loads(spread.stdout)  # only rank 0 prints
    ranks = sorted({brick["rank"] for brick in report["bricks"]})
    assert ranks == [0, 1], report["bricks"]
    with open(alone, "rb") as a, open(ranked, "rb") as b:
        assert a.read() == b.read(), "the two-rank asset differs from the one-process asset"
    figures = ["psnr_db", "fg_psnr_db", "seam_psnr_db", "interior_psnr_db", "seam_voxels"]
    for figure in figures:
        assert report[figure] == alone_report[figure], (figure, report[figure], alone_report[figure])
    print(f"2 ranks: {len(report['bricks'])} bricks, byte-identical to one process "
          f"({os.path.getsize(ranked)} bytes), the same {report['psnr_db']} dB")

    failed_path = os.path.join(WORK, "failed.gvr")
    # A test hook, not a flag: -x hands the variable to every rank.
    failing = dict(ENV, GVR_TEST_FAIL_BRICK="2")
    failed = run([*MPIRUN, "-x", "GVR_TEST_FAIL_BRICK", GVR, *FIT, "-o", failed_path], env=failing)
    assert failed.returncode != 0, "a failing brick gave exit code 0"
    assert "brick 2 (rank " in failed.stderr, failed.stderr
    assert not os.path.exists(failed_path), "a failed run wrote its output"
    print("a failing brick: named with its rank, exit", failed.returncode, "and no file")


main()
