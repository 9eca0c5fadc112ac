#!/usr/bin/env bash
# Two builds of gvr side by side, alternating, twice over: peak memory, stack builds
# and reused frames of 24-frame orbits across the axes. The table of
# docs/benchmarks.md, "A render's memory". Prints one line a run; nothing is
# asserted. Run it with nothing else on the machine.
#
# Usage: bench/stack_memory.sh GVR_BEFORE GVR_AFTER CT_HEAD.vdb CHEST.vdb
#   CT_HEAD.vdb: gvr ingest ../shared/data/ct-head-visible-human-png
#   CHEST.vdb:   gvr ingest ../shared/data/ct-chest-ricord-512
set -euo pipefail
if [ $# -ne 4 ]; then
    sed -n '7,9p' "$0" >&2
    exit 2
fi
before=$(realpath "$1") after=$(realpath "$2") head=$(realpath "$3") chest=$(realpath "$4")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for _ in 1 2; do
    for row in "chest-ct|$chest --tf ct" "chest-ct-supersample-1|$chest --tf ct --supersample 1" \
               "chest-ct-bone|$chest --tf ct-bone" "head-mri|$head --tf mri" \
               "chest-ct-segments|$chest --tf ct --classify segments"; do
        name=${row%%|*} args=${row#*|}
        for gvr in "$before" "$after"; do
            # shellcheck disable=SC2086  # the row's arguments split on purpose
            /usr/bin/time -f "%M" -o "$work/peak" "$gvr" render $args -o "$work/o.png" --orbit 24 --stacks axes -q \
                --stats "$work/stats.json" >/dev/null
            python3 - "$name" "$gvr" "$(cat "$work/peak")" "$work/stats.json" <<'PY'
import json, sys
frames = json.load(open(sys.argv[4]))["frames"]
builds = [f["build_ms"] for f in frames if not f["reused"]]
reused = sorted(f["composite_ms"] + f["warp_ms"] for f in frames if f["reused"])
print(sys.argv[1], sys.argv[2], "peak %.0f MB;" % (int(sys.argv[3]) / 1024),
      "build %.0f ms;" % (sum(builds) / len(builds)), "reused %.1f ms" % reused[len(reused) // 2])
PY
        done
    done
done
