#!/usr/bin/env bash
# scripts/device/pack_bench.sh: packs the bench and the viewer's unit tests, as built here in
# the Debian 13 root, with every shared library they load and the root's dynamic loader,
# into one archive a lent GPU machine can run without installing anything
# (scripts/device/view_tail.sh unpacks and runs it there; BENCHMARKS.md says how).
#
#   ./ladarvr shell -c "scripts/device/pack_bench.sh [OUT_DIR]"     (default OUT_DIR: .devpack)
#
# Writes OUT_DIR/bench.tar.xz (bin/, lib/, ld-linux-x86-64.so.2) atomically (a temporary
# then a rename). The GL libraries packed are glvnd's dispatchers: the machine's own
# vendor library (NVIDIA's EGL) is found there through __EGL_VENDOR_LIBRARY_FILENAMES.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:-"$root/.devpack"}
build=${LADARVR_BUILD_DIR:-"$root/build/release"}
bins=("$build/bench/ladarvr-bench" "$build/tests/viewer/viewer_tests")
for b in "${bins[@]}"; do
  [ -x "$b" ] || { echo "pack_bench: $b: not built; build ladarvr_bench_cli and viewer_tests first" >&2; exit 2; }
done
mkdir -p "$out"
stage=$(mktemp -d "$out/.pack.XXXXXX")
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/pack/bin" "$stage/pack/lib"
cp "${bins[@]}" "$stage/pack/bin/"
# Every library the programs load (ldd follows the whole graph), and the loader itself.
ldd "${bins[@]}" | awk '/=> \// {print $3}' | sort -u | while read -r lib; do cp -L "$lib" "$stage/pack/lib/"; done
loader=$(ldd "${bins[0]}" | awk '/ld-linux-x86-64/ {print $1}')
cp -L "$loader" "$stage/pack/ld-linux-x86-64.so.2"
# glvnd's EGL and GL dispatchers are loaded by name at run time, not through DT_NEEDED.
for name in libEGL.so.1 libGLdispatch.so.0 libOpenGL.so.0; do
  p=$(ldconfig -p | awk -v n="$name" '$1 == n && /x86-64/ {print $NF; exit}')
  [ -n "$p" ] && cp -L "$p" "$stage/pack/lib/"
done
tar -C "$stage" -cf - pack | xz -T2 -9 >"$stage/bench.tar.xz"
mv "$stage/bench.tar.xz" "$out/bench.tar.xz"
size=$(du -m "$out/bench.tar.xz" | cut -f1)
echo "pack_bench: $out/bench.tar.xz, $size MiB"
[ "$size" -lt 50 ] || echo "pack_bench: warning: $size MiB: with the working tree (about 13 MiB) near the 64 MiB a device call carries" >&2
