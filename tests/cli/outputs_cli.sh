#!/usr/bin/env bash
# Outputs never destroy anything but the regular file they name: symlinks are written through and
# stay symlinks, devices and FIFOs are written directly (never replaced), an output that is an
# input of the run or another output is a usage error naming both, a full disk is an error (also
# on standard output), and a signal leaves no temporary file. Usage: outputs_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# no_temp_files: no temporary output file (.NAME.tmp.XXXXXX) anywhere under the scratch folder.
no_temp_files() { test -z "$(find . -name '.*.tmp.*')"; }

cat >m.tnet <<'EOF'
model m
include "parts.tnet"
conductance g n amb G = 1
heater h n P = table("power.csv", "P")
case c { duration = 100; output = 10; data "meas.csv" }
EOF
cat >parts.tnet <<'EOF'
boundary amb T = 20
node n C = 1000 T0 = 50
EOF
printf 'time,P\n0,5\n100,5\n' >power.csv
printf 'time,n\n0,50\n50,40\n100,35\n' >meas.csv
cp m.tnet m.orig
cp parts.tnet parts.orig
cp power.csv power.orig
cp meas.csv meas.orig
inputs_unchanged() {
  cmp -s m.tnet m.orig && cmp -s parts.tnet parts.orig && cmp -s power.csv power.orig &&
    cmp -s meas.csv meas.orig
}
run simulate m.tnet -o ref.csv
check "the model simulates (exit 0)" test "$rc" -eq 0 -a -s ref.csv

# ----------------------------------------------------------------------------- symlinks
echo old >real.csv
ln -s real.csv link.csv
run simulate m.tnet -o link.csv
check "-o through a symlink: exit 0, the symlink stays a symlink to the same file" \
  eval 'test "$rc" -eq 0 && test -L link.csv && test "$(readlink link.csv)" = real.csv'
check "  ... and the file it points to holds the CSV" cmp -s real.csv ref.csv
mkdir -p sub
ln -s sub/new.csv dangling.csv
run simulate m.tnet -o dangling.csv
check "-o onto a dangling symlink creates the file it names, the symlink stays" \
  eval 'test "$rc" -eq 0 && test -L dangling.csv && cmp -s sub/new.csv ref.csv'
ln -s /dev/null null_link
run simulate m.tnet -o null_link --plot null_link
check "-o and --plot onto a symlink to /dev/null: exit 0, still a symlink to a character device" \
  eval 'test "$rc" -eq 0 && test -L null_link && test -c null_link && test -c /dev/null'
check "  ... nothing left behind" no_temp_files

# ----------------------------------------------------------------------------- devices, FIFOs
if [ "$(id -u)" -eq 0 ]; then
  # As root, a device node of our own (the same device as /dev/null) stands in for /dev/null.
  mknod nul c 1 3
  run simulate m.tnet -o nul
  check "-o onto a character device (as root): exit 0, still a character device" \
    eval 'test "$rc" -eq 0 && test -c nul && test ! -s nul'
  mknod blk b 7 200
  run simulate m.tnet -o blk
  check "-o onto a block device: exit 2 saying what it is, the device left alone" \
    eval 'test "$rc" -eq 2 && grep -q "block device" err.txt && test -b blk'
else
  ok "(not root: the device-node checks use the symlink to /dev/null above)"
fi
mkfifo fifo
timeout 60 cat fifo >from_fifo.csv & # bounded, should thermnet never open the FIFO
reader=$!
timeout 60 "$TN" simulate m.tnet -o fifo >out.txt 2>err.txt
rc=$?
wait "$reader"
check "-o onto a FIFO with a reader: exit 0 within the time limit, the CSV arrives" \
  eval 'test "$rc" -eq 0 && cmp -s from_fifo.csv ref.csv'
check "  ... and the FIFO is still a FIFO" test -p fifo

# ----------------------------------------------------------------------------- inputs as outputs
run simulate m.tnet -o m.tnet
check "-o onto the model: exit 2 naming the model" \
  eval "test \"\$rc\" -eq 2 && grep -q \"\\-o 'm.tnet' would overwrite the model 'm.tnet'\" err.txt"
ln m.tnet hardlink.tnet
run simulate m.tnet -o hardlink.tnet
check "-o onto a hard link of the model: exit 2" \
  eval 'test "$rc" -eq 2 && grep -q "would overwrite the model" err.txt'
ln -s parts.tnet parts_link.tnet
run simulate m.tnet --plot parts_link.tnet
check "--plot onto a symlink to an included file: exit 2 naming it" \
  eval 'test "$rc" -eq 2 && grep -q "would overwrite the included file .*parts.tnet" err.txt'
run simulate m.tnet -o power.csv
check "-o onto a table file: exit 2 naming it" \
  eval 'test "$rc" -eq 2 && grep -q "would overwrite the table file .*power.csv" err.txt'
run simulate m.tnet -o meas.csv
check "-o onto the measured data: exit 2 naming it" \
  eval 'test "$rc" -eq 2 && grep -q "would overwrite the data file .*meas.csv" err.txt'
