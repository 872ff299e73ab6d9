#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/fuzz_*.cpp, -DLOCUS_FUZZ=ON with clang++) into build-fuzz and
# runs each for SECONDS (default 60), seeded from fuzz/corpus/<target>/. Fails on any crash,
# sanitizer report, leak or timeout. The committed corpus is never written: each target works
# in a temporary copy; a failing input is kept under <build dir>/fuzz-artifacts/.
#   scripts/fuzz.sh [SECONDS] [TARGET...]     e.g. scripts/fuzz.sh 10 fuzz_survey_format
#   LOCUS_FUZZ_BUILD_DIR  build directory (default build-fuzz)
#   LOCUS_FUZZ_CXX        compiler (default clang++; needs libFuzzer: Debian clang + libclang-rt-14-dev)
#   LOCUS_JOBS            parallel compile jobs (default 2)
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
shift $(($# > 0 ? 1 : 0))
BUILD_DIR="${LOCUS_FUZZ_BUILD_DIR:-build-fuzz}"
JOBS="${LOCUS_JOBS:-2}"
cxx="${LOCUS_FUZZ_CXX:-clang++}"
# Debian's clang takes libFuzzer and the sanitizer runtimes from a recommended package.
[ -n "${LOCUS_FUZZ_CXX:-}" ] || bash scripts/install_packages.sh clang libclang-rt-14-dev cmake make g++
probe="$(mktemp -d)"
echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' >"$probe/p.cpp"
if ! "$cxx" -fsanitize=fuzzer,address,undefined "$probe/p.cpp" -o "$probe/p" 2>"$probe/err"; then
  cat "$probe/err" >&2
  echo "fuzz: $cxx cannot build a libFuzzer target; on Debian 12: apt-get install clang libclang-rt-14-dev" >&2
  rm -rf "$probe"
  exit 2
fi
rm -rf "$probe"

# -O1 -gline-tables-only, the flags OSS-Fuzz builds with: crash reports keep file and line at a
# fraction of -O2 -g's build time.
source scripts/phase.sh
phase "fuzz configure" bash scripts/configure.sh "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" -DLOCUS_FUZZ=ON -DLOCUS_BENCHMARKS=OFF \
      -DCMAKE_CXX_COMPILER="$cxx" >/dev/null
phase "fuzz build" cmake --build "$BUILD_DIR" -j"$JOBS" --target locus_fuzz

targets=("$@")
if ((${#targets[@]} == 0)); then
  for dir in fuzz/corpus/*/; do targets+=("$(basename "$dir")"); done
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
artifacts="$BUILD_DIR/fuzz-artifacts"
mkdir -p "$artifacts"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=${LOCUS_DETECT_LEAKS:-1}:print_stacktrace=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"

# One target's run: its report to $work/$t.report, its status to $work/$t.rc.
run_target() {
  local t=$1 bin="$BUILD_DIR/bin/$1" dict=() rc=0
  mkdir -p "$work/$t"
  [ -d "fuzz/corpus/$t" ] && cp -R "fuzz/corpus/$t/." "$work/$t/"
  [ -f "fuzz/dict/$t.dict" ] && dict=(-dict="fuzz/dict/$t.dict")
  "$bin" "$work/$t" "${dict[@]}" -max_total_time="$seconds" -timeout=25 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$artifacts/$t-" >"$work/$t.log" 2>&1 || rc=$?
  if ((rc == 0)); then
    grep -E '^(stat::number_of_executed_units|stat::average_exec_per_sec|stat::new_units_added)' "$work/$t.log" |
      sed "s/^/fuzz: $t: /" || true
  else
    tail -n 60 "$work/$t.log"
    echo "fuzz: $t FAILED (input under $artifacts/)"
  fi >"$work/$t.report"
  echo "$rc" >"$work/$t.rc"
}

# A fuzzer is one process on one core: LOCUS_FUZZ_JOBS of them (default LOCUS_JOBS) run at once.
fuzz_jobs="${LOCUS_FUZZ_JOBS:-$JOBS}"
for t in "${targets[@]}"; do
  [ -x "$BUILD_DIR/bin/$t" ] || { echo "fuzz: no target $t ($BUILD_DIR/bin/$t)" >&2; exit 2; }
done
run_all() {
  for t in "${targets[@]}"; do
    while (($(jobs -rp | wc -l) >= fuzz_jobs)); do wait -n || true; done
    echo "fuzz: $t for ${seconds} s" >&2
    run_target "$t" &
  done
  wait
}
phase "fuzz runs ($fuzz_jobs at once)" run_all
failed=()
for t in "${targets[@]}"; do
  cat "$work/$t.report" >&2
  [ "$(cat "$work/$t.rc" 2>/dev/null)" = 0 ] || failed+=("$t")
done
if ((${#failed[@]})); then
  echo "fuzz: failures in ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: ${#targets[@]} targets ran ${seconds} s each without a failure" >&2
