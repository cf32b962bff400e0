#!/usr/bin/env bash
# tests/viewer/view_ooc_test.sh LADARVR: `ladarvr view` of a COPC cloud far larger than its
# RAM cache and its GPU arena, along a scripted path, headless (Xvfb, desktop mode, llvmpipe):
#   1. a cloud from `ladarvr generate` (the demo scene, 50 views: about 0.8 M points) indexed
#      by `ladarvr index` in nodes of at most 100,000 points (many nodes to come and go), viewed with --cache-mb and --gpu-mb a small fraction of what the
#      cloud takes (its points at 40 bytes in RAM, 20 on the GPU) and --upload-mb, along an
#      orbit of 2 s a turn zoomed in and out by the script: in every frame record the
#      resident bytes stay within the cache, the GPU bytes within the arena, the bytes
#      uploaded within --upload-mb, the points drawn within the point budget; the peaks in
#      "source" too; nodes leave the GPU for others and come back; the process's peak RSS
#      (VmHWM in the log) stays under 400 MiB (what llvmpipe, Xvfb's client side and the
#      viewer take with these bounds; the cloud held whole would add its points three times);
#      drawn by the compute rasterizer (--rasterizer compute), which the log records;
#   2. --upload-mb with --upload-budget is refused in one line, and so is an unknown --rasterizer;
#   3. the same cloud as plain LAZ (held whole, streamed) with a 4 MiB arena: one warning line
#      says the arena holds part of it, and the GPU bytes stay within it in every frame;
#   4. without --point-budget and with --adaptive-budget on, the budget comes from the GPU
#      class (llvmpipe: software, 3,000,000) and every frame's budget stays between the
#      adaptive floor and that ceiling; without --rasterizer, the rasterizer comes from the
#      GPU class too (software: points).
# The runs end after --frames frames (no sleeps); headless_env.sh starts and kills Xvfb.
set -euo pipefail
bin=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/ladarvr-ooctest.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

"$bin" generate --out "$work/cloud.laz" --views 50 2>"$work/generate.err" ||
  { cat "$work/generate.err" >&2; exit 1; }
"$bin" index "$work/cloud.laz" --out "$work/cloud.copc.laz" --node-points 100000 2>"$work/index.err" ||
  { cat "$work/index.err" >&2; exit 1; }
cat >"$work/path.script" <<'S'
# orbit (2 s a turn), fly in, out, in again, then the free mode
40 grab_scale 4
80 grab_scale 0.5
120 grab_scale 8
150 space
S
common=(--no-xr --width 480 --height 270 --timeout 200 --point-size 2)
status=0
"$here/headless_env.sh" --timeout 240 -- "$bin" view "$work/cloud.copc.laz" "${common[@]}" --frames 180 \
  --orbit-period 2 --orbit-radius 120 --orbit-height 60 --script "$work/path.script" \
  --cache-mb 6 --gpu-mb 2 --upload-mb 0.5 --point-budget 80000 --rasterizer compute \
  --log-json "$work/ooc.json" 2>"$work/ooc.err" || status=$?
[ "$status" = 0 ] || { cat "$work/ooc.err" >&2; echo "view_ooc_test: the run exited $status" >&2; exit 1; }

status=0
"$bin" view "$work/cloud.copc.laz" --no-xr --frames 1 --upload-mb 1 --upload-budget 5000 \
  >"$work/both.out" 2>"$work/both.err" || status=$?
[ "$status" != 0 ] || { echo "view_ooc_test: --upload-mb with --upload-budget was accepted" >&2; exit 1; }
status=0
"$bin" view "$work/cloud.copc.laz" --no-xr --frames 1 --rasterizer gl >"$work/raster.out" 2>"$work/raster.err" ||
  status=$?
[ "$status" != 0 ] || { echo "view_ooc_test: --rasterizer gl was accepted" >&2; exit 1; }

printf 'loaded+5 escape\n' >"$work/loaded.script"
status=0
"$here/headless_env.sh" --timeout 120 -- "$bin" view "$work/cloud.laz" "${common[@]}" --frames 2000 \
  --gpu-mb 4 --script "$work/loaded.script" --log-json "$work/whole.json" 2>"$work/whole.err" || status=$?
[ "$status" = 0 ] || { cat "$work/whole.err" >&2; echo "view_ooc_test: the held-whole run exited $status" >&2; exit 1; }

status=0
"$here/headless_env.sh" --timeout 120 -- "$bin" view "$work/cloud.copc.laz" "${common[@]}" --frames 20 \
  --adaptive-budget on --log-json "$work/auto.json" 2>"$work/auto.err" || status=$?
[ "$status" = 0 ] || { cat "$work/auto.err" >&2; echo "view_ooc_test: the adaptive run exited $status" >&2; exit 1; }

python3 - "$work" "$here" <<'PY'
import json, re, sys
work = sys.argv[1]
sys.path.insert(0, sys.argv[2])
from check_view_log import check, failures

MiB = 1048576
err = open(f"{work}/ooc.err").read()
m = re.search(r"is COPC: (\d+) nodes, (\d+) points", err)
check(m is not None, f"no COPC start-up line in: {err!r}")
points = int(m.group(2)) if m else 0
cache, gpu, upload, budget = 6 * MiB, 2 * MiB, MiB // 2, 80000
check(points * 40 > 4 * cache and points * 20 > 4 * gpu,
      f"{points} points is not much larger than the cache and the arena")
