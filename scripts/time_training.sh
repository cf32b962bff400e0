#!/usr/bin/env bash
# scripts/time_training.sh: how long `ladarvr train` takes on N new items of the shipped
# model's recipe (docs/detect.md, "The trained detector"; BENCHMARKS.md, "Training time on
# 1,000 items").
#
#   scripts/time_training.sh [--items N] [--work DIR] [--jobs K]
#   scripts/time_training.sh [--items N] --specs-only DIR
#
# The SPECs are assets/detect/shipped_*.json scaled: the same scenes, sensors and vehicles,
# each SPEC's count scaled so that the counts add up to N (default 1000; largest remainders
# round, a SPEC whose share rounds to 0 is left out) and its seed plus 1000, so the items
# are new. Paths in them are absolute. --specs-only writes them to DIR and stops.
#
# Otherwise, under --work (default /tmp/ladarvr-time-training; about 14 MB an item, checked
# against the free space first): the vehicles and the real places' scenes
# (scripts/train_shipped_model.sh --scenes-to), one corpus per SPEC at nice 19 with --jobs
# (default 2) items at once, then `ladarvr train CORPORA --threads 2 --memory-mb 2048` at
# normal priority, timed (wall and CPU seconds, and peak resident memory of the largest
# process). It prints, one per line: items built and left out, the scenes' seconds, the
# corpora's seconds, train's seconds, train's peak RSS, and the load average before and
# after train. On cores shared with other work the wall time is an upper bound; the CPU
# seconds over the threads bound a quiet machine's from below.
# A rerun resumes finished corpora, so only train is timed again. The folder is kept: delete
# it when the figures are taken. LADARVR names the ladarvr command (default ./ladarvr).
set -euo pipefail
export LC_ALL=C
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
items=1000
work=/tmp/ladarvr-time-training
jobs=2
specs_only=
usage="usage: scripts/time_training.sh [--items N] [--work DIR] [--jobs K] | [--items N] --specs-only DIR"
value() {
    if [ "$1" -lt 2 ] || [ -z "$2" ]; then echo "time_training: $3 needs a value; $usage" >&2; exit 2; fi
}
while [ $# -gt 0 ]; do
    case "$1" in
        --items) value $# "${2-}" "$1"; items=$2; shift 2 ;;
        --work) value $# "${2-}" "$1"; work=$2; shift 2 ;;
        --jobs) value $# "${2-}" "$1"; jobs=$2; shift 2 ;;
        --specs-only) value $# "${2-}" "$1"; specs_only=$2; shift 2 ;;
        -h|--help) echo "$usage"; exit 0 ;;
        *) echo "time_training: unknown argument '$1'; $usage" >&2; exit 2 ;;
    esac
done
if ! [[ $items =~ ^[1-9][0-9]{0,5}$ ]] || [ "$items" -gt 100000 ]; then
    echo "time_training: --items '$items': allowed a whole number 1..100000" >&2
    exit 2
fi
[[ $jobs =~ ^[1-9][0-9]?$ ]] || { echo "time_training: --jobs '$jobs': allowed a whole number 1..99" >&2; exit 2; }
ladarvr=${LADARVR:-"$repo/ladarvr"}
work=$(realpath -m -- "$work")
generated="$work/generated"

# writeSpecs DIR: the scaled SPECs, each written to a temporary name and renamed.
writeSpecs() {
    python3 - "$repo/assets/detect" "$generated" "$items" "$1" <<'EOF'
import glob, json, os, sys
detect, generated, items, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
paths = sorted(glob.glob(os.path.join(detect, "shipped_*.json")))
specs = [json.load(open(p)) for p in paths]
total = sum(s["count"] for s in specs)
# Largest remainders: floor shares, then one more to the largest fractions (ties by order).
shares = [s["count"] * items / total for s in specs]
counts = [int(x) for x in shares]
for i in sorted(range(len(specs)), key=lambda i: (counts[i] - shares[i], i))[: items - sum(counts)]:
    counts[i] += 1

def place(rel):
    if rel.startswith("generated/"):
        return os.path.join(generated, rel[len("generated/"):])
    return os.path.normpath(os.path.join(detect, rel))

os.makedirs(out, exist_ok=True)
for path, spec, count in zip(paths, specs, counts):
    if count == 0:
        continue
    spec["comment"] = "%s scaled by scripts/time_training.sh to %d items with seed %d: %s" % (
        os.path.basename(path), count, spec.get("seed", 0) + 1000, spec.get("comment", ""))
    spec["count"] = count
    spec["seed"] = spec.get("seed", 0) + 1000
    spec["scene"] = place(spec["scene"])
    spec["vary"]["target_files"] = [dict(f, file=place(f["file"])) if isinstance(f, dict) else place(f)
                                    for f in spec["vary"]["target_files"]]
    dest = os.path.join(out, os.path.basename(path))
    with open(dest + ".tmp", "w") as f:
        json.dump(spec, f, indent=2, sort_keys=True)
        f.write("\n")
    os.replace(dest + ".tmp", dest)
EOF
}

