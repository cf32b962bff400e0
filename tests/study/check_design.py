#!/usr/bin/env python3
"""tests/study/check_design.py SCENARIO WORK: assertions on the folders of
study_design_test.sh: trials.csv's design columns against the Williams square computed
here, study.json, each trial's colours in the run log, the breaks, the candidates per
condition; and for resume, the resumed folder against the uninterrupted one."""
import csv
import hashlib
import json
import os
import sys

scenario, work = sys.argv[1], sys.argv[2]
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


OLD_COLUMNS = ["trial", "cloud", "decision", "designated_x", "designated_y", "designated_z",
               "target_distance_m", "hit", "time_to_first_designation_s", "time_to_decision_s",
               "designations", "mode_switches", "seconds_in_free_mode", "visibility_metric"]
COLUMNS = OLD_COLUMNS + ["participant", "condition", "block", "practice", "name", "candidates_shown",
                         "designation_hit", "box_hit"]
CONDITIONS = ["heightedl", "white", "label"]
COLOUR = {"heightedl": "height", "white": "white", "label": "label"}
CANDIDATES = {"heightedl": True, "white": False, "label": False}


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [dict(zip(rows[0], r)) for r in rows[1:]]


def williams_row(n, r):
    """Williams (1949): the first row 0, 1, n-1, 2, n-2, ..., row r adds r mod n; an odd
    n's rows n..2n-1 are the first n reversed."""
    first, lo, hi = [0], 1, n - 1
    for k in range(1, n):
        if k % 2 == 1:
            first.append(lo); lo += 1
        else:
            first.append(hi); hi -= 1
    row = [(c + r) % n for c in first]
    return row if r < n else list(reversed([(c + r - n) % n for c in first]))


def expected_session(index):
    order = [CONDITIONS[c] for c in williams_row(3, index)]
    trials = []
    for c in order:
        trials.append((c, "", "1"))
        trials.append((c, "first", "0"))
        trials.append((c, "second", "0"))
    return order, trials


def check_folder(folder, participant, index, log=None):
    header, rows = read_csv(os.path.join(folder, "trials.csv"))
    check(header == COLUMNS, f"{folder}: header {header}")
    order, trials = expected_session(index)
    check(len(rows) == len(trials), f"{folder}: {len(rows)} rows, expected {len(trials)}")
    for n, (row, (condition, block, practice)) in enumerate(zip(rows, trials), 1):
        got = (row["trial"], row["participant"], row["condition"], row["block"], row["practice"])
        check(got == (str(n), participant, condition, block, practice), f"{folder}: trial {n}: {got}")
        # The design's trial names; the two candidate boxes where the condition shows them
        # (the practice trial has none).
        shown = (row["name"], row["candidates_shown"])
        want_shown = ({"": "practice", "first": "one", "second": "two"}[block],
                      "2" if CANDIDATES[condition] and block else "0")
        check(shown == want_shown, f"{folder}: trial {n}: name and candidates shown {shown}, expected {want_shown}")
        check(row["decision"] == "confirm" and row["hit"] == "1", f"{folder}: trial {n}: {row['decision']} hit {row['hit']}")
        # The label condition starts in free mode; that is not one of the operator's switches.
        check(row["mode_switches"] == "0", f"{folder}: trial {n}: {row['mode_switches']} mode switches")
        free_s = float(row["seconds_in_free_mode"])
        check((free_s > 0) == (condition == "label"), f"{folder}: trial {n} ({condition}): {free_s} s in free mode")
    study = json.load(open(os.path.join(folder, "study.json")))
    sha = hashlib.sha256(open(os.path.join(work, "design.json"), "rb").read()).hexdigest()
    check(study["design_sha256"] == sha, f"{folder}: study.json's SHA-256 {study['design_sha256']}")
    check(study["participant"] == participant, f"{folder}: study.json participant {study['participant']}")
    check(study["condition_order"] == order, f"{folder}: study.json condition_order {study['condition_order']}")
    check(study["order"] == list(range(len(trials))), f"{folder}: study.json order {study['order']}")
    # Verdicts only for the trials whose condition shows the candidates: one trial of each
    # block confirms the tank's box, the far box stays unreviewed.
    _, cands = read_csv(os.path.join(folder, "candidates.csv"))
    want = []
    for n, (condition, block, practice) in enumerate(trials, 1):
        if CANDIDATES[condition] and block:
            want += [(str(n), "tank", "confirmed"), (str(n), "far", "unreviewed")]
    got = [(r["trial"], r["candidate"], r["verdict"]) for r in cands]
    check(got == want, f"{folder}: candidates {got}, expected {want}")
    for n in range(1, len(trials) + 1):
        check(os.path.exists(os.path.join(folder, f"trace_{n}.csv")), f"{folder}: no trace_{n}.csv")
    if log:
        frames = json.load(open(log))["frames"]
        for n, (condition, _, _) in enumerate(trials, 1):
            colours = {f["colour"] for f in frames if f.get("trial") == n - 1}
            check(colours == {COLOUR[condition]}, f"{log}: trial {n} ({condition}) drawn in {colours}")
        switches = json.load(open(log)).get("mode_switches", [])
        labels = sum(1 for condition, _, _ in trials if condition == "label")
        check([(s["from"], s["to"], s["source"]) for s in switches] == [("automatic", "free", "condition")] * labels,
              f"{log}: mode switches {switches}")
        starts = [a for a in json.load(open(log))["actions"] if a.get("action") == "start"]
        check(len(starts) == len(trials), f"{log}: {len(starts)} starts")
        for a in starts:
            first_of_later_condition = a["trial"] in (3, 6)
            check(("ready_screen_s" in a) == first_of_later_condition, f"{log}: start {a}")
            if "ready_screen_s" in a:
                check(a["ready_screen_s"] >= 0.5, f"{log}: the break lasted {a['ready_screen_s']} s < 0.5 s")
    print(f"{folder}: {participant}: {order}, {len(rows)} trials")
    return rows


