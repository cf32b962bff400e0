#!/usr/bin/env bash
# scripts/fuzz.sh: builds the libFuzzer targets (clang, ASan + UBSan, build/fuzz) and runs
# each for a bounded time. Not part of CI; `ladarvr bench fuzz` and `bench all` call it.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]      (inside the root: ./ladarvr shell -c ...)
#
# SECONDS per target (default 60); targets default to all (fuzz_scene_json,
# fuzz_cloud_reader). The working corpus lives in build/fuzz/corpus/<target> (seeded
# from fuzz/seeds and the test data, kept between runs); crashes land in
# build/fuzz/artifacts/<target>/ and make the script exit 1. The last line of each run
# is "fuzz: <target> seconds=S runs=N corpus=C cov=V crashes=K".
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_scene_json fuzz_cloud_reader)
build="${LADARVR_FUZZ_BUILD:-$repo/build/fuzz}"

command -v clang++ >/dev/null || { echo "fuzz: clang++ is missing (apt-get install clang libclang-rt-dev)" >&2; exit 2; }
if [ ! -f "$build/build.ninja" ]; then
  CC=clang CXX=clang++ cmake -S "$repo" -B "$build" -G Ninja -DLADARVR_FUZZ=ON \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLADARVR_BUILD_TESTS=OFF >/dev/null
fi
cmake --build "$build" --target "${targets[@]}" >/dev/null

status=0
for t in "${targets[@]}"; do
  corpus="$build/corpus/$t"; artifacts="$build/artifacts/$t"
  mkdir -p "$corpus" "$artifacts"
  case $t in
    fuzz_scene_json)
      seeds=("$repo"/fuzz/seeds/scene/* "$repo"/tests/data/scenes/bad/*.json "$repo"/tests/data/scenes/basic/scene.json
             "$repo"/tests/data/engine/fuzz_regressions/*.json)
      dict="$repo/fuzz/scene.dict"; max_len=2048 ;;
    fuzz_cloud_reader)
      seeds=("$repo"/fuzz/seeds/cloud/* "$repo"/tests/data/engine/*.pcd "$repo"/tests/data/engine/fuzz_regressions/*.pcd
             "$repo"/assets/common/*.ply)
      dict="$repo/fuzz/cloud.dict"; max_len=16384 ;;
    *) echo "fuzz: unknown target '$t'; allowed: fuzz_scene_json, fuzz_cloud_reader" >&2; exit 2 ;;
  esac
  for s in "${seeds[@]}"; do [ -f "$s" ] && cp -n "$s" "$corpus/" 2>/dev/null || true; done
  log="$build/$t.log"
  set +e
  "$build/fuzz/$t" "$corpus" -dict="$dict" -max_len=$max_len -max_total_time="$seconds" \
    -rss_limit_mb=2048 -malloc_limit_mb=512 -timeout=10 -print_final_stats=1 -artifact_prefix="$artifacts/" \
    -close_fd_mask=1 >"$log" 2>&1
  rc=$?
  set -e
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -oE '(DONE|pulse|NEW|REDUCE|INITED) +cov: [0-9]+' "$log" | tail -n1 | grep -oE '[0-9]+$' || echo 0)
  crashes=$(find "$artifacts" -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
  echo "fuzz: $t seconds=$seconds runs=${runs:-0} corpus=$(ls "$corpus" | wc -l) cov=${cov:-0} crashes=$crashes rc=$rc"
  if [ $rc -ne 0 ] || [ "$crashes" -gt 0 ]; then
    status=1
    grep -m3 -E 'ERROR|SUMMARY|deadly|Test unit written' "$log" >&2 || true
  fi
done
exit $status
