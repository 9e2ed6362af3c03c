#!/usr/bin/env bash
# The quick start's SUNDIALS (cmake/sundials.cmake): a folder holding libsundials-dev as unpacked
# by `dpkg-deb -x` (here: a copy of the installed package's headers and static libraries, which
# are what it holds) configures a build that links those static libraries into the executable,
# and a folder without them fails with a message naming it. Configure only (the quick start's own
# build is timed in the README).
#   tests/build/sundials_unpacked.sh SOURCE_DIR
set -euo pipefail
src=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
arch=$(gcc -print-multiarch)
root="$tmp/libsundials-dev"
mkdir -p "$root/usr/lib/$arch" "$root/usr/include"
dpkg -L libsundials-dev | grep '^/usr/include/.*\.h$' | while read -r h; do
  mkdir -p "$root$(dirname "$h")"
  cp "$h" "$root$h"
done
cp /usr/lib/"$arch"/libsundials_*.a "$root/usr/lib/$arch/"

cmake -S "$src" -B "$tmp/build" -G Ninja -DTHERMNET_BUILD_TESTS=OFF -DTHERMNET_MPI=OFF \
  -DTHERMNET_PYTHON=OFF -DTHERMNET_SUNDIALS_UNPACKED="$root" >"$tmp/configure.log" 2>&1 ||
  { cat "$tmp/configure.log"; echo "FAIL: configuring with the unpacked SUNDIALS failed"; exit 1; }
grep -q "SUNDIALS 6: static libraries unpacked in $root" "$tmp/configure.log" ||
  { cat "$tmp/configure.log"; echo "FAIL: no status line for the unpacked SUNDIALS"; exit 1; }
link=$(cd "$tmp/build" && ninja -t commands cli/thermnet | tail -n 1)
for lib in cvodes ida kinsol sunlinsolklu; do
  grep -q -- "$root/usr/lib/$arch/libsundials_$lib.a" <<<"$link" ||
    { echo "$link"; echo "FAIL: the executable does not link libsundials_$lib.a"; exit 1; }
done
if grep -q 'libsundials_[a-z]*\.so\|-lsundials' <<<"$link"; then
  echo "$link"; echo "FAIL: the executable links a shared SUNDIALS too"; exit 1
fi

rm -rf "$tmp/build" "$root/usr/include/cvodes"
if cmake -S "$src" -B "$tmp/build" -G Ninja -DTHERMNET_BUILD_TESTS=OFF -DTHERMNET_MPI=OFF \
  -DTHERMNET_PYTHON=OFF -DTHERMNET_SUNDIALS_UNPACKED="$root" >"$tmp/configure.log" 2>&1; then
  echo "FAIL: a folder without the SUNDIALS headers configured"; exit 1
fi
# (CMake wraps the message: compared without line breaks and spaces)
tr -d ' \n' <"$tmp/configure.log" | grep -qi "nosundialsheadersunder$root/usr/include" ||
  { cat "$tmp/configure.log"; echo "FAIL: the message does not name the folder"; exit 1; }
echo "PASS: the unpacked SUNDIALS is linked statically; a folder without it is named"
