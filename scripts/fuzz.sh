#!/usr/bin/env bash
# scripts/fuzz.sh: builds the libFuzzer targets (clang, ASan + UBSan, build/fuzz) and runs
# each for a bounded time. Not part of CI; `ladarvr bench fuzz` and `bench all` call it.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]      (inside the root: ./ladarvr shell -c ...)
#
# SECONDS per target (default 600); targets default to all (fuzz_scene_json,
# fuzz_cloud_reader, fuzz_view_script, fuzz_las_reader, fuzz_copc_reader, fuzz_las_crs,
# fuzz_detect_model, fuzz_view_replay, fuzz_candidates_file, fuzz_study_file,
# fuzz_study_report). Targets run as many at a time as the machine has cores
# (LADARVR_FUZZ_JOBS overrides), each a single libFuzzer process held to
# -rss_limit_mb=2048 (the whole process, ASan included) and -malloc_limit_mb=512 (one
# allocation); going over either is reported as a crash (oom-*). The working corpus
# lives in build/fuzz/corpus/<target> (seeded from fuzz/seeds and the test data, kept
# between runs); crashes land in build/fuzz/artifacts/<target>/ and make the script
# exit 1. When all targets are done, one line per target, in the order given:
# "fuzz: <target> seconds=S runs=N corpus=C cov=V crashes=K rc=R", S the seconds it ran
# (SECONDS, or fewer where it stopped at a crash).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_scene_json fuzz_cloud_reader fuzz_view_script fuzz_las_reader fuzz_copc_reader fuzz_las_crs fuzz_detect_model fuzz_view_replay fuzz_candidates_file fuzz_study_file fuzz_study_report)
build="${LADARVR_FUZZ_BUILD:-$repo/build/fuzz}"
rss_limit_mb=2048
malloc_limit_mb=512
jobs=${LADARVR_FUZZ_JOBS:-$(nproc)}
[[ $jobs =~ ^[1-9][0-9]*$ ]] || { echo "fuzz: LADARVR_FUZZ_JOBS='$jobs': allowed a whole number >= 1" >&2; exit 2; }
[[ $seconds =~ ^[1-9][0-9]*$ ]] || { echo "fuzz: SECONDS='$seconds': allowed a whole number >= 1" >&2; exit 2; }

for t in "${targets[@]}"; do
  case $t in
    fuzz_scene_json|fuzz_cloud_reader|fuzz_view_script|fuzz_las_reader|fuzz_copc_reader|fuzz_las_crs|fuzz_detect_model|fuzz_view_replay|fuzz_candidates_file|fuzz_study_file|fuzz_study_report) ;;
    *) echo "fuzz: unknown target '$t'; allowed: fuzz_scene_json, fuzz_cloud_reader, fuzz_view_script, fuzz_las_reader, fuzz_copc_reader, fuzz_las_crs, fuzz_detect_model, fuzz_view_replay, fuzz_candidates_file, fuzz_study_file, fuzz_study_report" >&2; exit 2 ;;
  esac
done
command -v clang++ >/dev/null || { echo "fuzz: clang++ is missing (apt-get install clang libclang-rt-dev)" >&2; exit 2; }
if [ ! -f "$build/build.ninja" ]; then
  CC=clang CXX=clang++ cmake -S "$repo" -B "$build" -G Ninja -DLADARVR_FUZZ=ON \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLADARVR_BUILD_TESTS=OFF >/dev/null
fi
cmake --build "$build" --target "${targets[@]}" >/dev/null

