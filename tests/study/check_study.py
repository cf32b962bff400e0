#!/usr/bin/env python3
"""tests/study/check_study.py SCENARIO WORK: assertions on a headless study's files
(study_headless_test.sh): trials.csv's rows and columns, the traces, the run log."""
import csv
import json
import os
import sys

scenario, work = sys.argv[1], sys.argv[2]
out = os.path.join(work, "out")
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


TRIAL_COLUMNS = ["trial", "cloud", "decision", "designated_x", "designated_y", "designated_z",
                 "target_distance_m", "hit", "time_to_first_designation_s", "time_to_decision_s",
                 "designations", "mode_switches", "seconds_in_free_mode", "visibility_metric"]
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
        check_trace(i + 1, ends[i] - starts[i])
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