# The SSQ's symptoms in Kennedy et al.'s (1993) order and its clusters (N nausea, O
# oculomotor, D disorientation), written out here from the paper's table.
SSQ = [("general_discomfort", "NO"), ("fatigue", "O"), ("headache", "O"), ("eyestrain", "O"),
       ("difficulty_focusing", "OD"), ("salivation_increasing", "N"), ("sweating", "N"), ("nausea", "ND"),
       ("difficulty_concentrating", "NO"), ("fullness_of_head", "D"), ("blurred_vision", "OD"),
       ("dizziness_eyes_open", "D"), ("dizziness_eyes_closed", "D"), ("vertigo", "D"),
       ("stomach_awareness", "N"), ("burping", "N")]

if scenario == "run":
    check_folder(os.path.join(work, "P01"), "P01", 0, os.path.join(work, "P01.log.json"))
    check_folder(os.path.join(work, "P02"), "P02", 1, os.path.join(work, "P02.log.json"))
elif scenario == "resume":
    whole = check_folder(os.path.join(work, "whole"), "P01", 0, os.path.join(work, "whole.log.json"))
    resumed = check_folder(os.path.join(work, "resumed"), "P01", 0)
    timed = {"time_to_first_designation_s", "time_to_decision_s", "seconds_in_free_mode"}
    for a, b in zip(whole, resumed):
        check({k: v for k, v in a.items() if k not in timed} == {k: v for k, v in b.items() if k not in timed},
              f"resumed trial {b['trial']} differs: {a} vs {b}")
    # The three trials written before the kill are kept byte for byte.
    killed = open(os.path.join(work, "killed_trials.csv")).read().splitlines()
    now = open(os.path.join(work, "resumed", "trials.csv")).read().splitlines()
    check(now[:4] == killed, "the rows written before the kill changed")
    # Trial 4's trace is the resumed run's alone: its times start again near 0 and increase.
    with open(os.path.join(work, "resumed", "trace_4.csv")) as f:
        times = [float(line.split(",")[0]) for line in list(f)[1:]]
    check(times and times[0] < 1.0 and all(b >= a for a, b in zip(times, times[1:])), f"trace_4 times {times[:5]}")
    _, cw = read_csv(os.path.join(work, "whole", "candidates.csv"))
    _, cr = read_csv(os.path.join(work, "resumed", "candidates.csv"))
    check([(r["trial"], r["candidate"], r["verdict"]) for r in cw] == [(r["trial"], r["candidate"], r["verdict"]) for r in cr],
          "candidates.csv differs")
