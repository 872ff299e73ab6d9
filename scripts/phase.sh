# Sourced by the build and test scripts: `phase NAME CMD [ARG…]` runs CMD and prints how long it
# took, on stderr, as `phase: NAME  M min SS s` (and `(failed: STATUS)` when it failed), so every
# log shows where the time went and the next slow step is visible. With LOCUS_PHASE_LOG set, the
# line is also appended to that file: .ci/run prints them all again at its end. Returns CMD's
# status; timings are reported, never checked.
phase() {
  local name=$1 start=$SECONDS rc=0
  shift
  "$@" || rc=$?
  local took=$((SECONDS - start)) failed=""
  ((rc == 0)) || failed=" (failed: $rc)"
  local line
  line=$(printf 'phase: %-34s %3d min %02d s%s' "$name" $((took / 60)) $((took % 60)) "$failed")
  echo "$line" >&2
  [ -z "${LOCUS_PHASE_LOG:-}" ] || echo "$line" >>"$LOCUS_PHASE_LOG"
  return $rc
}
