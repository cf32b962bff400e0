#!/usr/bin/env python3
"""tests/study/check_report.py MODE ...: the checks of study_report_test.sh.

  questionnaires RESULTS   writes a questionnaires.csv into each session folder under
                           RESULTS, in study/instruments.hpp's layout (SSQ before and after,
                           raw TLX after each condition, a Likert and a free-text answer,
                           one SSQ item answered twice).
  figures RESULTS REPORT   recomputes the report's figures from the raw CSV files, here
                           and independently (scipy for the t quantiles and the tests'
                           statistics; the exact p by walking every sign arrangement or
                           every order of each participant's ranks), and compares them with
                           REPORT/figures.json and its CSV tables.
  screenshot PNG W H       the browser's screenshot: a PNG of W x H pixels showing dark
                           text and the plots' bar colour.
"""
import csv
import itertools
import json
import math
import os
import random
import statistics
import struct
import sys
import zlib

from scipy import stats

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def finish():
    if failures:
        for f in failures[:40]:
            print("FAIL:", f)
        sys.exit(1)
    print("check_report: ok")


def sessions(results):
    return sorted(os.path.join(results, d) for d in os.listdir(results)
                  if os.path.isfile(os.path.join(results, d, "study.json")))


# Kennedy et al. (1993): the 16 symptoms, their clusters and weights, written out here
# again rather than read from the C++ table.
SSQ = {
    "general_discomfort": "NO", "fatigue": "O", "headache": "O", "eyestrain": "O",
    "difficulty_focusing": "OD", "salivation_increasing": "N", "sweating": "N", "nausea": "ND",
    "difficulty_concentrating": "NO", "fullness_of_head": "D", "blurred_vision": "OD",
    "dizziness_eyes_open": "D", "dizziness_eyes_closed": "D", "vertigo": "D",
    "stomach_awareness": "N", "burping": "N",
}
TLX = ["mental", "physical", "temporal", "performance", "effort", "frustration"]
MEASURES = ["hit_rate", "false_confirmations", "time_to_decision_s", "target_distance_m", "tlx_raw",
            "correct_rejection_rate"]


def ssq_scores(ratings):
    n = sum(r for item, r in ratings.items() if "N" in SSQ[item])
    o = sum(r for item, r in ratings.items() if "O" in SSQ[item])
    d = sum(r for item, r in ratings.items() if "D" in SSQ[item])
    return {"nausea": n * 9.54, "oculomotor": o * 7.58, "disorientation": d * 13.92, "total": (n + o + d) * 3.74}


def write_questionnaires(results):
    for folder in sessions(results):
        record = json.load(open(os.path.join(folder, "study.json")))
        p = record["participant"]
        rng = random.Random(p)
        rows = [["participant", "condition", "instrument", "occasion", "item", "response", "time_s"]]
        t = 0.0
        for occasion in ("pre", "post"):
            if occasion == "post":
                for c in record["condition_order"]:
                    for item in TLX:
                        t += 1.5
                        rows.append([p, c, "tlx", "after_condition", item, str(5 * rng.randint(0, 20)), f"{t:.6f}"])
                    rows.append([p, c, "likert", "after_condition", "confident", str(rng.randint(1, 7)), f"{t:.6f}"])
            for item in SSQ:
                t += 0.5
                rows.append([p, "", "ssq", occasion, item, str(rng.randint(0, 3)), f"{t:.6f}"])
        rows.append([p, "", "ssq", "post", "nausea", "3", f"{t + 1:.6f}"])  # corrected: the last answer counts
        rows.append([p, "", "text", "post", "comments", "dizzy, \"a bit\"\nthen fine", f"{t + 2:.6f}"])
        with open(os.path.join(folder, "questionnaires.csv"), "w", newline="") as f:
            csv.writer(f, lineterminator="\n").writerows(rows)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def mean(values):
    return sum(values) / len(values) if values else float("nan")


