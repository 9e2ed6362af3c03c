#!/usr/bin/env bash
# The report pages of diagnose --html and calibrate --html in a real browser: headless Chromium
# (Debian's chromium package, installed by scripts/install-deps) loads each page with no console
# message and no network request (its net log holds no URL but the page's own file), renders it
# to a screenshot that is not blank, and prints it to a PDF of A4 pages. A page made to fail
# (an image from the network, a script) shows that the checks can fail.
# Without chromium the test is skipped (exit 77, ctest's SKIP_RETURN_CODE) and says why.
# Usage: html_report_browser.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

CHROMIUM=${CHROMIUM:-$(command -v chromium || command -v chromium-browser || true)}
if [ -z "$CHROMIUM" ]; then
  echo "SKIP: chromium not found; install Debian's chromium package (scripts/install-deps, or" \
    "apt-get install -y chromium) to check the report pages in a browser"
  exit 77
fi
PY=/usr/bin/python3
export HOME="$WORK/home" # the browser's profile and crash reports stay in the scratch folder
mkdir -p "$HOME"

# browse PAGE NAME: loads PAGE; its DOM in NAME.dom, the browser's log in NAME.log, its net log in
# NAME.net.json, a screenshot in NAME.png and the printed page in NAME.pdf.
browse() {
  local page=$1 name=$2
  local flags=(--headless --disable-gpu --no-sandbox --no-first-run --disable-extensions
    --disable-background-networking --disable-component-update --disable-sync
    --disable-default-apps --user-data-dir="$WORK/profile_$name" --enable-logging=stderr --v=0
    --virtual-time-budget=3000)
  timeout 120 "$CHROMIUM" "${flags[@]}" --log-net-log="$name.net.json" --dump-dom \
    "file://$WORK/$page" >"$name.dom" 2>"$name.log"
  timeout 120 "$CHROMIUM" "${flags[@]}" --window-size=1280,1600 --screenshot="$WORK/$name.png" \
    "file://$WORK/$page" >/dev/null 2>>"$name.log"
  timeout 120 "$CHROMIUM" "${flags[@]}" --no-pdf-header-footer --print-to-pdf="$WORK/$name.pdf" \
    "file://$WORK/$page" >/dev/null 2>>"$name.log"
}

# console NAME: the console messages of the page (errors, CSP refusals, script output).
console() { grep -E 'CONSOLE|Uncaught|Refused to|Content Security Policy' "$1.log"; }

# requests NAME PAGE: every URL the page asked the network for: the net log's request jobs started
# for the page (an initiator or isolation key of its own; the browser's own background requests,
# such as update checks, have "not an origin" and no file:// key), other than the page's file.
cat >requests.py <<'EOF'
import json, sys
log = json.load(open(sys.argv[1]))
names = {v: k for k, v in log["constants"]["logEventTypes"].items()}
page = "file://" + sys.argv[2]
for e in log.get("events", []):
    p = e.get("params", {})
    if names.get(e.get("type")) != "URL_REQUEST_START_JOB":
        continue
    url = p.get("url", "")
    mine = p.get("initiator") != "not an origin" or "file://" in p.get("network_isolation_key", "")
    if mine and url and url != page and not url.startswith("data:"):
        print(url)
EOF
requests() { "$PY" requests.py "$1.net.json" "$WORK/$2"; }

# picture NAME: "colours non_white_share" of the screenshot (Pillow, else a PNG decoder here).
cat >picture.py <<'EOF'
import struct, sys, zlib
def pixels(path):
    try:
        from PIL import Image
        im = Image.open(path).convert("RGB")
        return list(im.getdata())
    except ImportError:
        pass
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and ctype in (2, 6)
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, out, prev, stride = zlib.decompress(idat), [], bytearray(w * bpp), w * bpp
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out += [tuple(line[i:i + 3]) for i in range(0, stride, bpp)]
        prev = line
    return out
px = pixels(sys.argv[1])
print(len(set(px)), sum(1 for p in px if p != (255, 255, 255)) / len(px))
EOF
picture() { "$PY" picture.py "$1.png"; }

# pdf_pages NAME: "pages A4" of the printed page (A4 when every page is 595 x 842 pt).
pdf_pages() {
  "$PY" - "$1.pdf" <<'EOF'
import re, sys
pdf = open(sys.argv[1], "rb").read()
pages = len(re.findall(rb"/Type\s*/Page[^s]", pdf))
boxes = re.findall(rb"/MediaBox\s*\[\s*0 0 ([\d.]+) ([\d.]+)\s*\]", pdf)
a4 = bool(boxes) and all(abs(float(w) - 595.3) < 2 and abs(float(h) - 841.9) < 2 for w, h in boxes)
print(pages, "A4" if a4 else "not-A4")
EOF
}

. "$HERE/html_report_fixture.sh"

# ----------------------------------------------------------------------------- controls
# A page that fetches an image from the network and runs a script: the checks must catch both.
cat >bad.html <<'EOF'
<!DOCTYPE html><html><head><meta charset="utf-8"><title>bad</title></head>
<body><p>bad</p><img src="http://192.0.2.1/x.png"><script>console.error("boom")</script></body></html>
EOF
browse bad.html bad
check "control: a page's console error is seen" eval 'console bad | grep -q boom'
check "control: a page's network request is seen" eval 'requests bad bad.html | grep -q 192.0.2.1'

# ----------------------------------------------------------------------------- the pages
run diagnose m.tnet --threads 2 --json d.json --html d.html
check "diagnose --html written" eval 'test "$rc" -eq 0 -a -s d.html'
run calibrate m.tnet --method mc --samples 64 --tolerance 30 --json c.json --html c.html
check "calibrate --html written" eval 'test "$rc" -eq 0 -a -s c.html'
for name in d c; do
  browse "$name.html" "$name"
  check "$name.html loads: the DOM has its sections and figures" \
    eval 'grep -q "<section id=\"run\"" '"$name"'.dom && grep -q "<svg" '"$name"'.dom'
  what=$([ "$name" = d ] && echo diagnose || echo calibrate)
  check "$name.html as the browser shows it: every finding or param, case and plot of its JSON" \
    eval '"$PY" "$HERE/html_report_check.py" '"$what $name"'.dom '"$name"'.json >check.txt 2>&1 ||
      { cat check.txt >err.txt; false; }'
  check "$name.html: no console message" eval '! console '"$name"' >"$name.console" 2>&1 ||
    { cat "$name.console" >err.txt; false; }'
  check "$name.html: no network request" eval 'test -s '"$name"'.net.json && test -z "$(requests '"$name"' '"$name"'.html)"'
  read -r colours share < <(picture "$name")
  check "$name.html: the screenshot is not blank ($colours colours, ${share:0:5} not white)" \
    eval '[ "${colours:-0}" -gt 16 ] && "$PY" -c "import sys; sys.exit(0 if '"${share:-0}"' > 0.02 else 1)"'
  read -r pages paper < <(pdf_pages "$name")
  check "$name.html prints on A4 ($pages pages, $paper)" \
    eval '[ "${pages:-0}" -ge 1 ] && [ "$paper" = A4 ]'
done
if [ -n "${KEEP_SCREENSHOT:-}" ]; then cp d.png "$KEEP_SCREENSHOT"; fi

finish
