"""Tests .ci/deps-audit: it must fail when a used file's package is missing from the list.

Usage: test_deps_audit.py AUDIT BUILD_DIR WORK_DIR

Synthetic build folders stand for the two ways a package gets used: the build (an imported
target's file, as OpenImageIOTargets.cmake checks /usr/bin/iconvert) and the tests (a
program in strace's output). The real build folder is audited too, with and without
openimageio-tools in the list.
"""
import os
import subprocess
import sys

from checks import check, run

USAGE = "usage: test_deps_audit.py AUDIT BUILD_DIR WORK_DIR"


def audit(build_dir, *flags, env=None):
    result = subprocess.run([sys.argv[1], build_dir] + list(flags), stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, env=env)
    return result.returncode, result.stdout


def fake_build(folder, imported="", trace=""):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "CMakeCache.txt"), "w") as f:
        f.write("CMAKE_MAKE_PROGRAM:FILEPATH=/usr/bin/ninja\n")
    with open(os.path.join(folder, "imported-files.txt"), "w") as f:
        f.write(imported)
    with open(os.path.join(folder, "build.ninja"), "w") as f:
        f.write("# empty\n")
    trace_file = os.path.join(folder, "trace.txt")
    with open(trace_file, "w") as f:
        f.write(trace)
    return trace_file


def body(_audit, build_dir, tmp):
    tool = os.path.join(tmp, "tool")
    trace = fake_build(tool, imported="OpenImageIO::iconvert\tIMPORTED_LOCATION_RELEASE\t/usr/bin/iconvert\n")
    code, out = audit(tool, "--trace", trace)
    check("an imported tool from a listed package passes", code == 0, f"exit {code}: {out.strip()}")
    code, out = audit(tool, "--trace", trace, "--drop", "openimageio-tools")
    check("an imported tool from a dropped package fails, naming file and package",
          code == 1 and "/usr/bin/iconvert" in out and "openimageio-tools" in out, f"exit {code}: {out.strip()}")

    ran = os.path.join(tmp, "ran")
    trace = fake_build(ran, trace='42  execve("/usr/bin/oiiotool", ["oiiotool"], 0x7f /* 3 vars */) = 0\n')
    code, out = audit(ran, "--trace", trace, "--drop", "openimageio-tools")
    check("a program the tests ran from a dropped package fails",
          code == 1 and "/usr/bin/oiiotool" in out and "executed by the tests" in out, f"exit {code}: {out.strip()}")

    home = os.path.join(tmp, "home")
    module = os.path.join(home, ".local", "lib", "python3.11", "site-packages", "handmade.py")
    os.makedirs(os.path.dirname(module))
    open(module, "w").close()
    hand = os.path.join(tmp, "hand")
    trace = fake_build(hand, trace=f'7  openat(AT_FDCWD, "{module}", O_RDONLY|O_CLOEXEC) = 3\n')
    code, out = audit(hand, "--trace", trace, env=dict(os.environ, HOME=home))
    check("a module installed by hand, outside any package, fails",
          code == 1 and module in out and "no Debian package" in out, f"exit {code}: {out.strip()}")

    code, out = audit(build_dir)
    check("the real build passes with the project's list", code == 0, f"exit {code}: {out.strip()[-800:]}")
    code, out = audit(build_dir, "--drop", "openimageio-tools")
    check("the real build fails without openimageio-tools", code == 1 and "/usr/bin/iconvert" in out,
          f"exit {code}: {out.strip()[-800:]}")


if __name__ == "__main__":
    sys.exit(run(body, USAGE))
