#!/usr/bin/env bash
# tests/tree/clang_format_test.sh SOURCE_DIR: every C++ file of the tree follows the
# .clang-format at its root (clang-format --dry-run -Werror names the first lines that do
# not). Build folders are skipped.
set -euo pipefail
src=$(realpath "$1")
cd "$src"
[ -f .clang-format ] || { echo "FAIL: no .clang-format in $src"; exit 1; }
mapfile -d '' files < <(find . -path ./build -prune -o -path ./.git -prune -o \
  \( -name '*.cpp' -o -name '*.hpp' \) -type f -print0 | sort -z)
[ "${#files[@]}" -gt 100 ] || { echo "FAIL: only ${#files[@]} C++ files found under $src"; exit 1; }
if ! clang-format --dry-run -Werror "${files[@]}" 2>"${TMPDIR:-/tmp}/ladarvr-format.$$"; then
  head -n 20 "${TMPDIR:-/tmp}/ladarvr-format.$$"
  rm -f "${TMPDIR:-/tmp}/ladarvr-format.$$"
  echo "FAIL: files above do not follow .clang-format (apply: clang-format -i FILE)"
  exit 1
fi
rm -f "${TMPDIR:-/tmp}/ladarvr-format.$$"
echo "clang_format: ${#files[@]} files follow .clang-format"
