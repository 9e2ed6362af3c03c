#!/usr/bin/env bash
# Golden diagnostics tests and hostile inputs for `thermnet lint`.
#
#   run.sh THERMNET [--update] [--golden | --hostile]
#
# Golden cases: every NAME.tnet in this folder is linted from inside the folder (so paths in the
# output are relative) and its stdout, followed by a line `exit: N`, must equal NAME.expected.
# NAME.json.expected / NAME.sarif.expected, where present, hold the output of --format json|sarif.
# Files that cases include live in include/; data files (.csv) sit next to the cases.
# --update rewrites the expected files from the current output (review the diff before committing).
#
# Hostile inputs are generated into a temporary folder: each must end in a clear message and the
# right exit status in bounded time, never in a signal. BIG_MB sets the size of the large-file
# test (default 20; 100 MB takes about 20 s on a 2-core machine).
set -u
# The factor on the hostile runs' time limits (slow builds: scripts/asan-suite sets 10).
timeout_scale=${THERMNET_TEST_TIMEOUT_SCALE:-1}
[[ $timeout_scale =~ ^[1-9][0-9]{0,3}$ ]] || {
  echo "THERMNET_TEST_TIMEOUT_SCALE='$timeout_scale': expected a whole number from 1 to 9999" >&2
  exit 2
}

if [ $# -lt 1 ]; then
  echo "usage: $0 THERMNET [--update] [--golden | --hostile]" >&2
  exit 2
fi
bin=$(realpath "$1")
shift
update=0 do_golden=1 do_hostile=1
for arg in "$@"; do
  case "$arg" in
  --update) update=1 ;;
  --golden) do_hostile=0 ;;
  --hostile) do_golden=0 ;;
  *)
    echo "unknown option $arg" >&2
    exit 2
    ;;
  esac
done
if [ ! -x "$bin" ]; then
  echo "not an executable: $bin" >&2
  exit 2
fi

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export NO_COLOR=1 LC_ALL=C.UTF-8
passed=0
failed=0

fail() {
  echo "FAIL: $1"
  failed=$((failed + 1))
}

# Runs `thermnet lint` with the given arguments; prints stdout and a final `exit: N` line.
lint_output() {
  local out status
  out=$(timeout 60 "$bin" lint "$@" 2>/dev/null)
  status=$?
  [ -n "$out" ] && printf '%s\n' "$out"
  printf 'exit: %s\n' "$status"
}

# Compares the output of one golden run with its expected file (or rewrites it with --update).
compare() {
  local label=$1 expected=$2 actual=$3
  if [ "$update" = 1 ]; then
    printf '%s' "$actual" >"$expected"
    echo "updated $expected"
    passed=$((passed + 1))
    return
  fi
  if [ ! -f "$expected" ]; then
    fail "$label: missing $expected (run with --update to create it)"
    return
  fi
  local diff_out
  if diff_out=$(diff -u --label "$expected" --label "actual output" "$expected" - <<<"${actual%$'\n'}"); then
    passed=$((passed + 1))
  else
    fail "$label"
    printf '%s\n' "$diff_out"
  fi
}

run_golden() {
  cd "$here" || exit 2
  local model name
  for model in *.tnet; do
    name=${model%.tnet}
    compare "$name" "$name.expected" "$(lint_output "$model")"$'\n'
    local fmt
    for fmt in json sarif; do
      # SARIF names the tool version; it is replaced so releases do not break the test.
      if [ -f "$name.$fmt.expected" ]; then
        compare "$name ($fmt)" "$name.$fmt.expected" \
          "$(lint_output "$model" --format "$fmt" |
            sed -E 's/^(          "version": )"[^"]*"/\1"VERSION"/')"$'\n'
      fi
    done
  done
}

# One hostile case: runs lint on FILE with a time limit and checks the exit status (one of the
# allowed ones, never a signal or a timeout) and that stdout contains PATTERN.
hostile() {
  local label=$1 limit=$2 allowed=$3 pattern=$4
  shift 4
  hostile_run "$label" "$limit" 0 "$allowed" "$pattern" lint "$@"
}

