#!/usr/bin/env bash
# Builds rtabmap_core alone (plain CMake, no ROS) with a sanitizer and runs its unit tests.
#   sanitizers.sh asan <build-dir>   AddressSanitizer + UndefinedBehaviorSanitizer
#   sanitizers.sh tsan <build-dir>   ThreadSanitizer (the database writer thread, the optimiser's
#                                    and the memory's worker threads)
#   sanitizers.sh asan <build-dir> library   only the library (fuzz.sh links its targets to it)
# Any sanitizer report fails the test that produced it (halt_on_error / no recovery), so a
# green run means "no report". SAN_TESTS="db memory" limits the run to those test areas (ctest
# regex on the "core.<area>." prefix); JOBS sets the parallelism (default 2).
set -euo pipefail
kind="$1"; build="$2"; what="${3:-tests}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
jobs="${JOBS:-2}"
cxx="${SAN_CXX:-clang++}"
# -O1 keeps the tests fast enough; frame pointers and line tables give readable stacks.
common="-O1 -gline-tables-only -fno-omit-frame-pointer"
# The ASan objects also carry libFuzzer's coverage instrumentation (inert without libFuzzer),
# so build/asan and build/fuzz (fuzz.sh) compile the core once between them through ccache:
# same flags, same object paths relative to the build folder, build folder not hashed.
export CCACHE_NOHASHDIR=1 CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
case "$kind" in
  asan) san="address,undefined"; flags="$common -fsanitize=$san,fuzzer-no-link"
        export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
        export LSAN_OPTIONS="suppressions=$root/tools/build/sanitizers/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
        # Recoverable UBSan checks + halt_on_error: the first report still ends the test, but the
        # suppressions (third-party headers) are honoured, which -fno-sanitize-recover skips.
        export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$root/tools/build/sanitizers/ubsan.supp" ;;
  tsan) san="thread"; flags="$common -fsanitize=$san"
        export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$root/tools/build/sanitizers/tsan.supp${TSAN_OPTIONS:+:$TSAN_OPTIONS}" ;;
  *) echo "usage: $0 asan|tsan <build-dir>" >&2; exit 2 ;;
esac
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$root/rtabmap_core" -B "$build" -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=$san" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=$san" \
  -DRTABMAP_CORE_BUILD_BENCH=OFF -DRTABMAP_CORE_TEST_TIMEOUT=1800 "${launcher[@]}" >/dev/null
echo "$flags" > "$build/sanitizer-flags"
if [[ "$what" == library ]]; then
  cmake --build "$build" --target rtabmap_core -- -j"$jobs"
  exit 0
fi
filter=()
if [[ -n "${SAN_TESTS:-}" ]]; then
  # Only the test binaries asked for (and what they depend on): a sanitizer build is slow.
  targets=()
  for area in $SAN_TESTS; do targets+=(--target "test_$area"); done
  cmake --build "$build" "${targets[@]}" -- -j"$jobs"
  filter=(-R "^core\.($(tr ' ' '|' <<<"$SAN_TESTS"))\.")
else
  cmake --build "$build" -- -j"$jobs"
fi
# The sanitizers slow the tests 2-10x: a generous per-test timeout.
ctest --test-dir "$build" -j"$jobs" --output-on-failure --timeout 1800 "${filter[@]}"