# Runs target $1 and writes its summary line to $build/$1.result.
run_one() {
  local t=$1 corpus="$build/corpus/$1" artifacts="$build/artifacts/$1" log="$build/$1.log"
  local seeds dict max_len rc runs cov crashes
  mkdir -p "$corpus" "$artifacts"
  case $t in
    fuzz_scene_json)
      seeds=("$repo"/fuzz/seeds/scene/* "$repo"/tests/data/scenes/bad/*.json "$repo"/tests/data/scenes/basic/scene.json
             "$repo"/tests/data/io/fuzz_regressions/*.json)
      dict="$repo/fuzz/scene.dict"; max_len=2048 ;;
    fuzz_cloud_reader)
      seeds=("$repo"/fuzz/seeds/cloud/* "$repo"/tests/data/io/*.pcd "$repo"/tests/data/io/fuzz_regressions/*.pcd
             "$repo"/assets/common/*.ply)
      dict="$repo/fuzz/cloud.dict"; max_len=16384 ;;
    fuzz_view_script)
      seeds=("$repo"/fuzz/seeds/script/*)
      dict="$repo/fuzz/script.dict"; max_len=4096 ;;
    fuzz_las_reader)
      seeds=("$repo"/fuzz/seeds/las/*)
      dict="$repo/fuzz/las.dict"; max_len=16384 ;;
    fuzz_copc_reader)
      seeds=("$repo"/fuzz/seeds/copc/*)
      dict="$repo/fuzz/las.dict"; max_len=65536 ;;
    fuzz_las_crs)
      seeds=("$repo"/fuzz/seeds/las_crs/*)
      dict="$repo/fuzz/crs.dict"; max_len=4096 ;;
    fuzz_detect_model)
      # The shipped model (155 KB) is cut at max_len; the small seeds cover its structure.
      seeds=("$repo"/fuzz/seeds/model/*)
      dict="$repo/fuzz/model.dict"; max_len=8192 ;;
    fuzz_view_replay)
      seeds=("$repo"/fuzz/seeds/replay/*)
      dict="$repo/fuzz/replay.dict"; max_len=4096 ;;
    fuzz_candidates_file)
      seeds=("$repo"/fuzz/seeds/candidates/*)
      dict="$repo/fuzz/candidates.dict"; max_len=4096 ;;
    fuzz_study_file)
      seeds=("$repo"/fuzz/seeds/study/*)
      dict="$repo/fuzz/study.dict"; max_len=4096 ;;
    fuzz_study_report)
      seeds=("$repo"/fuzz/seeds/study_report/*)
      dict="$repo/fuzz/study_report.dict"; max_len=4096 ;;
  esac
  # A seed replaces its earlier copy, so a seed remade since the last run (the shipped
  # model retrained, its cuts remade) is fuzzed as it is now, not as it was.
  for s in "${seeds[@]}"; do [ -f "$s" ] && cp "$s" "$corpus/" 2>/dev/null || true; done
  local started=$SECONDS
  set +e
  "$build/fuzz/$t" "$corpus" -dict="$dict" -max_len=$max_len -max_total_time="$seconds" \
    -rss_limit_mb=$rss_limit_mb -malloc_limit_mb=$malloc_limit_mb -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$artifacts/" -close_fd_mask=1 >"$log" 2>&1
  rc=$?
  set -e
  local ran=$((SECONDS - started))
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -oE '(DONE|pulse|NEW|REDUCE|INITED) +cov: [0-9]+' "$log" | tail -n1 | grep -oE '[0-9]+$' || echo 0)
  crashes=$(find "$artifacts" -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
  echo "fuzz: $t seconds=$ran runs=${runs:-0} corpus=$(ls "$corpus" | wc -l) cov=${cov:-0} crashes=$crashes rc=$rc" \
    >"$build/$t.result"
  if [ $rc -ne 0 ] || [ "$crashes" -gt 0 ]; then
    grep -m3 -E 'ERROR|SUMMARY|deadly|Test unit written' "$log" >&2 || true
  fi
  echo "fuzz.sh: $t done (log $log)" >&2
}

running=0
for t in "${targets[@]}"; do
  rm -f "$build/$t.result"
  if [ $running -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
  echo "fuzz.sh: $t for $seconds s (rss limit $rss_limit_mb MB, malloc limit $malloc_limit_mb MB)" >&2
  run_one "$t" &
  running=$((running + 1))
done
wait

status=0
for t in "${targets[@]}"; do
  if [ ! -f "$build/$t.result" ]; then
    echo "fuzz: $t did not report; see $build/$t.log" >&2; status=1; continue
  fi
  line=$(cat "$build/$t.result")
  echo "$line"
  case $line in *" crashes=0 rc=0") ;; *) status=1 ;; esac
done
exit $status