log = json.load(open(f"{work}/ooc.json"))
src = log.get("source", {})
check(src.get("cache_bytes") == cache, f"cache_bytes {src.get('cache_bytes')}")
check(src.get("gpu_bytes_bound") == gpu, f"gpu_bytes_bound {src.get('gpu_bytes_bound')}")
check(0 < src.get("resident_bytes_peak", 0) <= cache, f"resident_bytes_peak {src.get('resident_bytes_peak')}")
check(0 < src.get("gpu_bytes_peak", 0) <= gpu, f"gpu_bytes_peak {src.get('gpu_bytes_peak')}")
check(src.get("hierarchy_bytes", 0) > 0, f"hierarchy_bytes {src.get('hierarchy_bytes')}")
check(src.get("upload_points_per_frame") == upload // 20, f"upload_points_per_frame {src.get('upload_points_per_frame')}")
frames = log["frames"]
check(len(frames) == 180, f"{len(frames)} frame records")
for f in frames:
    s = f.get("stream", {})
    n = f["frame"]
    check(s.get("resident_bytes", -1) >= 0 and s["resident_bytes"] <= cache, f"frame {n}: resident_bytes {s.get('resident_bytes')}")
    check(s.get("gpu_bytes", -1) >= 0 and s["gpu_bytes"] <= gpu, f"frame {n}: gpu_bytes {s.get('gpu_bytes')}")
    check(s.get("upload_bytes", -1) >= 0 and s["upload_bytes"] <= upload, f"frame {n}: upload_bytes {s.get('upload_bytes')}")
    check(f["points_drawn"] <= budget, f"frame {n}: points_drawn {f['points_drawn']} over {budget}")
    check(s.get("point_budget") == budget, f"frame {n}: point_budget {s.get('point_budget')}")
check(max(f["points_drawn"] for f in frames) > 0, "no points drawn")
# The path churns the arena: GPU copies leave for others, and nodes come in over many frames.
check(src.get("gpu_nodes_evicted", 0) > 0, f"gpu_nodes_evicted {src.get('gpu_nodes_evicted')}")
check(sum(f["stream"].get("gpu_nodes_added", 0) for f in frames) == src.get("gpu_nodes_added"),
      "the frames' gpu_nodes_added do not add up to the run's")
check(sum(1 for f in frames if f["stream"].get("gpu_nodes_added", 0) > 0) > 3, "nodes were uploaded in 3 frames or fewer")
check(log.get("adaptive_budget") is False, f"adaptive_budget {log.get('adaptive_budget')} (off with --frames)")
check(log.get("point_budget_choice", {}).get("from") == "option", f"point_budget_choice {log.get('point_budget_choice')}")
check(log.get("rasterizer_choice") == {"from": "option", "rasterizer": "compute"},
      f"rasterizer_choice {log.get('rasterizer_choice')}")
hwm = log.get("vm_hwm_bytes", 0)
check(0 < hwm < 400 * MiB, f"vm_hwm_bytes {hwm} (bound 400 MiB)")

both = open(f"{work}/both.err").read().strip().splitlines()
check(len(both) == 1 and "--upload-budget" in both[0] and "--upload-mb" in both[0] and "not both" in both[0],
      f"--upload-mb with --upload-budget: {both}")
raster = open(f"{work}/raster.err").read().strip().splitlines()
check(len(raster) == 1 and raster[0].endswith("view: --rasterizer 'gl' is not one of auto, points, compute"),
      f"--rasterizer gl: {raster}")

whole_err = open(f"{work}/whole.err").read()
warnings = [l for l in whole_err.splitlines() if "warning" in l]
check(len(warnings) == 1 and "GPU arena (--gpu-mb, 4194304 bytes) holds" in warnings[0] and "the rest is not drawn" in warnings[0],
      f"held-whole warning lines: {warnings}")
whole = json.load(open(f"{work}/whole.json"))
check(whole.get("exit") == "escape", f"held-whole exit {whole.get('exit')}")
for f in whole["frames"]:
    check(f["stream"]["gpu_bytes"] <= 4 * MiB, f"held-whole frame {f['frame']}: gpu_bytes {f['stream']['gpu_bytes']}")
check(0 < whole["points_uploaded"] < points, f"held-whole points_uploaded {whole['points_uploaded']} of {points}")

auto = json.load(open(f"{work}/auto.json"))
choice = auto.get("point_budget_choice", {})
check(choice.get("from") == "gpu class" and choice.get("gpu_class") == "software" and choice.get("point_budget") == 3000000,
      f"point_budget_choice {choice}")
check(auto.get("rasterizer_choice") == {"from": "gpu class", "gpu_class": "software", "rasterizer": "points"},
      f"rasterizer_choice {auto.get('rasterizer_choice')}")
adaptive = auto.get("adaptive_budget")
check(isinstance(adaptive, dict) and adaptive.get("floor") == 375000 and adaptive.get("ceiling") == 3000000,
      f"adaptive_budget {adaptive}")
for f in auto["frames"]:
    b = f["stream"]["point_budget"]
    check(375000 <= b <= 3000000, f"adaptive frame {f['frame']}: point_budget {b}")
    check(f["points_drawn"] <= b, f"adaptive frame {f['frame']}: points_drawn {f['points_drawn']} over {b}")
for e in auto["events"]:
    if e.startswith("point budget "):
        check(re.match(r"point budget \d+ -> \d+ at frame \d+ \(frame [\d.]+ of [\d.]+ ms\)$", e) is not None, f"event {e!r}")
for f in failures:
    print("view_ooc_test:", f, file=sys.stderr)
sys.exit(1 if failures else 0)
PY
