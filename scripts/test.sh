#!/usr/bin/env bash
# Installs what is missing (Debian 12), builds, and runs the whole test suite (unit, node, e2e).
# Extra arguments go to ctest, e.g. scripts/test.sh -L unit
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
coopnav_install_deps
coopnav_build
coopnav_ensure_multicast
cd "$COOPNAV_BUILD_DIR"
ctest --output-on-failure --timeout 900 -j"$(nproc)" "$@"
