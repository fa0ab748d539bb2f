#!/usr/bin/env bash
# One command for a fresh Debian 12 machine: install dependencies, build, run
# the whole test suite (CTest + GoogleTest, rendering on lavapipe), the Debian
# package installed and run from /tmp, the tests that drive both tools against
# ASan + UBSan builds of them, and every fuzzing harness for 20 s.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# One style (.clang-format): every C++ file as clang-format would write it.
git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run -Werror
bash scripts/build.sh -DAAR_WARNINGS_AS_ERRORS=ON
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 900
# The .deb installs and renders outside the source tree (about 1 minute).
bash scripts/test-package.sh
# aar-render and aar-analyze built with ASan + UBSan, and the 47 tests that run them (about 17 minutes).
bash scripts/sanitize.sh
# libFuzzer + ASan + UBSan on every parser, 20 s each, two at a time (about 6 minutes with the build).
bash scripts/fuzz.sh 20
