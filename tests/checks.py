"""What the Python integration tests share: named checks that print PASS or FAIL,
and a runner that gives the test a scratch folder and turns failures into an exit
code for ctest."""
import os
import shutil
import sys
import tempfile
import time
import traceback

failures = []


def check(name, ok, detail=""):
    print(f"{'PASS' if ok else 'FAIL'} {name}" + (f": {detail}" if detail else ""), flush=True)
    if not ok:
        failures.append(name)
    return ok


def run(body, usage):
    """Calls body(gvr, shared_data, scratch) with the paths from
    argv = GVR_EXECUTABLE SHARED_DATA_DIR WORK_DIR; returns the exit code."""
    if len(sys.argv) < 4:
        print(usage)
        return 2
    gvr, shared, work = os.path.abspath(sys.argv[1]), sys.argv[2], sys.argv[3]
    os.makedirs(work, exist_ok=True)
    scratch = tempfile.mkdtemp(prefix=os.path.basename(sys.argv[0]).replace(".py", "_"), dir=work)
    started = time.time()
    try:
        body(gvr, shared, scratch)
    except Exception:
        traceback.print_exc()
        failures.append("exception")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    print(f"{'FAILED' if failures else 'OK'}: {len(failures)} failed check(s) in {time.time() - started:.1f} s"
          + (f": {failures}" if failures else ""))
    return 1 if failures else 0
