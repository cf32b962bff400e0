#!/usr/bin/env bash
# scripts/device/view_tail.sh: the viewer's tail on a lent GPU, in one call of at most 8
# minutes: the compute rasterizer's p99 at 10^8 and 10^9 points along each bench head path
# with and without its subgroup reduction and with GL_POINTS, and the paper's cloud out of
# core against in core on the second lap (BENCHMARKS.md, "Viewer on a GPU").
#
#   scripts/device/view_tail.sh [PACK]     (PACK: scripts/device/pack_bench.sh's folder, .devpack)
#
# Run from the repository root on the lent machine, with PACK carried (the device tool's
# `carry: [".devpack"]`). Results go to $OUT (else /tmp/view_tail_out), five files:
# subgroup_test.txt (the bit-for-bit test of the subgroup path on that GPU), v1e8.md,
# v1e9.md, paper.md (the bench's tables, in the order run) and summary.txt (each step,
# its seconds, or why it was skipped). A step is skipped when the time left (of 470 s)
# is below its estimate, so the call always returns its files.
set -uo pipefail
start=$(date +%s)
budget_s=${VIEW_TAIL_BUDGET_S:-470}
pack=${1:-.devpack}
out=${OUT:-/tmp/view_tail_out}
work=/tmp/view_tail
mkdir -p "$out" "$work/copc"
summary="$out/summary.txt"
: >"$summary"
note() { echo "$*" | tee -a "$summary"; }

[ -f "$pack/bench.tar.xz" ] || { note "view_tail: $pack/bench.tar.xz missing: run scripts/device/pack_bench.sh here and carry $pack"; exit 2; }
tar -C "$work" -xJf "$pack/bench.tar.xz" || { note "view_tail: $pack/bench.tar.xz does not unpack"; exit 1; }
# The bench finds the demo scene where it was built (/work/main/assets): the same tree here.
if [ ! -e /work/main/assets ]; then mkdir -p /work && ln -sfn "$PWD" /work/main; fi
# NVIDIA's EGL vendor library, wherever the machine keeps its glvnd file.
for f in /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json /usr/share/glvnd/egl_vendor.d/10_nvidia.json; do
  if [ -f "$f" ]; then export __EGL_VENDOR_LIBRARY_FILENAMES=$f; break; fi
done
# The programs through the carried loader and libraries.
loader=("$work/pack/ld-linux-x86-64.so.2" --library-path "$work/pack/lib")
bench=("${loader[@]}" "$work/pack/bin/ladarvr-bench")
tests=("${loader[@]}" "$work/pack/bin/viewer_tests")
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | sed 's/^/gpu: /' >>"$summary"

# step NAME ESTIMATE_S LOG COMMAND...: runs COMMAND (appending to LOG) if ESTIMATE_S fits.
step() {
  local name=$1 estimate=$2 log=$3
  shift 3
  local now left
  now=$(date +%s)
  left=$((budget_s - (now - start)))
  if [ "$left" -lt "$estimate" ]; then
    note "skipped: $name (needs about ${estimate} s, ${left} s left)"
    return 0
  fi
  echo "## $name" >>"$log"
  echo "\$ $*" >>"$log"
  local t0=$(date +%s) rc=0
  timeout "$left" "$@" >>"$log" 2>&1 || rc=$?
  note "ran: $name: $(( $(date +%s) - t0 )) s, exit $rc"
}

common=(view --paths ooc --display none --no-md --eye 1440x1600 --ooc-dir "$work/copc")
synthetic=("${common[@]}" --ooc-synthetic --in-core-max 0)
step "subgroup test" 20 "$out/subgroup_test.txt" \
  "${tests[@]}" -tc='*subgroup*' -s
step "1e8 compute, subgroup on" 70 "$out/v1e8.md" \
  "${bench[@]}" "${synthetic[@]}" --ooc-points 100000000 --head-paths orbit,turn,fly-in --rasterizer compute
step "1e8 compute, subgroup off" 35 "$out/v1e8.md" \
  "${bench[@]}" "${synthetic[@]}" --ooc-points 100000000 --head-paths orbit,turn,fly-in --rasterizer compute --subgroup off
step "1e8 points" 35 "$out/v1e8.md" \
  "${bench[@]}" "${synthetic[@]}" --ooc-points 100000000 --head-paths orbit,turn,fly-in --rasterizer points
step "1e9 compute, subgroup on" 200 "$out/v1e9.md" \
  "${bench[@]}" "${synthetic[@]}" --ooc-points 1000000000 --head-paths orbit,turn,fly-in --rasterizer compute
step "1e9 compute, subgroup off" 40 "$out/v1e9.md" \
  "${bench[@]}" "${synthetic[@]}" --ooc-points 1000000000 --head-paths orbit,turn --rasterizer compute --subgroup off
step "paper cloud, ooc against in core, compute" 60 "$out/paper.md" \
  "${bench[@]}" "${common[@]}" --ooc-points 1638400 --head-paths orbit,turn,fly-in --rasterizer compute
step "1e9 points" 30 "$out/v1e9.md" \
  "${bench[@]}" "${synthetic[@]}" --ooc-points 1000000000 --head-paths orbit,turn --rasterizer points
note "total: $(( $(date +%s) - start )) s"
