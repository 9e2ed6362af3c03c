#!/usr/bin/env bash
# diagnose --html and calibrate --html: the report page holds every finding, candidate, node,
# whiteness series and plot of the --json report of the same run (html_report_check.py), is
# self-contained (no script, nothing to fetch), escapes what the model and its files name (a data
# file and a param description with <script> and &), and is refused, before anything runs, where
# --json would be: a directory, an unwritable place, the model or its data, another output.
# The model and its data: html_report_fixture.sh.
# Usage: html_report_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

PY=/usr/bin/python3
CHECK="$HERE/html_report_check.py"
. "$HERE/html_report_fixture.sh"
test -s "$DATA1" || { bad "the fixture's data were written"; finish; exit 1; }
cp m.tnet m.orig

# ----------------------------------------------------------------------------- diagnose
run diagnose m.tnet --threads 2 --json d.json --html d.html
check "diagnose --json --html: exit 0, both written" eval 'test "$rc" -eq 0 -a -s d.json -a -s d.html'
check "  ... the diagnosis found the missing loss (a finding to show)" \
  "$PY" -c "import json,sys; sys.exit(0 if json.load(open('d.json'))['findings'] else 1)"
check "  ... every finding, candidate, node and plot of the JSON is on the page, self-contained" \
  eval '"$PY" "$CHECK" diagnose d.html d.json >check.txt 2>&1 || { cat check.txt >err.txt; false; }'
check "  ... the data file's name is escaped (no <script, the escaped text present)" \
  eval '! grep -qi "<script" d.html && grep -qF "d&lt;script&gt;alert(1)&amp;1.csv" d.html'
cat >same_statement.py <<'EOF'
import json, sys
f = json.load(open(sys.argv[1]))["findings"][0]
sys.exit(0 if f["statement"] and f["statement"] in open(sys.argv[2]).read() else 1)
EOF
"$TN" diagnose m.tnet --threads 2 --write ext.tnet >/dev/null 2>err.txt
check "  ... the finding's statement on the page is the one --write writes" \
  "$PY" same_statement.py d.json ext.tnet

run diagnose short.tnet --criterion prediction --threads 2 --json p.json --html p.html --top 1
check "diagnose --criterion prediction --html: exit 0" eval 'test "$rc" -eq 0 -a -s p.html'
check "  ... the innovations' whiteness series and plots of the JSON are on the page" \
  eval '"$PY" "$CHECK" diagnose p.html p.json >check.txt 2>&1 || { cat check.txt >err.txt; false; }'
check "  ... it names the innovations" grep -q "innovations" p.html
cat >step_plots.py <<'EOF'
import json, sys
n = len(json.load(open(sys.argv[1]))["findings"])
page = open(sys.argv[2]).read()
sys.exit(0 if n and all(f'data-plot="finding-{k}-step"' in page for k in range(1, n + 1)) else 1)
EOF
check "  ... every finding has the plot of its own step" "$PY" step_plots.py d.json d.html
check "  ... (under the likelihood criterion too)" "$PY" step_plots.py p.json p.html
cat >likelihood_rows.py <<'EOF'
import json, sys
findings = json.load(open(sys.argv[1]))["findings"]
page = open(sys.argv[2]).read()
# a finding of the likelihood criterion is tested by its likelihood ratio; the output-error
# criterion's held-out z and local gain are not computed for it and must not read as zeros
sys.exit(0 if findings and "likelihood ratio" in page
         and "held-out gain over its reference fit" not in page
         and "largest local gain" not in page else 1)
EOF
check "  ... a finding shows its likelihood-ratio test, not the output-error tests it never ran" \
  "$PY" likelihood_rows.py p.json p.html

# ----------------------------------------------------------------------------- calibrate
run calibrate m.tnet --method lm --json c.json --html c.html
check "calibrate --method lm --html: exit 0" eval 'test "$rc" -eq 0 -a -s c.html'
check "  ... no sampling fields that lm has not (seed, samples accepted, acceptance limit)" \
  eval '! grep -qE "acceptance limit|samples, [0-9]+ accepted|<th[^>]*>seed<" c.html'
check "  ... every param, case and plot of the JSON is on the page, self-contained" \
  eval '"$PY" "$CHECK" calibrate c.html c.json >check.txt 2>&1 || { cat check.txt >err.txt; false; }'
check "  ... the param's description is escaped" \
  eval '! grep -qi "<script" c.html && grep -qF "&lt;script&gt;alert(&apos;param&apos;)&lt;/script&gt; &amp; the a-b link" c.html'
cat >interval.py <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
v, se = r["params"]["Gab"], r["std_errors"]["Gab"]
sys.exit(0 if f"{v - 1.96 * se:.4g} … {v + 1.96 * se:.4g}" in open(sys.argv[2]).read() else 1)
EOF
check "  ... lm's interval: the fitted value ± 1.96 standard errors" "$PY" interval.py c.json c.html
run calibrate m.tnet --method mc --samples 64 --seed 3 --tolerance 30 --json mc.json --html mc.html
check "calibrate --method mc --html: exit 0, with the convergence plot" \
  eval 'test "$rc" -eq 0 && grep -q "data-plot=\"convergence\"" mc.html'
