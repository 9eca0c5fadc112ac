"""Independent check of gvr ingest: nibabel reads the source, pyopenvdb reads gvr's
output, and both must agree on world positions and voxel values.

Usage: cross_check.py GVR_EXECUTABLE SHARED_DATA_DIR WORK_DIR
Runs with Debian's /usr/bin/python3 (python3-nibabel, python3-openvdb, python3-numpy).
"""
import os
import subprocess
import sys

import nibabel
import numpy as np
import pyopenvdb as vdb

gvr, shared, work = sys.argv[1:4]
cases = [
    "ct-gantry-tilt-shear/shear.nii.gz",
    "mri-colin27-aal/ch2.nii.gz",
    "mri-freesurfer-norm-aparc/norm.mgz",
    "mri-4d-asl-float32/mpld_asl.nii.gz",
]
rng = np.random.default_rng(7)
failures = 0
for case in cases:
    source = os.path.join(shared, case)
    output = os.path.join(work, os.path.basename(case) + ".vdb")
    subprocess.run([gvr, "ingest", "-q", source, "-o", output], check=True,
                   stdout=subprocess.DEVNULL)
    image = nibabel.load(source)
    data = image.get_fdata()  # scl_slope and scl_inter applied
    if data.ndim == 4:
        data = data[..., 0]
    grid = vdb.read(output, "density")
    accessor = grid.getConstAccessor()
    worst_mm, worst_value = 0.0, 0.0
    for _ in range(200):
        ijk = tuple(int(rng.integers(0, n)) for n in data.shape[:3])
        expected_world = image.affine @ np.array([*ijk, 1.0])
        world = np.array(grid.transform.indexToWorld(ijk))
        worst_mm = max(worst_mm, float(np.abs(world - expected_world[:3]).max()))
        value, active = accessor.probeValue(ijk)
        if active:
            worst_value = max(worst_value, abs(value - data[ijk]))
    ok = worst_mm < 1e-3 and worst_value < 1e-3 * max(1.0, float(np.abs(data).max()))
    failures += not ok
    print(f"{'ok  ' if ok else 'FAIL'} {case}: worst position error {worst_mm:.2e} mm, "
          f"worst value error {worst_value:.2e}")
print(f"{len(cases) - failures} passed, {failures} failed")
sys.exit(1 if failures else 0)
