#!/usr/bin/env bash
# Installs everything gvr needs to build, run and test: the Debian 12 packages named in
# .ci/packages.txt, and nothing else. Run as root.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
packages=$(grep -v '^\s*\(#\|$\)' "$(dirname "$0")/packages.txt")
apt-get update -qq
# shellcheck disable=SC2086 # one package name per word
apt-get install -y -qq --no-install-recommends $packages > /dev/null
