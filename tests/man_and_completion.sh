#!/usr/bin/env bash
# The man page that the build makes with help2man lists the commands, and the bash
# completion completes commands and options from what gvr itself prints.
# Usage: man_and_completion.sh GVR_EXECUTABLE MAN_PAGE COMPLETION_SCRIPT
set -euo pipefail
gvr=$1 man=$2 completion=$3
fail() { echo "FAIL $*"; exit 1; }
grep -q 'ingest' "$man" || fail "the man page does not list ingest"
grep -q '^\.TH GVR' "$man" || fail "the man page has no .TH header"
source "$completion"
complete_words() { COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _gvr; echo "${COMPREPLY[*]}"; }
[[ "$(complete_words "$gvr" fi)" == "fit" ]] || fail "'gvr fi' completes to '$(complete_words "$gvr" fi)'"
[[ " $(complete_words "$gvr" fit --ti) " == *" --time "* ]] || fail "'gvr fit --ti' completes to '$(complete_words "$gvr" fit --ti)'"
[[ " $(complete_words "$gvr" export x.gvr --fl) " == *" --float32 "* ]] || fail "'gvr export --fl' misses --float32"
echo "OK"
