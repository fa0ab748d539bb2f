#!/usr/bin/env bash
# Builds aar-render, aar-analyze and the test suites that drive them with
# AddressSanitizer and UndefinedBehaviorSanitizer (gcc) into build-asan/, and
# runs the tests that call the executables: bad input, resume, reliability,
# exports and end-to-end runs, every dataset rendered by the sanitized
# renderer. A sanitizer report ends the process with exit code 86 and a
# report on stderr, which fails the test that ran it.
# Usage: bash scripts/sanitize.sh [CTEST_REGEX]   (about 20 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
pattern=${1:-'^(Render(BadInput|BadOutput|Resume|CommandLine|Concurrent)|Analyze(BadInput|Robustness|CommandLine)|Reliability|Export|Pipeline)'}
flags="-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=None "-DCMAKE_CXX_FLAGS=$flags" "-DCMAKE_C_FLAGS=$flags" \
  "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined" >/dev/null
cmake --build build-asan --target aar-render aar-analyze test_renderer test_pipeline --parallel "$(nproc)"
# Mesa's lavapipe keeps a few hundred bytes until exit, and the Vulkan loader
# unloads it before LeakSanitizer looks: preloaded, it stays mapped, so its
# frames have a name the suppressions (tests/sanitizers/lsan.supp) can match.
lvp=$(find /usr/lib -name libvulkan_lvp.so -print -quit)
export LD_PRELOAD=${lvp}
export ASAN_OPTIONS=exitcode=86:detect_leaks=1:strict_string_checks=1:check_initialization_order=1:verify_asan_link_order=0
export LSAN_OPTIONS=suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:exitcode=86
ctest --test-dir build-asan --output-on-failure --parallel "$(nproc)" --timeout 1800 -R "$pattern"