def quartiles(values):
    """Median and quartiles by linear interpolation between order statistics (type 7)."""
    if not values:
        return float("nan"), float("nan"), float("nan")
    if len(values) == 1:
        return values[0], values[0], values[0]
    q1, median, q3 = statistics.quantiles(values, n=4, method="inclusive")
    return median, q1, q3


def summary(values):
    n = len(values)
    median, q1, q3 = quartiles(values)
    out = {"n": n, "mean": mean(values), "sd": float("nan"), "ci95_low": float("nan"), "ci95_high": float("nan"),
           "median": median, "q1": q1, "q3": q3}
    if n >= 2:
        m = out["mean"]
        sd = math.sqrt(sum((v - m) ** 2 for v in values) / (n - 1))
        half = stats.t.ppf(0.975, n - 1) * sd / math.sqrt(n)
        out.update(sd=sd, ci95_low=m - half, ci95_high=m + half)
    return out


def midranks(values):
    return list(stats.rankdata(values))


def wilcoxon(a, b):
    """Signed-rank test of b - a: statistic, Z, rank-biserial r, and p exact over every sign
    arrangement (the e2e sessions have two participants) or from Z past 16 pairs."""
    d = [y - x for x, y in zip(a, b) if y != x]
    if not d:
        return {"n": 0, "statistic": float("nan"), "p": float("nan"), "z": float("nan"),
                "effect_size": float("nan"), "p_method": None}
    n = len(d)
    ranks = midranks([abs(v) for v in d])
    w_plus = sum(r for r, v in zip(ranks, d) if v > 0)
    total = n * (n + 1) / 2
    w = min(w_plus, total - w_plus)
    ties = sum(t ** 3 - t for t in (ranks.count(r) for r in set(ranks)))
    z = (w_plus - total / 2) / math.sqrt(n * (n + 1) * (2 * n + 1) / 24 - ties / 48)
    if n <= 16:
        at_most = sum(1 for signs in itertools.product((0, 1), repeat=n)
                      if sum(r for r, s in zip(ranks, signs) if s) <= w + 1e-9)
        p, method = min(1.0, 2 * at_most / 2 ** n), "exact"
    else:
        p, method = 2 * stats.norm.cdf(-abs(z)), "normal"
    return {"n": n, "statistic": w, "p": p, "z": z, "effect_size": (w_plus - (total - w_plus)) / total,
            "p_method": method}


def friedman_exact_p(rows):
    """P(sum of squared rank sums >= observed) over every order of every row's ranks."""
    ranks = [midranks(r) for r in rows]
    k = len(rows[0])
    observed = sum(sum(r[j] for r in ranks) ** 2 for j in range(k))
    orders = [list(itertools.permutations(r)) for r in ranks]
    total = at_least = 0
    for pick in itertools.product(*orders):
        total += 1
        if sum(sum(o[j] for o in pick) ** 2 for j in range(k)) >= observed - 1e-9:
            at_least += 1
    return at_least / total


def close(a, b, what, rel=1e-6):
    if a is None:
        a = float("nan")
    if b is None:
        b = float("nan")
    if isinstance(a, float) and math.isnan(a) or isinstance(b, float) and math.isnan(b):
        check((isinstance(a, float) and math.isnan(a)) and (isinstance(b, float) and math.isnan(b)),
              f"{what}: report {a}, expected {b}")
        return
    check(abs(a - b) <= rel * max(1.0, abs(b)), f"{what}: report {a}, expected {b}")