run sensitivity m.tnet --json meas.csv
check "sensitivity --json onto the data: exit 2" test "$rc" -eq 2
run diagnose m.tnet --write m.tnet
check "diagnose --write onto the model: exit 2 before diagnosing" \
  eval 'test "$rc" -eq 2 && grep -q "would overwrite the model" err.txt'
printf 'case,start,end\nc,0,10\nnope,20,30\n' >events.csv
run diagnose m.tnet --events events.csv
check "diagnose --events naming an unknown case: exit 1 at its file:row:column" \
  eval 'test "$rc" -eq 1 && grep -q "events.csv:3:1: the model has no case .nope. (its cases: c)" err.txt'
run diagnose m.tnet --events no_such_events.csv
check "diagnose --events on a missing file: exit 2 naming it" \
  eval 'test "$rc" -eq 2 && grep -q "no_such_events.csv" err.txt'
run diagnose m.tnet --events events.csv --json events.csv
check "diagnose --json onto the events file: exit 2 naming it" \
  eval 'test "$rc" -eq 2 && grep -q "would overwrite the events file" err.txt'
run simulate m.tnet -o x.csv --plot x.csv
check "-o x.csv --plot x.csv: exit 2 naming both" \
  eval "test \"\$rc\" -eq 2 && grep -q \"\\-o 'x.csv' and --plot 'x.csv' are the same file\" err.txt"
check "  ... and nothing written" test ! -e x.csv
printf 'time,B,C,D\n0,1,2,3\n1,2,3,4\n' >sensors.csv
cp sensors.csv sensors.orig
run invert sensors.csv --sensors B,C,D --window 1 -o sensors.csv
check "invert -o onto its data: exit 2 naming it, the data untouched" \
  eval 'test "$rc" -eq 2 && grep -q "would overwrite the data file .sensors.csv." err.txt && cmp -s sensors.csv sensors.orig'
check "no input was changed by any of these runs" inputs_unchanged
mkdir -p adir
run simulate m.tnet -o adir
check "-o onto a directory: exit 2" eval 'test "$rc" -eq 2 && grep -q "is a directory" err.txt'

# ----------------------------------------------------------------------------- full disks
"$TN" simulate m.tnet >/dev/full 2>err.txt
rc=$?
check "simulate > /dev/full: exit 2 with the reason" \
  eval 'test "$rc" -eq 2 && grep -q "cannot write to standard output: No space left on device" err.txt'
"$TN" lint m.tnet --format json >/dev/full 2>err.txt
rc=$?
check "lint --format json > /dev/full: non-zero with a message" \
  eval 'test "$rc" -ne 0 && grep -q "No space left on device" err.txt'
"$TN" kinds >/dev/full 2>err.txt
rc=$?
check "kinds > /dev/full: non-zero with a message" \
  eval 'test "$rc" -ne 0 && grep -q "No space left on device" err.txt'
run simulate m.tnet -o /dev/full
check "-o /dev/full: exit 2 with the reason, /dev/full still a device" \
  eval 'test "$rc" -eq 2 && grep -q "No space left on device" err.txt && test -c /dev/full'

# ----------------------------------------------------------------------------- signals
# A long run streams its CSV into a temporary file; SIGTERM must remove it and leave the target.
cat >long.tnet <<'EOF'
boundary amb T = 20
node n C = 1000 T0 = 50
conductance g n amb G = 1
heater h n P = pwl(0: 0, 1e6: 100, 2e6: 0)
case c { duration = 1e7; output = 1 }
EOF
echo keep >long.csv
"$TN" simulate long.tnet -o long.csv >/dev/null 2>err.txt &
pid=$!
for _ in $(seq 1 300); do # until the temporary file exists (at most 30 s)
  [ -n "$(find . -name '.long.csv.tmp.*')" ] && break
  sleep 0.1
done
seen=$(find . -name '.long.csv.tmp.*' | wc -l)
kill -TERM "$pid"
wait "$pid"
rc=$?
check "SIGTERM during a streamed simulate: the temporary file existed, the process ends by SIGTERM" \
  test "$seen" -eq 1 -a "$rc" -eq 143
check "  ... the temporary file is removed and the old target kept" \
  eval 'no_temp_files && test "$(cat long.csv)" = keep'
# calibrate with many samples, terminated while it samples: no output and no temporary file.
cat >cal.tnet <<'EOF'
boundary amb T = 20
node n C = 1000 T0 = 50
param G = 1 [W/K] range 0.2 .. 5
conductance g n amb G = G
case c { duration = 100; output = 10; data "meas.csv" }
EOF
"$TN" calibrate cal.tnet --method mc --samples 100000000 --tolerance 100 -o cal_out.tnet \
  --json cal.json >/dev/null 2>err.txt &
pid=$!
sleep 2
kill -TERM "$pid"
wait "$pid"
rc=$?
check "SIGTERM during a long calibrate: ends by SIGTERM, no output and no temporary file" \
  eval 'test "$rc" -eq 143 && test ! -e cal_out.tnet && test ! -e cal.json && no_temp_files'

finish