check "  ... every param, case and plot of the JSON is on the page" \
  eval '"$PY" "$CHECK" calibrate mc.html mc.json >check.txt 2>&1 || { cat check.txt >err.txt; false; }'
run calibrate m.tnet --criterion prediction --json cp.json --html cp.html
check "calibrate --criterion prediction --html: exit 0, the innovations' tests on the page" \
  eval 'test "$rc" -eq 0 && "$PY" "$CHECK" calibrate cp.html cp.json >check.txt 2>&1 &&
        grep -q "innovations" cp.html'

# ----------------------------------------------------------------------------- refusals
# Every other file an option writes refuses an empty name too, while the options are read
# (before this, `-o ''`, `--plot ''` and `--write ''` wrote nothing and said nothing, exit 0).
for spec in "calibrate -o" "calibrate --plot" "check --json" "design -o" "design --json" \
  "design --plot" "diagnose --write" "diagnose --plot" "estimate -o" "estimate --plot" \
  "estimate --json" "sensitivity --json" "simulate -o" "simulate --plot" "simulate --json" \
  "sweep -o" "sweep --plot"; do
  read -r c opt <<<"$spec"
  run "$c" m.tnet "$opt" ''
  check "$spec '': exit 2, an output needs a file name" \
    eval 'test "$rc" -eq 2 && grep -q "needs a file name" err.txt'
done

mkdir -p adir
for cmd in diagnose calibrate; do
  run "$cmd" m.tnet --html adir
  check "$cmd --html onto a directory: exit 2, 'is a directory'" \
    eval 'test "$rc" -eq 2 && grep -q "is a directory" err.txt'
  run "$cmd" m.tnet --html ''
  check "$cmd --html '': exit 2, an output needs a file name" \
    eval 'test "$rc" -eq 2 && grep -q "needs a file name" err.txt'
  run "$cmd" m.tnet --html no_such_dir/r.html
  check "$cmd --html into a missing folder: exit 2 naming it" \
    eval 'test "$rc" -eq 2 && grep -q "cannot write .no_such_dir/r.html." err.txt'
  run "$cmd" m.tnet --html m.tnet
  check "$cmd --html onto the model: exit 2 naming it, the model untouched" \
    eval 'test "$rc" -eq 2 && grep -q "would overwrite the model" err.txt && cmp -s m.tnet m.orig'
  run "$cmd" m.tnet --html d2.csv
  check "$cmd --html onto its data: exit 2 naming it" \
    eval 'test "$rc" -eq 2 && grep -q "would overwrite the data file" err.txt'
  run "$cmd" m.tnet --html same.html --json same.html
  check "$cmd --html and --json on one file: exit 2 naming both" \
    eval "test \"\$rc\" -eq 2 && grep -q \"same file\" err.txt && test ! -e same.html"
done
# A folder the user cannot write: refused before the diagnosis runs (no report on standard output),
# for a new file and for an existing one. Run as root, the check runs as the unprivileged user
# `nobody` (setpriv), whom the folder refuses as it refuses everyone but root.
mkdir -p ro && echo old >ro/old.html && chmod 755 ro && chmod a-w ro
as_user=()
if [ "$(id -u)" -eq 0 ]; then
  if command -v setpriv >/dev/null && id nobody >/dev/null 2>&1; then
    as_user=(setpriv --reuid=nobody --regid=nogroup --clear-groups)
    chmod -R a+rX . && chmod a-w ro # (the work folder is private: mktemp -d)
  else
    as_user=(skip)
  fi
fi
if [ "${as_user[0]:-}" != skip ]; then
  for target in ro/r.html ro/old.html; do
    "${as_user[@]}" "$TN" diagnose m.tnet --html "$target" >out.txt 2>err.txt
    rc=$?
    check "diagnose --html $target in a read-only folder: exit 2 before the diagnosis, naming it" \
      eval "test \"\$rc\" -eq 2 && grep -q \"cannot write .$target.*cannot be written\" err.txt && ! grep -q RMSE out.txt"
  done
  check "the file in the read-only folder is untouched" grep -qx old ro/old.html
else
  echo "SKIP: no setpriv or user nobody: the read-only folder is not checked as root"
fi
# Atomic: a report that exists stays whole until the new one is complete; no temporary is left.
echo old >keep.html
ln -s keep.html link.html
run calibrate m.tnet --method lm --html link.html
check "calibrate --html through a symlink: written where it points, the link kept" \
  eval 'test "$rc" -eq 0 && test -L link.html && grep -q "<!DOCTYPE html>" keep.html'
check "no temporary file left behind" test -z "$(find . -name '.*.tmp.*')"

finish
