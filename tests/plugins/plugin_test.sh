#!/usr/bin/env bash
# Out-of-tree plugins end to end: `cmake --install` into a temporary prefix, the example plugin
# (plugins/examples/peltier) and broken plugins built against it with find_package(thermnet), then
# lint, simulate, kinds and the language server with `plugin "..."` and `--plugin`, and the load
# errors (missing file, not a plugin, wrong ABI, duplicate kind).
# Usage: plugin_test.sh CMAKE BUILD_DIR SOURCE_DIR CXX_COMPILER
set -u

CMAKE=${1:?usage: plugin_test.sh CMAKE BUILD_DIR SOURCE_DIR CXX_COMPILER}
BUILD=${2:?build dir}
SRC=${3:?source dir}
CXX=${4:?compiler}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/thermnet_plugins.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 2

pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; [ $# -gt 1 ] && printf '       %s\n' "$2"; }
check() { # check DESCRIPTION COMMAND...: passes when COMMAND succeeds
  local what=$1; shift
  if "$@"; then ok "$what"; else bad "$what" "$(head -c 600 err.txt 2>/dev/null)"; fi
}
# run CMD...: runs thermnet, stores stdout/stderr/exit status in out.txt/err.txt/$rc (lint prints
# its diagnostics on stdout)
run() { "$TN" "$@" >out.txt 2>err.txt; rc=$?; }
# close_to FILE COLUMN EXPECTED TOL: the last CSV row's COLUMN is within TOL of EXPECTED
close_to() {
  /usr/bin/python3 -c "import csv,sys; r=list(csv.DictReader(open('$1')))[-1]; v=float(r['$2']); sys.exit(0 if abs(v-$3)<=$4 else print('got', v) or 1)"
}

GEN=()
command -v ninja >/dev/null && GEN=(-G Ninja)
configure_and_build() { # SOURCE BINARY: builds a project against the installed package
  "$CMAKE" -S "$1" -B "$2" "${GEN[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$CXX" \
    -DCMAKE_PREFIX_PATH="$WORK/prefix" >"$2.log" 2>&1 && "$CMAKE" --build "$2" >>"$2.log" 2>&1
}

# ----------------------------------------------------------------------------- install and build
"$CMAKE" --install "$BUILD" --prefix "$WORK/prefix" >install.log 2>&1
check "cmake --install succeeds" test $? -eq 0
check "the package installs thermnetConfig.cmake, headers and the executable" \
  test -f prefix/lib/cmake/thermnet/thermnetConfig.cmake -a -f prefix/include/thermnet/kernel/plugin_host/plugin_api.hpp \
  -a -x prefix/bin/thermnet
TN=$WORK/prefix/bin/thermnet

configure_and_build "$SRC/plugins/examples/peltier" "$WORK/peltier"
check "the example plugin builds out of tree with find_package(thermnet)" test -f peltier/libpeltier.so
configure_and_build "$SRC/tests/plugins/broken" "$WORK/broken"
check "the broken plugins build" test -f broken/libwrongabi.so -a -f broken/libdupkind.so -a -f broken/libnotplugin.so -a -f broken/libmarker.so
if [ "$fail" -ne 0 ]; then
  cat install.log peltier.log broken.log 2>/dev/null | tail -40
  echo "$pass passed, $fail failed"; exit 1
fi
PLUGIN=$WORK/peltier/libpeltier.so

# ----------------------------------------------------------------------------- models
# The example model with its plugin path made relative to this directory.
sed 's#"build/libpeltier.so"#"peltier/libpeltier.so"#' "$SRC/plugins/examples/peltier/cooler.tnet" >cooler.tnet
grep -v '^plugin' cooler.tnet >bare.tnet
# Steady state by hand: 2 W = S I Tc - I^2 R / 2 - K (Th - Tc) with S I = 0.1 W/K, I^2 R / 2 = 4 W,
# K = 0.5 W/K, Th = 298.15 K: Tc = (2 + 4 + 0.5 * 298.15) / 0.6 = 258.458333 K = -14.691667 degC.
EXPECTED=-14.691667

run lint --plugin "$PLUGIN" cooler.tnet
check "lint --plugin LIB of a model with plugin \"peltier/libpeltier.so\" (the same library) is clean" test "$rc" -eq 0 -a ! -s err.txt
run lint cooler.tnet
check "lint never loads a model's plugin: a plugin-error naming --plugin (exit 1)" \
  bash -c "test $rc -eq 1 && grep -q 'cooler.tnet:.*cannot load plugin .peltier/libpeltier.so.: thermnet lint never runs code named by a model.*--plugin PATH \[plugin-error\]' out.txt"
run simulate cooler.tnet --steady
check "simulate refuses a model's plugin unless allowed, naming --allow-model-plugins (exit 1)" \
  bash -c "test $rc -eq 1 && grep -q 'loads code only when you allow it: pass --allow-model-plugins (or set THERMNET_ALLOW_MODEL_PLUGINS=1)' err.txt"
run simulate --allow-model-plugins cooler.tnet --steady
check "simulate --allow-model-plugins --steady with the plugin exits 0" test "$rc" -eq 0
check "steady plate temperature matches the hand calculation ($EXPECTED degC)" close_to out.txt plate $EXPECTED 1e-4
THERMNET_ALLOW_MODEL_PLUGINS=1 "$TN" simulate cooler.tnet >out.txt 2>err.txt
rc=$?
check "transient simulate with THERMNET_ALLOW_MODEL_PLUGINS=1 exits 0" test "$rc" -eq 0
check "after 10 min (time constant 33 s) the plate has settled at $EXPECTED degC" close_to out.txt plate $EXPECTED 1e-3
check "the transient starts at 25 degC" /usr/bin/python3 -c "import csv,sys; r=list(csv.DictReader(open('out.txt')))[0]; sys.exit(abs(float(r['plate'])-25)>1e-9)"

run lint bare.tnet
check "without the plugin the kind is unknown (exit 1, unknown-kind)" \
  bash -c "test $rc -eq 1 && grep -q 'unknown-kind' out.txt err.txt"
run --plugin "$PLUGIN" simulate bare.tnet --steady
check "--plugin before the subcommand loads the kind" close_to out.txt plate $EXPECTED 1e-4
run simulate --plugin "$PLUGIN" bare.tnet --steady
check "--plugin after the subcommand loads the kind" close_to out.txt plate $EXPECTED 1e-4
run --plugin "$PLUGIN" simulate cooler.tnet --steady
check "the same library by --plugin and by the model: no flag needed, loaded once (no duplicate error)" \
  bash -c "test $rc -eq 0 && test ! -s err.txt"
run kinds peltier --plugin "$PLUGIN"
check "kinds shows the plugin kind with its keys" \
  bash -c "test $rc -eq 0 && grep -q '^peltier (2 terminals)' out.txt && grep -q 'Seebeck' out.txt"

# ----------------------------------------------------------------------------- load errors
printf 'model m\nplugin "missing/libnope.so"\nnode n C = 1\n' >missing.tnet
run simulate --allow-model-plugins missing.tnet
check "a missing plugin file is a plugin-error at the statement (missing.tnet:2:1)" \
  bash -c "test $rc -eq 1 && grep -q 'missing.tnet:2:1: error: cannot load plugin .missing/libnope.so.: no such file \[plugin-error\]' out.txt err.txt"
run --plugin missing/libnope.so kinds
check "--plugin with a missing file fails with a clear message" \
  bash -c "test $rc -ne 0 && grep -q \"cannot load plugin 'missing/libnope.so': no such file\" err.txt"

ABI=$(sed -n 's/^#define THERMNET_PLUGIN_ABI \([0-9]*\)$/\1/p' "$SRC/kernel/plugin_host/plugin_api.hpp")
run --plugin broken/libwrongabi.so kinds
check "a wrong ABI version is refused before registration runs, naming both versions" \
  bash -c "test $rc -eq 1 && grep -q 'built for plugin ABI $((ABI + 1000)), but this thermnet has plugin ABI $ABI' err.txt"
printf 'plugin "broken/libwrongabi.so"\nnode n C = 1\n' >abi.tnet
run simulate --allow-model-plugins abi.tnet
check "a wrong ABI in a model is a plugin-error diagnostic" \
  bash -c "test $rc -eq 1 && grep -q 'abi.tnet:1:1: error: cannot load plugin.*plugin ABI $((ABI + 1000)).*\[plugin-error\]' out.txt err.txt"

printf 'plugin "broken/libdupkind.so"\nboundary a T = 0\nnode n C = 1\nconductance g n a G = 1\n' >dup.tnet
run simulate --allow-model-plugins dup.tnet
check "a duplicate kind names the library and the kind" \
  bash -c "test $rc -eq 1 && grep -q \"cannot load plugin 'broken/libdupkind.so': its element kind 'conductance' is already registered by thermnet itself\" out.txt err.txt"
run --plugin broken/libdupkind.so kinds conductance
check "a duplicate kind by --plugin fails too" \
  bash -c "test $rc -eq 1 && grep -q \"libdupkind.so.*element kind 'conductance' is already registered\" err.txt"

run --plugin broken/libnotplugin.so kinds
check "a library without entry points is not a thermnet plugin" \
  bash -c "test $rc -eq 1 && grep -q 'not a thermnet plugin' err.txt"
run --plugin cooler.tnet kinds
check "a file that is no shared library is refused" \
  bash -c "test $rc -eq 1 && grep -q 'not a loadable shared library' err.txt"

# ----------------------------------------------------------------------------- code named by a model
# A library whose constructor writes a marker: lint, lsp and simulate without permission never
# load it (directly or through an include); a FIFO named as a plugin is refused, not waited on.
export THERMNET_TEST_MARKER=$WORK/marker
mkdir -p inc
printf 'include "inc/parts.tnet"\nboundary a T = 0\nnode n C = 1\nconductance g n a G = 1\ncase c { duration = 10 }\n' >hostile.tnet
printf 'plugin "../broken/libmarker.so"\n' >inc/parts.tnet
run lint hostile.tnet
check "lint of a model including a plugin statement: exit 1, no marker" \
  bash -c "test $rc -eq 1 && test ! -e marker && grep -q 'never runs code named by a model' out.txt"
run lint --format sarif hostile.tnet
check "lint --format sarif: no marker" test ! -e marker
run simulate hostile.tnet
check "simulate without --allow-model-plugins: exit 1 naming the flag, no marker" \
  bash -c "test $rc -eq 1 && test ! -e marker && grep -q -- '--allow-model-plugins' err.txt"
run calibrate hostile.tnet
check "calibrate without the flag: no marker" test ! -e marker
mkfifo fifo.so
printf 'plugin "fifo.so"\nnode n C = 1\n' >fifo.tnet
timeout 60 "$TN" simulate --allow-model-plugins fifo.tnet >out.txt 2>err.txt
rc=$?
check "a FIFO named as a plugin is refused at once (exit 1, not a regular file)" \
  bash -c "test $rc -eq 1 && grep -q 'not a regular file' err.txt"
timeout 60 "$TN" --plugin fifo.so kinds >out.txt 2>err.txt
rc=$?
check "a FIFO given to --plugin is refused at once" bash -c "test $rc -eq 1 && grep -q 'not a regular file' err.txt"

# lsp_session TN MODEL [ARGS...]: opens MODEL in `TN lsp ARGS`, hovers at line 8 column 3, prints
# the diagnostics and the hover as JSON lines.
lsp_session() {
  /usr/bin/python3 - "$@" <<'PY'
import json, subprocess, sys
tn, path, args = sys.argv[1], sys.argv[2], sys.argv[3:]
text = open(path).read()
uri = "file://" + path
msgs = [
    {"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}},
    {"jsonrpc": "2.0", "method": "textDocument/didOpen",
     "params": {"textDocument": {"uri": uri, "languageId": "tnet", "version": 1, "text": text}}},
    {"jsonrpc": "2.0", "id": 2, "method": "textDocument/hover",
     "params": {"textDocument": {"uri": uri}, "position": {"line": 7, "character": 2}}},
    {"jsonrpc": "2.0", "id": 3, "method": "shutdown"},
    {"jsonrpc": "2.0", "method": "exit"},
]
data = b"".join(b"Content-Length: %d\r\n\r\n%s" % (len(b), b) for b in (json.dumps(m).encode() for m in msgs))
out = subprocess.run([tn, "lsp", *args], input=data, capture_output=True, timeout=60).stdout
replies = []
while out:
    head, _, rest = out.partition(b"\r\n\r\n")
    n = int(head.split(b":")[1])
    replies.append(json.loads(rest[:n])); out = rest[n:]
diags = [r for r in replies if r.get("method") == "textDocument/publishDiagnostics"][0]["params"]["diagnostics"]
hover = [r for r in replies if r.get("id") == 2][0]["result"]
print(json.dumps(diags))
print(json.dumps(hover))
PY
}
lsp_session "$TN" "$WORK/hostile.tnet" >lsp.txt 2>err.txt
check "the language server never loads a model's plugin: a plugin-error diagnostic, no marker" \
  bash -c "test ! -e marker && grep -q 'never runs code named by a model' lsp.txt"

# ----------------------------------------------------------------------------- language server
lsp_session "$TN" "$WORK/cooler.tnet" --plugin "$PLUGIN" >lsp.txt 2>err.txt
check "lsp --plugin LIB: no diagnostics for the model's statement of it, hover on 'peltier' shows its doc" \
  bash -c "test \"\$(sed -n 1p lsp.txt)\" = '[]' && sed -n 2p lsp.txt | grep -q thermoelectric"
lsp_session "$TN" "$WORK/cooler.tnet" >lsp.txt 2>err.txt
check "lsp without --plugin: the statement is a plugin-error diagnostic naming --plugin" \
  bash -c "grep -q 'never runs code named by a model.*--plugin PATH' lsp.txt"
cat lsp.txt

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
