#!/usr/bin/env bash
# Builds Locus with AddressSanitizer + UndefinedBehaviorSanitizer (-DLOCUS_SANITIZE=ON) into its
# own build directory and runs the whole ctest suite there; any sanitizer report fails the run.
# The integration tests spawn the sanitized locus-server and locus of the same build.
#   LOCUS_ASAN_BUILD_DIR  build directory (default build-asan)
#   LOCUS_ASAN_CXX        compiler (default clang++: the same sanitizers, and it compiles this
#                         build in two thirds of g++'s time; Debian: clang libclang-rt-14-dev)
#   LOCUS_JOBS            parallel compile jobs (default 2)
#   LOCUS_TEST_JOBS       tests run at once (default twice LOCUS_JOBS, as in test.sh)
#   LOCUS_DETECT_LEAKS    0 turns LeakSanitizer off (it needs ptrace-like access some containers deny)
# Extra arguments go to ctest (e.g. -R FuzzRegressions, -L unit).
set -euo pipefail
cd "$(dirname "$0")/.."

BUILD_DIR="${LOCUS_ASAN_BUILD_DIR:-build-asan}"
JOBS="${LOCUS_JOBS:-2}"
cxx="${LOCUS_ASAN_CXX:-clang++}"
# Debian's clang takes the sanitizer runtimes from a recommended package.
[ -n "${LOCUS_ASAN_CXX:-}" ] || bash scripts/install_packages.sh clang libclang-rt-14-dev

# -O1 -g1, as the ASan documentation advises: reports keep file and line, and the build takes
# a fraction of -O2 -g's time (it is most of CI's time). No benchmarks: no test runs them.
source scripts/phase.sh
phase "sanitized configure" bash scripts/configure.sh "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DLOCUS_SANITIZE=ON -DLOCUS_BENCHMARKS=OFF \
      -DCMAKE_CXX_COMPILER="$cxx" >/dev/null

# Fatal on the first report (also when ctest runs a test binary to list its tests). UBSan is
# also made fatal at compile time (-fno-sanitize-recover=undefined).
asan="halt_on_error=1:detect_leaks=${LOCUS_DETECT_LEAKS:-1}:print_stacktrace=1:strict_string_checks=1"
asan+=":detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1"
ubsan="halt_on_error=1:print_stacktrace=1"
export ASAN_OPTIONS="$asan${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="$ubsan${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
phase "sanitized build" cmake --build "$BUILD_DIR" -j"$JOBS"

# During the tests every report also goes to a file: a server the tests stop with SIGTERM, or a
# CLI run whose exit status a test does not look at, could otherwise report (a leak at exit, an
# error in its last request) without failing anything.
reports="$(cd "$BUILD_DIR" && pwd)/sanitizer-reports"
rm -rf "$reports"
mkdir -p "$reports"
export ASAN_OPTIONS="$ASAN_OPTIONS:log_path=$reports/asan"
export UBSAN_OPTIONS="$UBSAN_OPTIONS:log_path=$reports/ubsan"

status=0
phase "sanitized tests" ctest --test-dir "$BUILD_DIR" --output-on-failure -j"${LOCUS_TEST_JOBS:-$((2 * JOBS))}" "$@" ||
  status=$?
if compgen -G "$reports/*" >/dev/null; then
  for f in "$reports"/*; do
    echo "=== sanitizer report $f" >&2
    cat "$f" >&2
  done
  echo "test_sanitized: sanitizer reports above (kept in $reports)" >&2
  exit 1
fi
exit "$status"
