# The harness shared by the shell tests; sourced, never run:
#   . "$(dirname "$0")/../lib/harness.sh" "$@"
# It takes PATH/TO/thermnet as $1 ($TN), sets $HERE to the test's folder, makes a scratch folder
# $WORK (removed on exit) and enters it, turns progress bars off, and defines the checks below;
# a test ends with `finish`, which prints the tally and fails when any check failed.
set -u

TN=${1:?usage: $(basename "$0") PATH/TO/thermnet}
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/thermnet_$(basename "$HERE")_$(basename "$0" .sh).XXXXXX")
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 2
export CI=1 # no progress bars

pass=0
fail=0
# ok DESCRIPTION / bad DESCRIPTION [DETAIL]: record a passed / failed check.
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; [ $# -gt 1 ] && printf '       %s\n' "$2"; }
# check DESCRIPTION COMMAND...: passes when COMMAND succeeds; shows the last run's stderr if not.
check() {
  local what=$1
  shift
  if "$@"; then ok "$what"; else bad "$what" "$(head -c 800 err.txt 2>/dev/null)"; fi
}
# run ARGS...: runs thermnet; stdout in out.txt, stderr in err.txt, exit status in $rc.
run() { "$TN" "$@" >out.txt 2>err.txt; rc=$?; }
# finish: prints the tally; the status is failure when any check failed.
finish() {
  echo "$pass passed, $fail failed"
  [ "$fail" -eq 0 ]
}