elif scenario == "questionnaires_xr":
    answers = json.load(open(os.path.join(work, "answers.json")))
    want = [("P01", "", "ssq", "pre", item, a) for (item, _), a in zip(SSQ, answers["pre"])]
    want.append(("P01", "", "text", "pre", "expect", ""))
    want.append(("P01", "white", "likert", "after_condition", "sure", "4"))
    want.append(("P01", "label", "likert", "after_condition", "sure", "2"))
    want += [("P01", "label", "ssq", "post", item, a) for (item, _), a in zip(SSQ, answers["post"])]
    _, rows = read_csv(os.path.join(work, "xr", "questionnaires.csv"))
    got = [(r["participant"], r["condition"], r["instrument"], r["occasion"], r["item"], r["response"]) for r in rows]
    check(got == want, f"questionnaires.csv rows:\n    {got}\n  expected\n    {want}")
    log = json.load(open(os.path.join(work, "xr.log.json")))
    check(log.get("frames_submitted", 0) > 0, f"no frame submitted to OpenXR: {log.get('frames_submitted')}")
    actions = [a for a in log["actions"] if a["action"] == "answer"]
    sources = [(a["source"], a["skipped"]) for a in actions]
    want_sources = [("pointer", False)] * 16 + [("headset", True)] + [("pointer", False)] * 18
    check(sources == want_sources, f"answers' sources {sources}")
    _, trials = read_csv(os.path.join(work, "xr", "trials.csv"))
    check([(t["condition"], t["decision"]) for t in trials] == [("white", "confirm"), ("label", "confirm")],
          f"trials.csv {trials}")
elif scenario == "questionnaires":
    TLX = ["mental", "physical", "temporal", "performance", "effort", "frustration"]
    answers = json.load(open(os.path.join(work, "answers.json")))
    want = [("P01", "", "ssq", "pre", item, a) for (item, _), a in zip(SSQ, answers["pre"])]
    for condition, sure in (("white", "4"), ("label", "2")):
        want += [("P01", condition, "tlx", "after_condition", item, a)
                 for item, a in zip(TLX, answers["tlx_" + condition])]
        want.append(("P01", condition, "likert", "after_condition", "sure", sure))
    want += [("P01", "label", "ssq", "post", item, a) for (item, _), a in zip(SSQ, answers["post"])]
    want.append(("P01", "label", "text", "post", "remarks", answers["remarks"]))
    header, rows = read_csv(os.path.join(work, "qwhole", "questionnaires.csv"))
    check(header == ["participant", "condition", "instrument", "occasion", "item", "response", "time_s"],
          f"questionnaires.csv header {header}")
    got = [(r["participant"], r["condition"], r["instrument"], r["occasion"], r["item"], r["response"]) for r in rows]
    check(got == want, f"questionnaires.csv rows:\n    {got}\n  expected\n    {want}")
    times = [float(r["time_s"]) for r in rows]
    check(times and times[0] >= 0 and all(b >= a for a, b in zip(times, times[1:])), f"time_s {times}")
    # The session's SSQ lines against the scores computed here.
    lines = open(os.path.join(work, "qwhole.ssq")).read().splitlines()
    for occasion in ("pre", "post"):
        ratings = [int(a) for a in answers[occasion]]
        raw = {c: sum(r for (_, cl), r in zip(SSQ, ratings) if c in cl) for c in "NOD"}
        expected = (f"ladarvr: study: SSQ {occasion}: nausea {raw['N'] * 9.54:.2f}, oculomotor {raw['O'] * 7.58:.2f}, "
                    f"disorientation {raw['D'] * 13.92:.2f}, total {(raw['N'] + raw['O'] + raw['D']) * 3.74:.2f}")
        check(expected in lines, f"no line '{expected}' in {lines}")
        print(expected)
    actions = [a for a in json.load(open(os.path.join(work, "qwhole.log.json")))["actions"] if a["action"] == "answer"]
    check(len(actions) == 47 and all(a["source"] == "script" and not a["skipped"] for a in actions),
          f"{len(actions)} answer actions in the run log, expected 47 from the script")
    # The killed and resumed session: the 35 rows written before the kill kept byte for
    # byte, then the rest as the uninterrupted run's (times aside); trials.csv likewise.
    killed = open(os.path.join(work, "qkilled.csv")).read().splitlines()
    resumed = open(os.path.join(work, "qresumed", "questionnaires.csv")).read().splitlines()
    check(len(killed) == 36, f"the killed run wrote {len(killed) - 1} answers, expected 35")
    check(resumed[:36] == killed, "the answers written before the kill changed")
    _, rrows = read_csv(os.path.join(work, "qresumed", "questionnaires.csv"))
    got = [(r["participant"], r["condition"], r["instrument"], r["occasion"], r["item"], r["response"]) for r in rrows]
    check(got == want, f"resumed questionnaires.csv rows differ: {got}")
    timed = {"time_to_first_designation_s", "time_to_decision_s", "seconds_in_free_mode"}
    _, tw = read_csv(os.path.join(work, "qwhole", "trials.csv"))
    _, tr = read_csv(os.path.join(work, "qresumed", "trials.csv"))
    check(len(tw) == 2 and [{k: v for k, v in r.items() if k not in timed} for r in tw] ==
          [{k: v for k, v in r.items() if k not in timed} for r in tr], f"trials.csv differs: {tw} vs {tr}")
    check(open(os.path.join(work, "qresumed.ssq")).read() == open(os.path.join(work, "qwhole.ssq")).read(),
          "the resumed session's SSQ scores differ")
