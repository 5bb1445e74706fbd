#!/usr/bin/env bash
# Installs what is missing (Debian 12), builds, and runs the whole test suite (unit, node, e2e).
# Extra arguments go to ctest, e.g. scripts/test.sh -L unit
# Without extra arguments (CI) the suite then runs again under sanitizers (docs/sanitizers.md):
# build-asan (ASan + UBSan: unit, node, e2e_lifecycle_test) and build-tsan (TSan: node,
# e2e_lifecycle_test), each building only what those tests run (~18 min together on 2 cores);
# any failed test or sanitizer report fails the run. COOPNAV_SANITIZERS=0 skips them.
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
coopnav_install_deps
coopnav_build
coopnav_ensure_multicast
(cd "$COOPNAV_BUILD_DIR" && ctest --output-on-failure --timeout 900 -j"$(nproc)" "$@")
# Without extra arguments (CI) the lint step also runs (scripts/lint.sh: clang-format check of
# every C++ file, clang-tidy on the set chosen there, ~3 min on 2 cores); any finding fails the
# run. COOPNAV_LINT=0 skips it.
if [ "$#" -eq 0 ] && [ "${COOPNAV_LINT:-1}" != 0 ]; then
  bash "$COOPNAV_ROOT/scripts/lint.sh"
fi
# Without extra arguments (CI) every libFuzzer target also runs briefly (build-fuzz, clang;
# test/fuzz/README.md); a finding fails the run. COOPNAV_FUZZ=0 skips it.
if [ "$#" -eq 0 ] && [ "${COOPNAV_FUZZ:-1}" != 0 ]; then
  bash "$COOPNAV_ROOT/scripts/fuzz.sh" --short
fi
if [ "$#" -eq 0 ] && [ "${COOPNAV_SANITIZERS:-1}" != 0 ]; then
  source "$COOPNAV_ROOT/scripts/sanitizers.sh"
  rc=0
  coopnav_sanitizer_pass asan address,undefined "coopnav_unit_tests coopnav_node_tests coopnav_ctl" \
    -L 'unit|node' || rc=1
  coopnav_sanitizer_pass tsan thread "coopnav_node_tests coopnav_ctl" -L 'node' || rc=1
  exit "$rc"
fi
