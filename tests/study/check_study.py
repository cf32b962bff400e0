#!/usr/bin/env python3
"""tests/study/check_study.py SCENARIO WORK: assertions on a headless study's files
(study_headless_test.sh): trials.csv's rows and columns, the traces (and the convention of
their head quaternion, the one `ladarvr metric --trace` reads), the run log, and
scripts/study_summary.py on the real trials.csv."""
import csv
import json
import math
import os
import subprocess
import sys

scenario, work = sys.argv[1], sys.argv[2]
out = os.path.join(work, "out")
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


TRIAL_COLUMNS = ["trial", "cloud", "decision", "designated_x", "designated_y", "designated_z",
                 "target_distance_m", "hit", "time_to_first_designation_s", "time_to_decision_s",
                 "designations", "mode_switches", "seconds_in_free_mode", "visibility_metric",
                 "name", "candidates_shown", "designation_hit", "box_hit"]
TRACE_COLUMNS = ["t_s", "head_x", "head_y", "head_z", "head_qw", "head_qx", "head_qy", "head_qz",
                 "mode", "scale", "hit_x", "hit_y", "hit_z"]


def read_csv(name, columns):
    with open(os.path.join(out, name), newline="") as f:
        rows = list(csv.reader(f))
    check(rows and rows[0] == columns, f"{name}: header {rows[0] if rows else None}")
    return [dict(zip(columns, r)) for r in rows[1:]]


def check_trace(n, frames_expected=None):
    rows = read_csv(f"trace_{n}.csv", TRACE_COLUMNS)
    check(len(rows) >= 5, f"trace_{n}: {len(rows)} rows")
    times = [float(r["t_s"]) for r in rows]
    check(all(b > a for a, b in zip(times, times[1:])), f"trace_{n}: times do not increase: {times[:10]}")
    check(all(r["mode"] in ("automatic", "free") for r in rows), f"trace_{n}: bad mode")
    hits = [r for r in rows if r["hit_x"]]
    check(len(hits) >= 3, f"trace_{n}: the pointer hit the cloud in {len(hits)} rows")
    if frames_expected is not None:
        check(len(rows) == frames_expected, f"trace_{n}: {len(rows)} rows for {frames_expected} frames of the trial")
    print(f"trace_{n}: {len(rows)} rows, t {times[0]:.3f}..{times[-1]:.3f} s, {len(hits)} with a hit")
    return rows


def rotate(q, v):
    """v turned by the unit quaternion q = (w, x, y, z)."""
    w, x, y, z = q
    t = [2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])]
    return [v[0] + w * t[0] + (y * t[2] - z * t[1]), v[1] + w * t[1] + (z * t[0] - x * t[2]),
            v[2] + w * t[2] + (x * t[1] - y * t[0])]


def check_gaze(rows, centres):
    """Desktop, automatic mode, mouse untouched: the head looks at the orbit centre. Its gaze
    as metric/src/trace.cpp reads the quaternion (head -z turned into the world) must point
    there, and its up (head +y) must point up: a trace written in another convention fails."""
    worst, lowest_up = 0.0, 1.0
    for r, centre in zip(rows, centres):
        if r["mode"] != "automatic":
            continue
        head = [float(r[k]) for k in ("head_x", "head_y", "head_z")]
        q = [float(r[k]) for k in ("head_qw", "head_qx", "head_qy", "head_qz")]
        check(abs(math.sqrt(sum(c * c for c in q)) - 1.0) < 1e-6, f"quaternion {q} is not a unit one")
        gaze = rotate(q, (0.0, 0.0, -1.0))
        to_centre = [c - h for c, h in zip(centre, head)]
        n = math.sqrt(sum(c * c for c in to_centre))
        cos = sum(g * c for g, c in zip(gaze, to_centre)) / n
        worst = max(worst, math.degrees(math.acos(max(-1.0, min(1.0, cos)))))
        lowest_up = min(lowest_up, rotate(q, (0.0, 1.0, 0.0))[2])
    check(worst < 1.0, f"the trace's gaze is {worst:.1f} deg off the orbit centre")
    check(lowest_up > 0.5, f"the trace's head up (+y) has a world z down to {lowest_up:.3f}: not up")
    print(f"trace gaze: at most {worst:.3f} deg off the orbit centre")


def check_summary(expected_all):
    """scripts/study_summary.py reads the trials.csv the study wrote."""
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "study_summary.py")
    run = subprocess.run([sys.executable, script, out], capture_output=True, text=True)
    check(run.returncode == 0, f"study_summary exited {run.returncode}: {run.stderr}")
    last = run.stdout.strip().splitlines()[-1].split() if run.stdout.strip() else []
    check(last[:1] == ["all"] and " ".join(last[1:]) == expected_all,
          f"study_summary's last row {last}, expected all {expected_all}")
    print("study_summary:", " ".join(last))


trials = read_csv("trials.csv", TRIAL_COLUMNS) if scenario != "sigint" else []
for r in trials:
    print("trial", r["trial"], r["decision"], "distance", r["target_distance_m"], "hit", r["hit"],
          "designated", r["designated_x"], r["designated_y"], r["designated_z"])