# The same for any command (ARGS start with the subcommand), its address space limited to MEM_MB
# megabytes (0: no limit; HOSTILE_NO_ULIMIT=1 drops every limit, for sanitizer builds, which
# reserve terabytes of address space).
hostile_run() {
  local label=$1 limit=$2 mem_mb=$3 allowed=$4 pattern=$5
  shift 5
  local start end out status
  [ "${HOSTILE_NO_ULIMIT:-0}" = 1 ] && mem_mb=0
  # THERMNET_TEST_TIMEOUT_SCALE stretches the limit for slow builds (sanitizers).
  limit=$((limit * timeout_scale))
  start=$(date +%s.%N)
  out=$(
    [ "$mem_mb" -gt 0 ] && ulimit -v $((mem_mb * 1024))
    timeout "$limit" "$bin" "$@" 2>&1
  )
  status=$?
  end=$(date +%s.%N)
  local secs
  secs=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')
  if [ "$status" = 124 ]; then
    fail "$label: no answer within ${limit} s"
  elif [ "$status" -ge 128 ]; then
    fail "$label: killed by signal $((status - 128))"
    printf '%s\n' "$out" | tail -5
  elif ! [[ " $allowed " == *" $status "* ]]; then
    fail "$label: exit status $status, expected one of: $allowed"
    printf '%s\n' "$out" | head -10
  elif [ -n "$pattern" ] && ! grep -qE -- "$pattern" <<<"$out"; then
    fail "$label: output lacks /$pattern/"
    printf '%s\n' "$out" | head -10
  else
    echo "ok: $label (${secs} s)"
    passed=$((passed + 1))
  fi
}

