#!/usr/bin/env bash
# The generated parts of the docs are what `thermnet kinds --family F --format markdown` prints,
# word for word: docs/element_reference.md whole, and the tables between
# "<!-- generated; ... -->" and "<!-- end generated -->" in docs/calibration.md (optimizers),
# docs/inverse.md (estimators) and docs/diagnose.md (hypotheses).
# Usage: generated_tables.sh THERMNET SOURCE_DIR
set -u
TN=${1:?usage: generated_tables.sh THERMNET SOURCE_DIR}
DOCS=${2:?source dir}/docs
status=0
# block FILE: the lines between the generated markers of FILE.
block() { sed -n '/^<!-- generated; /,/^<!-- end generated -->$/{//!p}' "$1"; }
# table: the command's output without its title (2 lines) and its final blank line.
table() { tail -n +3 | sed '${/^$/d}'; }
# compare FILTER FAMILY EXPECTED LABEL: EXPECTED against the command's output through FILTER.
compare() {
  local filter=$1 family=$2 expected=$3 label=$4
  if diff -u --label "$label" --label "thermnet kinds --family $family" "$expected" \
       <("$TN" kinds --family "$family" --format markdown | $filter); then
    echo "ok   - $label matches thermnet kinds --family $family --format markdown"
  else
    echo "FAIL - $label differs from thermnet kinds --family $family --format markdown"
    echo "       (regenerate it from that command's output)"
    status=1
  fi
}
compare cat element "$DOCS/element_reference.md" docs/element_reference.md
for pair in optimizer:calibration estimator:inverse hypothesis:diagnose; do
  family=${pair%%:*}
  doc="$DOCS/${pair#*:}.md"
  tmp=$(mktemp)
  block "$doc" >"$tmp"
  if [ ! -s "$tmp" ]; then
    echo "FAIL - $(basename "$doc") has no generated block"
    status=1
  else
    compare table "$family" "$tmp" "the generated block of docs/${pair#*:}.md"
  fi
  rm -f "$tmp"
done
exit $status
