#!/usr/bin/env bash
# Every C++ file of the repository laid out as .clang-format says: run
# `clang-format -i FILE` on any file this names.
set -euo pipefail
cd "$1"
command -v clang-format > /dev/null || { echo "code_format: no clang-format (.ci/install-deps.sh installs it)"; exit 1; }
# find, not git ls-files: the suite runs where only .ci/install-deps.sh's packages are installed.
mapfile -t files < <(find pipeline io render workflow bench cli python tests examples \
  -path tests/data -prune -o \( -name '*.cpp' -o -name '*.h' \) -print | sort)
(( ${#files[@]} > 100 )) || { echo "code_format: found only ${#files[@]} C++ files in $1"; exit 1; }
off=()
for file in "${files[@]}"; do
  clang-format --dry-run --Werror "$file" > /dev/null 2>&1 || off+=("$file")
done
if (( ${#off[@]} > 0 )); then
  echo "code_format: ${#off[@]} of ${#files[@]} files differ from .clang-format's layout:"
  printf '  %s\n' "${off[@]}"
  exit 1
fi
echo "code_format: ${#files[@]} files as .clang-format lays them out"
