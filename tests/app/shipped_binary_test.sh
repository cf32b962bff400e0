#!/bin/sh
# tests/app/shipped_binary_test.sh: the shipped `ladarvr` links no PCL I/O and imports no
# popen or system (it runs no scripts; the benchmarks that do are bench/'s own executable).
# Usage: shipped_binary_test.sh LADARVR_BINARY LADARVR_BENCH_BINARY
# The benchmarks' executable does both, so the same checks are seen to find them there.
set -eu
bin=$1
bench=$2
fail() { echo "FAIL: $*" >&2; exit 1; }

# imports BINARY SYMBOL: whether BINARY's dynamic symbol table asks for SYMBOL.
imports() { nm -D --undefined-only "$1" | awk '{print $NF}' | sed 's/@.*//' | grep -qx "$2"; }
# links BINARY LIB: whether the loader maps a library named LIB* for BINARY.
links() { ldd "$1" | awk '{print $1}' | grep -q "^$2"; }

imports "$bench" popen || fail "the check finds no popen in $bench, which calls it"
links "$bench" libpcl_io || fail "the check finds no libpcl_io for $bench, which links it"

for symbol in popen system; do
    imports "$bin" "$symbol" && fail "$bin imports $symbol"
done
links "$bin" libpcl_io && fail "$bin links $(ldd "$bin" | grep libpcl_io)"
echo "shipped_binary_test: no popen, no system, no libpcl_io in $bin"
