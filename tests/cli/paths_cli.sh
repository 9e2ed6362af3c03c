#!/usr/bin/env bash
# Files a model names stay within its reach: include/data/table paths outside the model's folder
# tree are refused unless --allow-outside-paths (or THERMNET_ALLOW_OUTSIDE_PATHS=1); FIFOs,
# devices, /proc and /sys are refused always, at once (never waited on); a message quotes at most
# a short excerpt of a referenced file, with control characters and invalid UTF-8 escaped
# (<U+001B>, <A5>) in text, JSON and SARIF. Usage: paths_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# tlint ARGS...: `thermnet lint` bounded by 60 s (a FIFO must never block it).
tlint() { timeout 60 "$TN" lint "$@" >out.txt 2>err.txt; rc=$?; }
export THERMNET_TEST_SECRET=s3cr3t-value
mkdir -p model outside
cd model || exit 2
base='boundary a T = 0
node n C = 1
conductance g n a G = 1'

printf '%s\ninclude "/proc/self/environ"\n' "$base" >environ.tnet
tlint environ.tnet
check "include /proc/self/environ: refused (outside the folder), the environment never printed" \
  eval 'test "$rc" -ne 0 && grep -q "outside the model.s folder" out.txt && ! grep -q s3cr3t out.txt err.txt'
tlint --allow-outside-paths environ.tnet
check "  ... and with --allow-outside-paths: refused as a kernel interface" \
  eval 'test "$rc" -ne 0 && grep -q "kernel interface" out.txt && ! grep -q s3cr3t out.txt err.txt'

head -c 300 /dev/zero | tr '\0' 'S' >../outside/secret.csv
printf '\n' >>../outside/secret.csv
printf '%s\ncase c { duration = 1; data "../outside/secret.csv" }\n' "$base" >outside.tnet
tlint outside.tnet
check "data outside the folder: data-unreadable naming the flag, nothing of the file shown" \
  eval 'test "$rc" -eq 2 && grep -q "data-unreadable" out.txt && grep -q -- "--allow-outside-paths" out.txt &&
        ! grep -q SSSS out.txt'
tlint --allow-outside-paths outside.tnet
check "  ... allowed by the flag: a data-format error quoting at most 40 characters of it" \
  eval 'test "$rc" -eq 1 && grep -q "found .S\{40\}\.\.\.." out.txt && ! grep -q "S\{41\}" out.txt'
THERMNET_ALLOW_OUTSIDE_PATHS=1 timeout 60 "$TN" lint outside.tnet >out.txt 2>err.txt
rc=$?
check "  ... or by THERMNET_ALLOW_OUTSIDE_PATHS=1" eval 'test "$rc" -eq 1 && grep -q "data-format" out.txt'
ln -s ../outside/secret.csv link.csv
sed 's#"../outside/secret.csv"#"link.csv"#' outside.tnet >link.tnet
tlint link.tnet
check "a symlink inside the folder to a file outside it is refused too" \
  eval 'test "$rc" -eq 2 && grep -q "outside the model.s folder" out.txt'
mkdir -p sub
printf '%s\ninclude "sub/part.tnet"\n' "$base" >inside.tnet
printf 'const k = 1\n' >sub/part.tnet
tlint inside.tnet
check "an include in a subfolder is fine (exit 0)" test "$rc" -eq 0

mkfifo pipe.tnet pipe.csv
printf '%s\ninclude "pipe.tnet"\n' "$base" >fifo_inc.tnet
tlint fifo_inc.tnet
check "an include naming a FIFO: refused at once (exit 2, FIFO)" \
  eval 'test "$rc" -eq 2 && grep -q "FIFO" out.txt'
printf '%s\ncase c { duration = 1; data "pipe.csv" }\n' "$base" >fifo_data.tnet
tlint fifo_data.tnet
check "data naming a FIFO: refused at once" eval 'test "$rc" -eq 2 && grep -q "FIFO" out.txt'
tlint pipe.tnet
check "a FIFO given as the model: refused at once" eval 'test "$rc" -eq 2 && grep -q "FIFO" out.txt'
timeout 60 "$TN" simulate fifo_data.tnet >out.txt 2>err.txt
rc=$?
check "simulate too (exit 2, never blocks)" eval 'test "$rc" -eq 2 && grep -q "FIFO" err.txt'
printf '%s\ninclude "/dev/stdin"\n' "$base" >stdin.tnet
tlint --allow-outside-paths stdin.tnet </dev/null
check "include /dev/stdin with --allow-outside-paths: refused (not a regular file)" \
  eval 'test "$rc" -eq 2 && grep -q "not a regular file" out.txt'

# Escaping: a referenced file whose header holds an escape sequence and an invalid byte.
printf '\033]0;pwned\007tim\245e,n\n0,1\n' >evil.csv
printf '%s\ncase c { duration = 1; data "evil.csv" }\n' "$base" >evil.tnet
tlint evil.tnet
check "text: control characters and invalid UTF-8 are shown as <U+001B> and <A5>, no raw bytes" \
  eval 'grep -q "found .<U+001B>\]0;pwned<U+0007>tim<A5>e." out.txt && ! grep -q $'"'"'\033'"'"' out.txt'
tlint --format json evil.tnet
check "json: valid JSON with the same escaped text" \
  eval 'python3 -c "import json,sys; d=json.load(open(\"out.txt\")); sys.exit(0 if \"<U+001B>]0;pwned<U+0007>tim<A5>e\" in json.dumps(d) else 1)"'
tlint --format sarif evil.tnet
check "sarif: valid JSON with the same escaped text" \
  eval 'python3 -c "import json,sys; d=json.load(open(\"out.txt\")); sys.exit(0 if \"<U+001B>]0;pwned<U+0007>tim<A5>e\" in json.dumps(d) else 1)"'
ln -s evil.csv "$(printf 'bad\033[2Jname.csv')"
printf '%s\ncase c { duration = 1; data "%s" }\n' "$base" "$(printf 'bad\033[2Jname.csv')" >evilname.tnet
timeout 60 "$TN" simulate evilname.tnet >out.txt 2>err.txt
check "a file name with an escape sequence is shown escaped in messages" \
  eval 'grep -q "bad<U+001B>\[2Jname.csv" err.txt && ! grep -q $'"'"'\033'"'"' err.txt'

finish