if scenario == "detector":
    # Each condition's candidates are what `ladarvr detect` finds in the trial's cloud with
    # that condition's detector; the tank's box, first, is confirmed in both trials.
    _, trials = read_csv(os.path.join(work, "det", "trials.csv"))
    _, cands = read_csv(os.path.join(work, "det", "candidates.csv"))
    check([r["condition"] for r in trials] == ["atr", "base"], f"conditions {[r['condition'] for r in trials]}")
    for n, name in ((1, "atr"), (2, "base")):
        want = [c["id"] for c in json.load(open(os.path.join(work, name + ".json")))["candidates"]]
        rows = [r for r in cands if r["trial"] == str(n)]
        check([r["candidate"] for r in rows] == want, f"trial {n} ({name}): candidates {[r['candidate'] for r in rows]}, detect gives {want}")
        check(trials[n - 1]["candidates_shown"] == str(len(want)),
              f"trial {n} ({name}): candidates_shown {trials[n - 1]['candidates_shown']}, detect gives {len(want)}")
        check(bool(rows) and rows[0]["verdict"] == "confirmed", f"trial {n} ({name}): c1 not confirmed: {rows[:1]}")
    lines = [l for l in open(os.path.join(work, "det.err")) if "detecting candidates" in l]
    check(len(lines) == 2, f"{len(lines)} detector runs, expected one per detector: {lines}")
if scenario == "tools":
    _, trials = read_csv(os.path.join(work, "tools", "trials.csv"))
    check([r["condition"] for r in trials] == ["all", "none"], f"conditions {[r['condition'] for r in trials]}")
    log = json.load(open(os.path.join(work, "tools.log.json")))
    for n, want in ((0, 2.0), (1, 1.0)):
        scales = {round(f["scale"], 6) for f in log["frames"] if f.get("trial") == n and "scale" in f}
        check(max(scales, default=0) == want, f"trial {n + 1}: scales {sorted(scales)}, expected at most {want}")
    grabs = [a for a in log["actions"] if a.get("action") == "grab_scale"]
    check([a.get("trial") for a in grabs] == [0], f"grab_scale actions {grabs}")
    # The second condition turns the cutting volume on: every frame of its trial has it on.
    for n, want in ((0, {False}), (1, {True})):
        cuts = {f["cut"] for f in log["frames"] if f.get("trial") == n}
        check(cuts == want, f"trial {n + 1}: cut {sorted(cuts)}, expected {want}")
    # With --cut, the condition that sets no cut starts each trial with it on as well.
    log = json.load(open(os.path.join(work, "tools_cut.log.json")))
    for n in (0, 1):
        cuts = {f["cut"] for f in log["frames"] if f.get("trial") == n}
        check(cuts == {True}, f"--cut: trial {n + 1}: cut {sorted(cuts)}, expected on")
if failures:
    print("FAIL:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("OK")
