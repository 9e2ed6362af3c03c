#!/bin/bash
# Copies a thermnet binary with every shared library it loads and the dynamic loader into DIR, so
# that it runs on a machine without thermnet's Debian packages (a lent 16-core machine):
#   DIR/lib/ld-linux-x86-64.so.2 --library-path DIR/lib DIR/bin/thermnet ARGS...
# (Open MPI's plugins are not copied: the bundle runs without mpirun.)
#
# Usage: bench/bundle_binary.sh BINARY DIR
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 BINARY DIR" >&2; exit 2; }
bin=$1 dir=$2
mkdir -p "$dir/bin" "$dir/lib"
cp "$bin" "$dir/bin/thermnet"
strip "$dir/bin/thermnet"
ldd "$bin" | awk '/=> \//{print $3}' | while read -r lib; do cp -L "$lib" "$dir/lib/"; done
cp -L "$(ldd "$bin" | awk '/ld-linux/{print $1}')" "$dir/lib/"
strip --strip-unneeded "$dir"/lib/*.so* 2>/dev/null || true
"$dir/lib/ld-linux-x86-64.so.2" --library-path "$dir/lib" "$dir/bin/thermnet" --version >/dev/null
du -sh "$dir"