def check_figures(results, report):
    fig = json.load(open(os.path.join(report, "figures.json")))
    parts = []
    for folder in sessions(results):
        record = json.load(open(os.path.join(folder, "study.json")))
        trials = read_csv(os.path.join(folder, "trials.csv"))
        answers = {}
        qpath = os.path.join(folder, "questionnaires.csv")
        if os.path.exists(qpath):
            for row in read_csv(qpath):
                answers[(row["instrument"], row["occasion"], row["condition"], row["item"])] = row["response"]
        parts.append((record, trials, answers))
    parts.sort(key=lambda x: x[0]["participant"])
    conditions = sorted(parts[0][0]["condition_order"])
    check(fig["conditions"] == conditions, f"conditions {fig['conditions']} != {conditions}")
    check(fig["participants"] == [p[0]["participant"] for p in parts], "participants")
    check(len({p[0]["design_sha256"] for p in parts}) == 1, "fixture: one design")

    def cell(rows):
        rows = [r for r in rows if r["practice"] == "0"]
        scored = [r for r in rows if r["hit"] in ("0", "1") and r["decision"] != "quit"]
        decided = [r for r in rows if r["decision"] in ("confirm", "no_target")]
        dist = [float(r["target_distance_m"]) for r in rows if r["target_distance_m"] != ""]
        absent = [r for r in rows if r["hit"] == "" and r["decision"] != "quit"]
        return {
            "trials": len(rows), "scored": len(scored), "hits": sum(r["hit"] == "1" for r in scored),
            "decided": len(decided),
            "hit_rate": sum(r["hit"] == "1" for r in scored) / len(scored) if scored else float("nan"),
            "false_confirmations": float(sum(r["decision"] == "confirm" and r["hit"] != "1" for r in rows))
            if rows else float("nan"),
            "time_to_decision_s": mean([float(r["time_to_decision_s"]) for r in decided]),
            "target_distance_m": mean(dist),
            "absent": len(absent), "correct_rejections": sum(r["decision"] == "no_target" for r in absent),
            "correct_rejection_rate": sum(r["decision"] == "no_target" for r in absent) / len(absent)
            if absent else float("nan"),
        }

    cells = {}
    for record, trials, answers in parts:
        p = record["participant"]
        for c in conditions:
            x = cell([r for r in trials if r["condition"] == c])
            tlx = [answers.get(("tlx", "after_condition", c, item)) for item in TLX]
            x["tlx_raw"] = mean([int(v) for v in tlx]) if all(v is not None for v in tlx) else float("nan")
            cells[(p, c)] = x
    reported = {(c["participant"], c["condition"]): c for c in fig["cells"]}
    check(len(reported) == len(cells), "cell count")
    for key, want in cells.items():
        for name, value in want.items():
            close(reported[key][name], value, f"cell {key} {name}")

    # The raw rows themselves: the sessions must have produced the mix the scripts asked for.
    all_rows = [r for _, trials, _ in parts for r in trials if r["practice"] == "0"]
    check(any(r["decision"] == "confirm" and r["hit"] == "0" for r in all_rows), "fixture: a false confirmation")
    check(any(r["decision"] == "no_target" for r in all_rows), "fixture: a no_target decision")
    check(any(r["hit"] == "1" for r in all_rows), "fixture: a hit")

    participants = [p[0]["participant"] for p in parts]
    for measure in MEASURES:
        m = fig["measures"][measure]
        for c in conditions:
            values = [cells[(p, c)][measure] for p in participants if not math.isnan(cells[(p, c)][measure])]
            want = summary(values)
            for k, v in want.items():
                close(m["by_condition"][c][k], v, f"{measure} {c} {k}")
        complete = [[cells[(p, c)][measure] for c in conditions] for p in participants
                    if all(not math.isnan(cells[(p, c)][measure]) for c in conditions)]
        test = m["test"]
        check(test["test"] == "friedman", f"{measure}: test {test['test']}, expected friedman (3 conditions)")
        check(test["n"] == len(complete), f"{measure}: n {test['n']} != {len(complete)}")
        if len(complete) >= 2 and any(len(set(row)) > 1 for row in complete):
            r = stats.friedmanchisquare(*zip(*complete))
            close(test["statistic"], float(r.statistic), f"{measure} friedman statistic")
            close(test["effect_size"], float(r.statistic) / (len(complete) * (len(conditions) - 1)),
                  f"{measure} Kendall's W")
            check(test["effect"] == "kendall_w", f"{measure}: effect {test['effect']}")
            # Two participants, three conditions: 6^2 orders, counted exactly.
            check(test["p_method"] == "exact", f"{measure}: p_method {test['p_method']}, expected exact")
            close(test["p"], friedman_exact_p(complete), f"{measure} friedman exact p")
        else:
            close(test["p"], float("nan"), f"{measure} friedman p (nothing to test)")

    # SSQ: scores before and after, their difference, and the signed-rank test per score.
    ssq = {}
    for record, _, answers in parts:
        for occasion in ("pre", "post"):
            ratings = {item: answers.get(("ssq", occasion, "", item)) for item in SSQ}
            if all(v is not None for v in ratings.values()):
                ssq[(record["participant"], occasion)] = ssq_scores({k: int(v) for k, v in ratings.items()})
    check(len(ssq) == 2 * len(parts), "fixture: SSQ pre and post for everyone")
    reported_ssq = {s["participant"]: s for s in fig["ssq"]["participants"]}
    for score in ["nausea", "oculomotor", "disorientation", "total"]:
        pre = [ssq[(p, "pre")][score] for p in participants]
        post = [ssq[(p, "post")][score] for p in participants]
        for p, a, b in zip(participants, pre, post):
            close(reported_ssq[p]["pre"][score], a, f"ssq {p} pre {score}")
            close(reported_ssq[p]["post"][score], b, f"ssq {p} post {score}")
            close(reported_ssq[p]["difference"][score], b - a, f"ssq {p} difference {score}")
        s = fig["ssq"]["summary"][score]
        for occasion, values in (("pre", pre), ("post", post), ("difference", [b - a for a, b in zip(pre, post)])):
            for k, v in summary(values).items():
                close(s[occasion][k], v, f"ssq {score} {occasion} {k}")
        w = wilcoxon(pre, post)
        check(s["test"]["n"] == w["n"] or w["n"] == 0, f"ssq {score} test n")
        close(s["test"]["p"], w["p"], f"ssq {score} wilcoxon p")
        close(s["test"]["statistic"], w["statistic"], f"ssq {score} wilcoxon statistic")
        close(s["test"]["z"], w["z"], f"ssq {score} wilcoxon Z")
        close(s["test"]["effect_size"], w["effect_size"], f"ssq {score} rank-biserial r")
        check(s["test"]["p_method"] == w["p_method"], f"ssq {score} p_method {s['test']['p_method']}")

    # Likert answers: per question (and condition after a condition), the last answer counts.
    likert = {}
    for record, _, answers in parts:
        for (instrument, occasion, condition, item), response in answers.items():
            if instrument == "likert":
                key = (item, occasion, condition if occasion == "after_condition" else "")
                likert.setdefault(key, []).append(int(response))
    reported_likert = {(x["item"], x["occasion"], x["condition"] or ""): x for x in fig["likert"]}
    check(set(reported_likert) == set(likert), f"likert questions {sorted(reported_likert)} != {sorted(likert)}")
    check(len(likert) == len(conditions), "fixture: a Likert item after each condition")
    for key, ratings in likert.items():
        got = reported_likert.get(key, {})
        check(got.get("counts") == [ratings.count(v) for v in range(1, 12)], f"likert {key} counts")
        median, q1, q3 = quartiles(sorted(ratings))
        close(got.get("median"), median, f"likert {key} median")
        close(got.get("q1"), q1, f"likert {key} q1")
        close(got.get("q3"), q3, f"likert {key} q3")

    # Every session ran its trials: complete, none left out.
    s = fig["sessions"]
    check((s["complete"], s["partial"], s["empty"]) == (len(parts), 0, 0), f"sessions {s}")
    check([x["trials_recorded"] for x in s["list"]] == [len(p[1]) for p in parts], "sessions: trials recorded")
    check([x["trials_planned"] for x in s["list"]] == [len(p[0]["order"]) for p in parts], "sessions: planned")

    # The CSV tables say what figures.json says.
    rows = read_csv(os.path.join(report, "conditions.csv"))
    check(len(rows) == len(MEASURES) * len(conditions), "conditions.csv rows")
    for row in rows:
        want = fig["measures"][row["measure"]]["by_condition"][row["condition"]]
        for key in ("mean", "median", "q1", "q3"):
            close(float(row[key]) if row[key] else float("nan"), want[key], f"conditions.csv {row['measure']} {key}")
    tests = read_csv(os.path.join(report, "tests.csv"))
    check(list(tests[0].keys()) == ["measure", "test", "n", "k", "statistic", "df", "p", "z", "effect", "effect_size",
                                    "p_method"], "tests.csv columns")
    for row in tests:
        if row["measure"] in MEASURES:
            want = fig["measures"][row["measure"]]["test"]
            close(float(row["p"]) if row["p"] else float("nan"), want["p"], f"tests.csv {row['measure']} p")
            check(row["p_method"] == (want["p_method"] or ""), f"tests.csv {row['measure']} p_method")
    rows = read_csv(os.path.join(report, "cells.csv"))
    for row in rows:
        want = cells[(row["participant"], row["condition"])]
        close(float(row["time_to_decision_s"]) if row["time_to_decision_s"] else float("nan"),
              want["time_to_decision_s"], f"cells.csv {row['participant']} {row['condition']}")
    rows = read_csv(os.path.join(report, "clouds.csv"))
    check([r["cloud"] for r in rows] == ["demo.pcd"], "clouds.csv: the one cloud")
    every = cell(all_rows)
    close(float(rows[0]["hit_rate"]), every["hit_rate"], "clouds.csv hit_rate")
    for name in ["index.html", "time_to_decision.png", "hit_rate.png", "cloud_difficulty.png", "tests.csv",
                 "ssq.csv", "ssq_summary.csv", "participants.csv", "likert.csv"]:
        check(os.path.isfile(os.path.join(report, name)), f"{name} missing")
    html = open(os.path.join(report, "index.html")).read()
    for needle in ['src="time_to_decision.png"', 'src="hit_rate.png"', 'src="cloud_difficulty.png"']:
        check(needle in html, f"index.html lacks {needle}")
    check("http:" not in html and "https:" not in html, "index.html names an outside resource")