if scenario in ("xr", "desktop"):
    check(len(trials) == 2, f"{len(trials)} rows in trials.csv, expected 2")
    if len(trials) == 2:
        a, b = trials
        check(a["decision"] == "confirm" and b["decision"] == "confirm", "decisions are not both confirm")
        check(a["hit"] == "1" and float(a["target_distance_m"]) < 1.0, f"trial 1 is no hit: {a}")
        check(b["hit"] == "0" and float(b["target_distance_m"]) > 1.0, f"trial 2 is a hit: {b}")
        # Trial 2's designation is on the house or what stands before it, metres from the tank.
        check(abs(float(b["designated_x"])) > 5.0, f"trial 2 designated near the tank: {b}")
        for r in trials:
            check(r["designations"] == "1", f"trial {r['trial']}: {r['designations']} designations")
            check(float(r["time_to_first_designation_s"]) <= float(r["time_to_decision_s"]), "times out of order")
            check(r["visibility_metric"] == "", "visibility_metric given with --no-metric")
        # The plan's names, and trial 1's three candidate boxes (trial 2 has none).
        check([(r["name"], r["candidates_shown"]) for r in trials] == [("demo A", "3"), ("demo B", "0")],
              f"names and candidates shown: {[(r['name'], r['candidates_shown']) for r in trials]}")
    cands = read_csv("candidates.csv", ["trial", "candidate", "score", "verdict", "t_s"])
    verdicts = {(r["trial"], r["candidate"]): r["verdict"] for r in cands}
    print("candidates:", verdicts)
    check(verdicts == {("1", "house"): "rejected", ("1", "tank"): "confirmed", ("1", "far"): "unreviewed"},
          f"candidate verdicts {verdicts}")
    with open(os.path.join(work, "log.json")) as f:
        log = json.load(f)
    check(log["exit"] == "trials done", f"exit {log['exit']}")
    if scenario == "xr":
        check(log.get("fallback") == "" and log["frames_submitted"] == log["frames_counted"] > 0,
          "the XR session did not last the run")
        check("FOCUSED" in log["states"], "never FOCUSED")
        check(log.get("headset_panel") is True, "the panel was not drawn in the headset")
    starts = [a["frame"] for a in log["actions"] if a["action"] == "start"]
    ends = [a["frame"] for a in log["actions"] if a["action"] == "end"]
    check(len(starts) == 2 and len(ends) == 2, f"starts {starts}, ends {ends}")
    for i in range(min(len(starts), len(ends))):
        # One trace row per counted frame from the start (exclusive) to the end (inclusive).
        rows = check_trace(i + 1, ends[i] - starts[i])
        if scenario == "desktop" and i == 0:
            # Row k of the trace is frame starts + 1 + k; its orbit centre (the cloud's bounds
            # centre, local frame) from the run log. Both trials show the same scene, so the
            # run's origin is trial 1's.
            by_frame = {f["frame"]: f["orbit_centre_local"] for f in log["frames"]}
            centres = [by_frame.get(starts[0] + 1 + k) for k in range(len(rows))]
            check(all(c is not None for c in centres), "trace rows without a frame in the run log")
            if all(c is not None for c in centres):
                check_gaze(rows, [[c[k] + log["origin"][k] for k in range(3)] for c in centres])
    # Trial 1 a hit, trial 2 a miss, both confirmed.
    if len(trials) == 2:
        median = sum(float(r["time_to_decision_s"]) for r in trials) / 2
        check_summary("2 2 0 0 0.50 (1/2) %.1f" % median)
if scenario == "desktop":
    with open(os.path.join(work, "replay.json")) as f:
        replay = json.load(f)
    check(replay["exit"] == "replay done", f"replay exit {replay['exit']}")
    origin = replay["origin"]
    trace = read_csv("trace_1.csv", TRACE_COLUMNS)
    heads = [(float(r["head_x"]), float(r["head_y"]), float(r["head_z"])) for r in trace]
    shown = [tuple(f["eyes_local"][0]["position"][i] + origin[i] for i in range(3)) for f in replay["frames"]]
    # Once loaded, every frame shows one of the trace's heads, and the last frame the last one.
    on_trace = [p for p in shown if any(max(abs(p[i] - h[i]) for i in range(3)) < 1e-6 for h in heads)]
    check(len(on_trace) >= 2, f"{len(on_trace)} replay frames at the trace's head poses")
    check(shown and max(abs(shown[-1][i] - heads[-1][i]) for i in range(3)) < 1e-6, "the replay did not end on the last sample")
    print(f"replay: {len(replay['frames'])} frames, {len(on_trace)} at the trace's head poses")
elif scenario == "kill":
    check(len(trials) == 1, f"{len(trials)} rows after the kill, expected 1")
    check(trials and trials[0]["hit"] == "1", "trial 1 is no hit")
    leftovers = [n for n in os.listdir(out) if n.startswith(".ladarvr-tmp")]
    check(not leftovers, f"temporaries left: {leftovers}")
elif scenario == "sigterm":
    check(len(trials) == 2, f"{len(trials)} rows, expected 2")
    if len(trials) == 2:
        check(trials[1]["decision"] == "quit", f"trial 2: {trials[1]['decision']}")
        # The quit trial has hit 0 (a cloud with a target, no designation) and is left out of
        # the hit rate; it is not decided either.
        check(trials[1]["hit"] == "0" and trials[1]["target_distance_m"] == "", f"trial 2: {trials[1]}")
        check_summary("2 1 0 1 1.00 (1/1) %.1f" % float(trials[0]["time_to_decision_s"]))
    with open(os.path.join(work, "log.json")) as f:
        log = json.load(f)
    check(log["exit"] == "SIGTERM", f"exit {log['exit']}")
elif scenario == "sigint":
    with open(os.path.join(work, "log.json")) as f:
        log = json.load(f)
    check(log["exit"] == "SIGINT", f"exit {log['exit']}")
    check(log["frames_counted"] > 0, "no frame counted")

if failures:
    for f in failures:
        print("FAIL:", f)
    sys.exit(1)
print("PASS")