run_hostile() {
  hostile_dir=$(mktemp -d)
  trap 'rm -rf "$hostile_dir"' EXIT
  local dir=$hostile_dir
  cd "$dir" || exit 2

  python3 -c "print('const x = ' + '(' * 20000 + '1' + ')' * 20000)" >parens.tnet
  hostile "20,000 nested parentheses" 20 1 "nesting-too-deep" parens.tnet

  python3 -c "print('boundary b T = 20\nnode n C = ' + '[' * 20000)" >brackets.tnet
  hostile "20,000 open square brackets" 20 1 "nesting-too-deep" brackets.tnet

  python3 -c "print('case c ' + '{' * 20000)" >braces.tnet
  hostile "20,000 open braces" 20 1 "nesting-too-deep" braces.tnet

  python3 -c "print('const x = ' + '-' * 1000000 + '1\nconst y = x')" >minus.tnet
  hostile "1,000,000 unary minus signs" 20 0 "unused-const" minus.tnet

  python3 -c "print('const x = 2' + '^2' * 200000)" >powers.tnet
  hostile "200,000 chained powers" 20 1 "invalid-value" powers.tnet

  python3 -c "print('const x = 1' + ' + 1' * 1000000 + '\nconst y = x')" >sum.tnet
  hostile "a sum of 1,000,000 terms" 20 0 "unused-const" sum.tnet

  python3 -c "print('const x = max(' + ', '.join(['1'] * 200000) + ')\nconst y = x')" >args.tnet
  hostile "a call with 200,000 arguments" 20 0 "unused-const" args.tnet

  python3 -c "print('const x = ' + 'sqrt(' * 64 + '1' + ')' * 64 + '\nconst y = x')" >calls.tnet
  hostile "64 nested calls" 20 0 "unused-const" calls.tnet

  local mb=${BIG_MB:-20}
  python3 - "$mb" >big.tnet <<'EOF'
import sys
limit = int(sys.argv[1]) * 1000 * 1000
out = sys.stdout
out.write('boundary amb T = 20\n')
size, i = 0, 0
while size < limit:
    s = 'node n%d C = 450 [J/K] T0 = 20 "node %d"\nconductance g%d n%d amb G = 0.5 [W/K]\n' % (i, i, i, i)
    out.write(s)
    size += len(s)
    i += 1
EOF
  hostile "a ${mb} MB model of valid statements" 60 "0 1" "" big.tnet

  python3 -c "print('node n C = 1 ' + 'x' * 50000000)" >longline.tnet
  hostile "a 50 MB line" 30 1 "syntax" longline.tnet

  head -c 10000000 /dev/urandom >random.tnet
  hostile "10 MB of random bytes" 20 1 "invalid-encoding" random.tnet

  python3 -c "
import random
random.seed(7)
print('\n'.join(''.join(random.choice('abc =+-*/()[]{}#\"12.;:\\\\,') for _ in range(40)) for _ in range(100000)))" >ascii.tnet
  hostile "100,000 lines of random punctuation" 20 1 "too-many-errors" ascii.tnet

  # A table file named 20,000 times is read once (issue 31, item 6): lint stays fast and small.
  printf 'time,P\n0,1\n3600,2\n' >small.csv
  python3 -c "
print('boundary b T = 20')
for i in range(20000):
    print('node n%d C = 1\nconductance g%d n%d b G = 1\nheater h%d n%d P = table(\"small.csv\", \"P\")' % ((i,) * 5))
print('case c { duration = 3600 }')" >tables.tnet
  hostile "a table file named 20,000 times" 30 0 "" tables.tnet

  python3 -c "print('\n'.join('node n%d C = = 1' % i for i in range(50000)))" >errors.tnet
  hostile "50,000 syntax errors" 20 1 "too many errors \(200\); stopping" errors.tnet

  python3 -c "print('\n'.join('conductance g%d a%d b%d G = x%d' % (i, i, i, i) for i in range(50000)))" >names.tnet
  hostile "50,000 unknown names" 20 1 "too many errors \(200\); stopping" names.tnet

  printf 'boundary b T = 20\nnode n C = 1\ncase c {\n  duration = 1\n  n.T0 = step(0: 1,' >unterminated.tnet
  hostile "an unterminated block at end of file" 20 1 "unterminated-block" unterminated.tnet

  printf 'boundary b T = 20\nnode n C = 1 "no end' >unterminated_string.tnet
  hostile "an unterminated string at end of file" 20 1 "unterminated string" unterminated_string.tnet

  printf 'node n C = 1\0\nboundary b T = 20\n' >nul.tnet
  hostile "a NUL byte" 20 1 "NUL byte" nul.tnet

  printf 'node n C = 1 "caf\xe9"\n' >latin1.tnet
  hostile "invalid UTF-8" 20 1 "not valid UTF-8" latin1.tnet

  printf '\xef\xbb\xbfnode n C = 1\n' >bom.tnet
  hostile "a UTF-8 byte order mark" 20 "0 1" "" bom.tnet

  : >empty.tnet
  hostile "an empty file" 20 0 "" empty.tnet

  mkdir -p adir
  hostile "a directory given as model" 20 2 "is a directory" adir

  hostile "a missing file" 20 2 "cannot read file" no_such_model.tnet

  printf 'include "self.tnet"\n' >self.tnet
  hostile "a file including itself" 20 1 "include-cycle" self.tnet

  for i in $(seq 0 99); do printf 'include "inc%d.tnet"\nnode n%d C = 1\n' $((i + 1)) "$i" >"inc$i.tnet"; done
  printf 'node n100 C = 1\n' >inc100.tnet
  hostile "includes nested 100 deep" 20 1 "include-too-deep" inc0.tnet

  printf 'boundary b T = 20\nnode n C = 1\nconductance g n b G = 1\ncase c {\n duration = 1\n data "%s"\n}\n' "/dev/urandom" >device.tnet
  hostile "a data file that never ends is not read forever" 30 2 "data-unreadable" device.tnet

  # shellcheck source=hostile_generated.sh
  . "$here/hostile_generated.sh"
  cd "$here" || exit 2
}

[ "$do_golden" = 1 ] && run_golden
[ "$do_hostile" = 1 ] && [ "$update" = 0 ] && run_hostile
echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