def decode_png(path):
    data = open(path, "rb").read()
    check(data[:8] == b"\x89PNG\r\n\x1a\n", "screenshot: not a PNG")
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace != 0:
                raise SystemExit(f"screenshot: PNG depth {depth} colour {colour} interlace {interlace}: not read here")
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return width, height, channels, rows


def check_screenshot(path, want_w, want_h):
    width, height, channels, rows = decode_png(path)
    check((width, height) == (want_w, want_h), f"screenshot {width}x{height}, expected {want_w}x{want_h}")
    dark = bar = 0
    colours = set()
    for line in rows:
        for x in range(0, len(line), channels):
            r, g, b = line[x], line[x + 1], line[x + 2]
            colours.add((r, g, b))
            if r < 90 and g < 90 and b < 90:
                dark += 1
            if abs(r - 70) <= 8 and abs(g - 130) <= 8 and abs(b - 180) <= 8:
                bar += 1
    print(f"screenshot: {width}x{height}, {len(colours)} colours, {dark} dark pixels, {bar} bar pixels")
    check(len(colours) > 20, "screenshot: blank (fewer than 20 colours)")
    check(dark > 2000, "screenshot: no text drawn")
    check(bar > 100, "screenshot: the plots' bars are not shown (images not rendered)")


mode = sys.argv[1]
if mode == "questionnaires":
    write_questionnaires(sys.argv[2])
elif mode == "figures":
    check_figures(sys.argv[2], sys.argv[3])
elif mode == "screenshot":
    check_screenshot(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
else:
    raise SystemExit(f"check_report: unknown mode {mode}")
finish()