if [ -n "$specs_only" ]; then
    writeSpecs "$(realpath -m -- "$specs_only")"
    exit 0
fi

# Disk: about 14 MB an item, less what an earlier run left.
mkdir -p "$work"
need_mb=$((items * 15 - $(du -sm "$work" | cut -f1)))
free_mb=$(df -Pm "$work" | awk 'NR == 2 {print $4}')
[ "$free_mb" -ge "$need_mb" ] ||
    { echo "time_training: $work: $free_mb MB free, $need_mb MB needed for $items items; allowed --items up to $((free_mb / 15))" >&2; exit 1; }
writeSpecs "$work/specs"

# 1. The vehicles and real places, by the shipped recipe's own steps.
start=$(date +%s)
bash "$repo/scripts/train_shipped_model.sh" --scenes-to "$generated" 2>"$work/scenes.log" ||
    { tail -5 "$work/scenes.log" >&2; echo "time_training: the scenes failed; log $work/scenes.log" >&2; exit 1; }
scenes_s=$(($(date +%s) - start))

# 2. Corpora at nice 19. An item without room for its target is left out (corpus exit 1
#    naming only such items), as in the shipped recipe; any other failure stops.
start=$(date +%s)
corpora=()
built=0
left_out=0
for spec in "$work"/specs/shipped_*.json; do
    name=$(basename "$spec" .json)
    log="$work/$name.log"
    rc=0
    nice -n 19 "$ladarvr" corpus "$spec" --out "$work/$name" --jobs "$jobs" --threads 1 2>"$log" || rc=$?
    failed=$(grep -E '^corpus: \[[0-9]+/[0-9]+\] item [0-9]+: ' "$log" || true)
    if [ "$rc" -ne 0 ]; then
        if [ "$rc" -ne 1 ] || [ -z "$failed" ] || printf '%s\n' "$failed" | grep -qv 'the target cannot be placed'; then
            tail -5 "$log" >&2
            echo "time_training: corpus $spec failed (exit $rc); its log is $log" >&2
            exit 1
        fi
        left_out=$((left_out + $(printf '%s\n' "$failed" | wc -l)))
    fi
    built=$((built + $(wc -l <"$work/$name/manifest.jsonl")))
    corpora+=("$work/$name")
done
corpus_s=$(($(date +%s) - start))

# 3. Train at normal priority, timed by a parent that reads its children's peak RSS (the
#    kernel carries each waited-for descendant's peak up to its parent).
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
python3 - "$work/train.time" "$ladarvr" train "${corpora[@]}" --out "$work/model.ldm" --threads 2 \
    --memory-mb 2048 2>"$work/train.log" <<'EOF' || { tail -5 "$work/train.log" >&2; echo "time_training: train failed; log $work/train.log" >&2; exit 1; }
import resource, subprocess, sys, time
start = time.monotonic()
rc = subprocess.call(sys.argv[2:])
wall_s = time.monotonic() - start
with open(sys.argv[1], "w") as f:
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    f.write("%.1f %.1f %d\n" % (wall_s, use.ru_utime + use.ru_stime, use.ru_maxrss // 1024))
sys.exit(rc)
EOF
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
read -r train_s train_cpu_s peak_mb <"$work/train.time"

echo "items: $built built, $left_out left out (asked $items)"
echo "scenes: $scenes_s s"
echo "corpus build: $corpus_s s (nice 19, --jobs $jobs)"
echo "train: $train_s s, $train_cpu_s CPU s (--threads 2 --memory-mb 2048)"
echo "train peak RSS: $peak_mb MiB"
echo "load average before train: $load_before; after: $load_after"
