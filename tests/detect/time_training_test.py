#!/usr/bin/env python3
"""tests/detect/time_training_test.py: scripts/time_training.sh scales the shipped model's
SPECs and refuses bad arguments, without building anything.

    time_training_test.py REPO SCRATCH_DIR

`--specs-only` at 1000 and at 12 items: the counts add up to the items asked, each within
one of its shipped share (a SPEC whose share rounds to 0 is left out), every seed is the
shipped one plus 1000, the scenes and target files are the shipped ones made absolute (the
recipe's generated ones under the work folder), every other key is unchanged. Bad
arguments: one line on stderr naming what is allowed, exit 2, nothing written; the same for
scripts/train_shipped_model.sh --scenes-to with an empty folder.
"""

import glob
import json
import os
import shutil
import subprocess
import sys


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def place(rel, detect, generated):
    if rel.startswith("generated/"):
        return os.path.join(generated, rel[len("generated/"):])
    return os.path.normpath(os.path.join(detect, rel))


def check_specs(script, detect, scratch, items):
    out = os.path.join(scratch, "specs_%d" % items)
    work = os.path.join(scratch, "work")
    r = subprocess.run(["bash", script, "--items", str(items), "--work", work, "--specs-only", out],
                       capture_output=True, text=True, env={**os.environ, "LADARVR": "/nonexistent"})
    if r.returncode != 0:
        fail("--items %d --specs-only: exit %d, stderr %r" % (items, r.returncode, r.stderr))
    if os.path.exists(work):
        fail("--specs-only created the work folder %s" % work)
    shipped = {os.path.basename(p): json.load(open(p)) for p in glob.glob(os.path.join(detect, "shipped_*.json"))}
    total = sum(s["count"] for s in shipped.values())
    written = {os.path.basename(p): json.load(open(p)) for p in glob.glob(os.path.join(out, "*"))}
    if not set(written) <= set(shipped):
        fail("--items %d: unexpected files %s" % (items, sorted(set(written) - set(shipped))))
    counts = {name: spec["count"] for name, spec in written.items()}
    if sum(counts.values()) != items:
        fail("--items %d: the SPECs' counts add up to %d" % (items, sum(counts.values())))
    generated = os.path.join(work, "generated")
    for name, base in shipped.items():
        share = base["count"] * items / total
        count = counts.get(name, 0)
        if abs(count - share) >= 1:
            fail("--items %d: %s has %d items, its share is %.2f" % (items, name, count, share))
        if name not in written:
            continue
        if count < 1:
            fail("--items %d: %s written with count %d" % (items, name, count))
        spec = written[name]
        if spec["seed"] != base["seed"] + 1000:
            fail("--items %d: %s: seed %d, expected %d" % (items, name, spec["seed"], base["seed"] + 1000))
        if spec["scene"] != place(base["scene"], detect, generated):
            fail("--items %d: %s: scene %s" % (items, name, spec["scene"]))
        want = [dict(f, file=place(f["file"], detect, generated)) if isinstance(f, dict) else
                place(f, detect, generated) for f in base["vary"]["target_files"]]
        if spec["vary"]["target_files"] != want:
            fail("--items %d: %s: target files not the shipped ones made absolute" % (items, name))
        for f in want:
            path = f["file"] if isinstance(f, dict) else f
            if not path.startswith(generated) and not os.path.isfile(path):
                fail("--items %d: %s: target %s does not exist" % (items, name, path))
        rest = {k: v for k, v in spec.items() if k not in ("count", "seed", "scene", "vary", "comment")}
        base_rest = {k: v for k, v in base.items() if k not in ("count", "seed", "scene", "vary", "comment")}
        vary = {k: v for k, v in spec["vary"].items() if k != "target_files"}
        base_vary = {k: v for k, v in base["vary"].items() if k != "target_files"}
        if rest != base_rest or vary != base_vary:
            fail("--items %d: %s: keys other than count, seed and paths changed" % (items, name))
    return len(written)


def main():
    repo, scratch = sys.argv[1:3]
    script = os.path.join(repo, "scripts", "time_training.sh")
    detect = os.path.join(repo, "assets", "detect")
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(scratch)

    if check_specs(script, detect, scratch, 1000) != len(glob.glob(os.path.join(detect, "shipped_*.json"))):
        fail("--items 1000 left a SPEC out")
    if check_specs(script, detect, scratch, 12) != 12:
        fail("--items 12: expected twelve SPECs of one item each (the six smallest shares round to 0)")

    # Bad arguments: one line, exit 2, before any work.
    work = os.path.join(scratch, "bad_work")
    cases = ((["--bogus"], "unknown argument '--bogus'"),
             (["--items", "0"], "--items '0': allowed a whole number 1..100000"),
             (["--items", "100001"], "--items '100001': allowed a whole number 1..100000"),
             (["--items", "12x"], "--items '12x': allowed"),
             (["--jobs", "0"], "--jobs '0': allowed a whole number 1..99"),
             (["--items"], "--items needs a value"),
             (["--specs-only", ""], "--specs-only needs a value"))
    for args, want in cases:
        r = subprocess.run(["bash", script, "--work", work] + args, capture_output=True, text=True,
                           env={**os.environ, "LADARVR": "/nonexistent"})
        if r.returncode != 2 or want not in r.stderr or len(r.stderr.strip().splitlines()) != 1:
            fail("script %s: exit %d, stderr %r" % (args, r.returncode, r.stderr))
        if os.path.exists(work):
            fail("script %s: wrote %s before refusing" % (args, work))
    # The scenes step it calls: an empty folder is refused, not read as "the repository's".
    r = subprocess.run(["bash", os.path.join(repo, "scripts", "train_shipped_model.sh"), "--scenes-to", ""],
                       capture_output=True, text=True, env={**os.environ, "LADARVR": "/nonexistent"})
    if r.returncode != 2 or len(r.stderr.strip().splitlines()) != 1:
        fail("train_shipped_model.sh --scenes-to '': exit %d, stderr %r" % (r.returncode, r.stderr))
    print("OK")


if __name__ == "__main__":
    main()
