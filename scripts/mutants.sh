#!/usr/bin/env bash
# scripts/mutants.sh [NAME...]: the mutation check behind `./ladarvr bench mutants`.
#
# Reads bench/mutants.txt (name :: file :: sed script :: ctest regex). Copies the tracked
# tree (working-tree contents) into $LADARVR_MUTANTS_DIR (default /tmp/ladarvr-mutants/src),
# configures it once with the release preset, warnings not errors (its own build
# folder), then for each mutant (all, or the NAMEs given):
#   restore the file from the repository, apply the sed script (refused if the file does
#   not change), rebuild, run `ctest -R REGEX`, restore the file.
# A mutant is killed when the build fails or a test fails. Before the mutants, each
# distinct regex runs once on the clean copy: a failing baseline would make every
# mutant look killed, so it stops the run.
# Output: one "mutant: NAME status=killed|survived|error tests=..." line per mutant and a
# Markdown table between "mutants-table-begin" and "mutants-table-end" lines.
# Exit status: 0 when every mutant ran (killed or survived), 1 on an error.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
list="$root/bench/mutants.txt"
work=${LADARVR_MUTANTS_DIR:-/tmp/ladarvr-mutants}
src="$work/src"
build="$src/build/release"
jobs=${LADARVR_MUTANTS_JOBS:-2}
[ -f "$list" ] || { echo "mutants: $list is missing" >&2; exit 1; }

# Parse the list: names, files, sed scripts, regexes (in order).
names=() files=() scripts=() regexes=()
while IFS= read -r line || [ -n "$line" ]; do
  case "$line" in '#'*|'') continue ;; esac
  rest=$line
  fields=()
  while [[ "$rest" == *" :: "* ]]; do fields+=("${rest%% :: *}"); rest=${rest#* :: }; done
  fields+=("$rest")
  [ "${#fields[@]}" = 4 ] ||
    { echo "mutants: $list: '$line': expected 4 fields separated by ' :: '" >&2; exit 1; }
  names+=("${fields[0]}") files+=("${fields[1]}") scripts+=("${fields[2]}") regexes+=("${fields[3]}")
done <"$list"

selected=()
if [ $# -gt 0 ]; then
  for want in "$@"; do
    found=""
    for i in "${!names[@]}"; do [ "${names[$i]}" = "$want" ] && { selected+=("$i"); found=1; }; done
    [ -n "$found" ] || { echo "mutants: no mutant named '$want' in $list; names: ${names[*]}" >&2; exit 1; }
  done
else
  selected=("${!names[@]}")
fi

# A clean copy of the tracked tree; the build folder inside it is kept between runs.
mkdir -p "$src"
(cd "$root" && git ls-files -z | tar --null -cf - -T -) | tar -xf - -C "$src"
echo "mutants: copy in $src, ${#selected[@]} mutant(s), build in $build" >&2
if [ ! -f "$build/build.ninja" ]; then
  # Warnings stay warnings: a mutant is killed by a failing build or test, not by a
  # warning its change raises.
  (cd "$src" && cmake --preset release -DLADARVR_WERROR=OFF >"$work/configure.log" 2>&1) ||
    { tail -n 20 "$work/configure.log" >&2; echo "mutants: configure failed" >&2; exit 1; }
fi
cmake --build "$build" -j "$jobs" >"$work/build.log" 2>&1 ||
  { tail -n 30 "$work/build.log" >&2; echo "mutants: the clean copy does not build" >&2; exit 1; }

# Baseline: each regex passes on the clean copy.
declare -A baseline_done=()
for i in "${selected[@]}"; do
  re=${regexes[$i]}
  [ -n "${baseline_done[$re]:-}" ] && continue
  baseline_done[$re]=1
  if ! ctest --test-dir "$build" -R "$re" -j "$jobs" --timeout 600 >"$work/baseline.log" 2>&1; then
    grep -A20 "tests FAILED" "$work/baseline.log" >&2 || tail -n 20 "$work/baseline.log" >&2
    echo "mutants: the clean copy fails ctest -R '$re'; fix that first" >&2
    exit 1
  fi
done

rows=()
status=0
for i in "${selected[@]}"; do
  name=${names[$i]} file=${files[$i]} script=${scripts[$i]} re=${regexes[$i]}
  t0=$(date +%s)
  cp "$root/$file" "$src/$file"
  sed -i -e "$script" "$src/$file"
  if cmp -s "$root/$file" "$src/$file"; then
    echo "mutant: $name status=error tests=(the sed script does not change $file)"
    rows+=("| $name | \`$file\` | error: does not apply | |")
    status=1
    continue
  fi
  result="survived" killers=""
  if ! cmake --build "$build" -j "$jobs" >"$work/$name.build.log" 2>&1; then
    result="killed" killers="(build fails)"
  elif ! ctest --test-dir "$build" -R "$re" -j "$jobs" --timeout 600 >"$work/$name.test.log" 2>&1; then
    result="killed"
    # ctest's summary: "	  123 - sim.name (Failed)"
    killers=$(sed -n '/tests FAILED:/,$p' "$work/$name.test.log" | sed -n 's/^[[:space:]]*[0-9]* - \(.*\) (.*)$/\1/p' |
              head -n 5 | paste -sd ';' | sed 's/;/; /g')
    n=$(sed -n '/tests FAILED:/,$p' "$work/$name.test.log" | grep -c ' - ' || true)
    [ "$n" -gt 5 ] && killers="$killers; ... ($n tests)"
  fi
  cp "$root/$file" "$src/$file"   # restore: the next mutant starts from the clean tree
  echo "mutant: $name status=$result seconds=$(( $(date +%s) - t0 )) tests=$killers"
  rows+=("| $name | \`$file\` | $result | ${killers//|/\\|} |")   # '|' in a test name: escaped for Markdown
done
# Rebuild the clean tree so the next run starts from it.
cmake --build "$build" -j "$jobs" >"$work/build.log" 2>&1 || true

echo "mutants-table-begin"
echo "| mutant | file | result | tests that killed it |"
echo "|---|---|---|---|"
printf '%s\n' "${rows[@]}"
echo "mutants-table-end"
exit "$status"
