#!/usr/bin/env bash
# `cmake --install` must give a tree that a project outside gvr builds against with
# find_package(gvr): examples/minimal.cpp is configured, built and run from it.
#     tests/installed_package.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
build=$1 source=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
# The installed package must not point back into the source or build tree.
if grep -rlF -e "$source/" -e "$build/" "$work/prefix/lib/cmake/gvr"; then
  echo "installed_package: the files above refer to the source or build tree" >&2
  exit 1
fi
cmake -S "$source/examples/installed" -B "$work/minimal" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log"
cmake --build "$work/minimal" > "$work/build.log"
"$work/minimal/minimal" /usr/share/mricron/templates/ch2.nii.gz "$work"
for output in minimal.gvr minimal.vdb minimal.png; do
  test -s "$work/$output" || { echo "installed_package: no $output" >&2; exit 1; }
done
"$work/prefix/bin/gvr" info "$work/minimal.gvr" > /dev/null
# Blender's script for `gvr export --dcc`, where the docs say it is.
test -s "$work/prefix/share/gvr/blender/render.py" || { echo "installed_package: no share/gvr/blender/render.py" >&2; exit 1; }
echo "installed_package: built and ran examples/minimal.cpp against $work/prefix"
