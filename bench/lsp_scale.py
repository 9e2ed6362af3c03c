#!/usr/bin/env python3
"""The language server at scale: how long `thermnet lsp` takes to answer on a large document.

Opens a document of N nodes (each isolated, so lint publishes one warning per node, as in
tests/lsp/lsp_test.py) and prints the wall time from sending each message until the first bytes
of its answer arrive (the server writes an answer once it has computed it): didOpen until its
diagnostics are published (parse + lint + publishing), documentSymbol, hover and definition on
the last node's name; then the CPU time of the server process (start-up included) and
`thermnet lint` on the same text for comparison.

Usage: lsp_scale.py PATH/TO/thermnet [--nodes 50000]
"""
import argparse
import json
import os
import resource
import subprocess
import tempfile
import time


def frame(msg):
    body = json.dumps(msg).encode()
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


def read_reply(out):
    """The next message and the time its first header line arrived (the server writes a reply
    only once it has computed it, so that time excludes this client's JSON decoding)."""
    length = None
    arrived = None
    while True:
        line = out.readline()
        if arrived is None:
            arrived = time.perf_counter()
        if not line:
            raise EOFError("the server closed its output")
        line = line.strip()
        if not line:
            break
        name, _, value = line.partition(b":")
        if name.lower() == b"content-length":
            length = int(value)
    return json.loads(out.read(length)), arrived


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("thermnet")
    ap.add_argument("--nodes", type=int, default=50000)
    a = ap.parse_args()
    n = a.nodes
    text = "boundary amb T = 20\n" + "".join(f"node n{k} C = 1\n" for k in range(n))
    work = tempfile.mkdtemp(prefix="lsp_scale_")
    path = os.path.join(work, "big.tnet")
    with open(path, "w") as f:
        f.write(text)
    uri = "file://" + path
    proc = subprocess.Popen([a.thermnet, "lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL)

    def send(msg):
        proc.stdin.write(frame(msg))
        proc.stdin.flush()

    def wait(pred):
        """The next message satisfying pred, and when it arrived."""
        while True:
            m, arrived = read_reply(proc.stdout)
            if pred(m):
                return m, arrived

    send({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {}})
    wait(lambda m: m.get("id") == 1)
    timings = []
    t0 = time.perf_counter()
    send({"jsonrpc": "2.0", "method": "textDocument/didOpen",
          "params": {"textDocument": {"uri": uri, "languageId": "tnet", "version": 1,
                                      "text": text}}})
    d, arrived = wait(lambda m: m.get("method") == "textDocument/publishDiagnostics")
    timings.append(("didOpen -> diagnostics published", arrived - t0,
                    f"{len(d['params']['diagnostics'])} diagnostics"))
    last_line = n  # 0-based line of node n{n-1}
    requests = [
        ("documentSymbol", "textDocument/documentSymbol", {}),
        ("hover on the last node", "textDocument/hover",
         {"position": {"line": last_line, "character": 6}}),
        ("definition of the last node", "textDocument/definition",
         {"position": {"line": last_line, "character": 6}}),
    ]
    for rid, (what, method, extra) in enumerate(requests, start=2):
        params = {"textDocument": {"uri": uri}, **extra}
        t0 = time.perf_counter()
        send({"jsonrpc": "2.0", "id": rid, "method": method, "params": params})
        r, arrived = wait(lambda m, rid=rid: m.get("id") == rid)
        res = r.get("result")
        size = len(res) if isinstance(res, list) else ("an answer" if res else "no answer")
        timings.append((what, arrived - t0, size))
    send({"jsonrpc": "2.0", "id": 99, "method": "shutdown"})
    wait(lambda m: m.get("id") == 99)
    send({"jsonrpc": "2.0", "method": "exit"})
    proc.stdin.close()
    proc.wait()
    cpu = resource.getrusage(resource.RUSAGE_CHILDREN)
    server_cpu = cpu.ru_utime + cpu.ru_stime
    t0 = time.perf_counter()
    subprocess.run([a.thermnet, "lint", path], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    lint = time.perf_counter() - t0
    print(f"language server on a {n}-node document ({len(text) / 1e6:.2f} MB), load average "
          f"{os.getloadavg()[0]:.1f}:")
    for what, secs, size in timings:
        print(f"  {what:36s} {secs:8.3f} s  ({size})")
    print(f"  server process CPU (all of the above)  {server_cpu:8.3f} s")
    print(f"  thermnet lint on the same file         {lint:8.3f} s wall")


if __name__ == "__main__":
    main()
