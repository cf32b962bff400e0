#!/usr/bin/env python3
"""Hit rate and median time to decision per cloud, from studies' trials.csv (python3 stdlib).

    python3 scripts/study_summary.py DIR/trials.csv     (or the study's output folder DIR)
    python3 scripts/study_summary.py DIR1 DIR2 ...      (several participants' studies, pooled)
    python3 scripts/study_summary.py --each DIR1 DIR2   (one table per study, in the order given)

Given several folders or files, their trials are pooled: the clouds are matched by the
cloud column's text. With --each, each folder or file is summarised on its own: its name
on a line ending in ':', its table, and a blank line between two. One row per cloud (in
order of first appearance), then one for all trials:
  trials     trials of that cloud in the file
  decided    trials the operator ended with confirm or no_target
  timeouts   trials that ran out of time; quits: ended by the experimenter (Escape, Ctrl-C)
  hit_rate   hits / trials with a hit value (1 or 0; empty when the cloud has no
             ground-truth target), quits left out (the experimenter stopped them, the
             operator did not miss); "n/a" when no trial is left
  median_s   median time_to_decision_s over the decided trials, "n/a" when none

docs/study.md explains every column of trials.csv. Exit status 2 with one line on stderr
(and nothing on stdout) for a file that is not a trials.csv (missing column, bad number,
unknown decision), a file given twice, or a command line without one (--help prints this
text on stdout, exit 0).
"""

import csv
import os
import statistics
import sys

REQUIRED = ["trial", "cloud", "decision", "hit", "time_to_decision_s"]
DECISIONS = {"confirm", "no_target", "timeout", "quit"}


def fail(message):
    print("study_summary: error: " + message, file=sys.stderr)
    sys.exit(2)


def trials_path(path):
    return os.path.join(path, "trials.csv") if os.path.isdir(path) else path


def read_trials(path):
    path = trials_path(path)
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
            header = rows[0].keys() if rows else []
    except OSError as e:
        fail("%s: %s" % (path, e.strerror))
    except (UnicodeDecodeError, csv.Error) as e:
        fail("%s: not a CSV file (%s)" % (path, e))
    if not rows:
        fail("%s: no trials (a header and one row per trial expected)" % path)
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        fail("%s: missing column %s; allowed a trials.csv written by ladarvr study" % (path, ", ".join(missing)))
    trials = []
    for line, row in enumerate(rows, start=2):
        decision = row["decision"]
        if decision not in DECISIONS:
            fail("%s: line %d, column decision: '%s' is not one of %s" % (path, line, decision, ", ".join(sorted(DECISIONS))))
        hit = row["hit"]
        if hit not in ("", "0", "1"):
            fail("%s: line %d, column hit: '%s'; allowed 1, 0 or empty" % (path, line, hit))
        try:
            seconds = float(row["time_to_decision_s"])
        except (TypeError, ValueError):
            fail("%s: line %d, column time_to_decision_s: '%s' is not a number" % (path, line, row["time_to_decision_s"]))
        if not seconds >= 0.0:
            fail("%s: line %d, column time_to_decision_s: %s; allowed seconds >= 0" % (path, line, seconds))
        trials.append({"cloud": row["cloud"], "decision": decision, "hit": None if hit == "" else int(hit),
                       "seconds": seconds})
    return trials


def summarise(trials):
    scored = [t["hit"] for t in trials if t["hit"] is not None and t["decision"] != "quit"]
    decided = [t["seconds"] for t in trials if t["decision"] in ("confirm", "no_target")]
    hit_rate = "%.2f (%d/%d)" % (sum(scored) / len(scored), sum(scored), len(scored)) if scored else "n/a"
    median = "%.1f" % statistics.median(decided) if decided else "n/a"
    return [str(len(trials)), str(len(decided)), str(sum(t["decision"] == "timeout" for t in trials)),
            str(sum(t["decision"] == "quit" for t in trials)), hit_rate, median]


def print_table(trials):
    clouds = list(dict.fromkeys(t["cloud"] for t in trials))
    table = [["cloud", "trials", "decided", "timeouts", "quits", "hit_rate", "median_s"]]
    for cloud in clouds:
        table.append([cloud] + summarise([t for t in trials if t["cloud"] == cloud]))
    table.append(["all"] + summarise(trials))
    widths = [max(len(row[k]) for row in table) for k in range(len(table[0]))]
    for row in table:
        print("  ".join(cell.ljust(w) if k == 0 else cell.rjust(w) for k, (cell, w) in enumerate(zip(row, widths))).rstrip())


def main():
    args = sys.argv[1:]
    if any(a in ("-h", "--help") for a in args):
        print(__doc__.strip())
        sys.exit(0)
    each = "--each" in args
    args = [a for a in args if a != "--each"]
    if not args:
        fail("no trials.csv given; usage: study_summary.py DIR|trials.csv [DIR|trials.csv ...] [--each] "
             "(--help for more)")
    unknown = [a for a in args if a.startswith("-")]
    if unknown:
        fail("unknown option %s; allowed -h, --help, --each, or study folders and trials.csv files" % unknown[0])
    seen = {}
    for path in args:
        key = os.path.realpath(trials_path(path))
        if key in seen:
            fail("%s: the same trials.csv as %s; allowed each study once" % (path, seen[key]))
        seen[key] = path
    # Every file is read before anything is printed, so an error leaves stdout empty.
    studies = [(path, read_trials(path)) for path in args]
    if not each:
        print_table([t for _, trials in studies for t in trials])
        return
    for i, (path, trials) in enumerate(studies):
        if i:
            print()
        print(path + ":")
        print_table(trials)


if __name__ == "__main__":
    main()
