#!/usr/bin/env bash
# scripts/train_shipped_model.sh: makes the shipped detector model (assets/detect/model.ldm)
# from scratch, in one command: the procedural vehicles, the real places made scenes, the
# training corpora of assets/detect/shipped_*.json and `ladarvr train` on them
# (docs/detect.md, "The trained detector").
#
#   scripts/train_shipped_model.sh [--work DIR] [--out MODEL] [--jobs K]
#   scripts/train_shipped_model.sh --scenes-to DIR
#
# --work (default /tmp/ladarvr-shipped-model) receives the corpora (about 4 GB; a rerun
# resumes them, and finished corpora are kept, so training again costs only `train`);
# --out (default assets/detect/model.ldm) the model; --jobs (default 2) the items a corpus
# builds at once. The vehicles and the real places' scenes are written under
# assets/detect/generated/ (ignored by git: the SPECs name them there). Every step runs at
# nice 19. LADARVR names the ladarvr command (default: the repository's ./ladarvr wrapper;
# inside `./ladarvr shell`, build/release/app/ladarvr). --scenes-to DIR makes only the
# vehicles and the real places' scenes (steps 1 and 2), under DIR instead of
# assets/detect/generated, and stops: scripts/time_training.sh builds its own corpora on them.
#
# The vehicles are scripts/make_vehicles.py's seed 2: `bench detect --families` evaluates
# the vehicles of seed 1, which this model never sees. The real places are the surveys of
# tests/data/real named below; any other survey there is kept for evaluation.
set -euo pipefail
export LC_ALL=C  # the SPECs and corpora in one order wherever it runs
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work=/tmp/ladarvr-shipped-model
out="$repo/assets/detect/model.ldm"
jobs=2
scenes_to=
usage="usage: scripts/train_shipped_model.sh [--work DIR] [--out MODEL] [--jobs K] | --scenes-to DIR"
while [ $# -gt 0 ]; do
    case "$1" in
        --work) [ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }; work=$2; shift 2 ;;
        --out) [ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }; out=$2; shift 2 ;;
        --jobs) [ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }; jobs=$2; shift 2 ;;
        --scenes-to) [ -n "${2-}" ] || { echo "$usage" >&2; exit 2; }; scenes_to=$2; shift 2 ;;
        -h|--help) echo "$usage"; exit 0 ;;
        *) echo "train_shipped_model: unknown argument '$1'; $usage" >&2; exit 2 ;;
    esac
done
[[ $jobs =~ ^[1-9][0-9]?$ ]] || { echo "train_shipped_model: --jobs '$jobs': allowed a whole number 1..99" >&2; exit 2; }
[ -z "$scenes_to" ] || scenes_to=$(realpath -m -- "$scenes_to")
ladarvr=${LADARVR:-"$repo/ladarvr"}
detect="$repo/assets/detect"
generated="${scenes_to:-$detect/generated}"
real="$repo/tests/data/real"
run() { nice -n 19 "$@"; }
start=$(date +%s)

# 1. Vehicles: six of each of the ten families (cars to tanks and towed guns).
run python3 "$repo/scripts/make_vehicles.py" --out "$generated/vehicles" --per-family 6 --seed 2

# 2. Real places: each survey's ground as terrain, its other points as 0.5 m boxes, a
#    vehicle on a free spot (the corpus moves it and replaces it by its own targets). The
#    4_6 tile is wooded nearly throughout: a car finds a spot there only without clearance.
run "$ladarvr" scene from-cloud "$real/FSite8_orig-utm.laz" --out "$generated/real/fsite8" \
    --vehicle "$detect/../common/van.obj" --seed 1
run "$ladarvr" scene from-cloud "$real/hexbin-crop.las" --out "$generated/real/hexbin" \
    --vehicle "$detect/../common/van.obj" --seed 1
run "$ladarvr" scene from-cloud "$real/sample_c.las" --out "$generated/real/sample_c" \
    --vehicle "$detect/../common/van.obj" --seed 1
run "$ladarvr" scene from-cloud "$real/4_6_crop.las" --out "$generated/real/crop_4_6" \
    --vehicle "$generated/vehicles/car_00.obj" --seed 1 --clearance-m 0 --max-slope 0.3 --max-roughness-m 0.5

if [ -n "$scenes_to" ]; then
    echo "train_shipped_model: wrote the vehicles and real places under $generated in $(($(date +%s) - start)) s" >&2
    exit 0
fi

# 3. Corpora, one per SPEC, in a fixed order. Where the scene leaves no room for a drawn
#    target (forest, street, wooded tile) the corpus leaves that item out and exits 1;
#    that is accepted, any other failure is not.
mkdir -p "$work"
corpora=()
for spec in "$detect"/shipped_*.json; do
    name=$(basename "$spec" .json)
    log="$work/$name.log"
    rc=0
    run "$ladarvr" corpus "$spec" --out "$work/$name" --jobs "$jobs" --threads 1 2>"$log" || rc=$?
    if [ "$rc" -ne 0 ]; then
        failed=$(grep -E '^corpus: \[[0-9]+/[0-9]+\] item [0-9]+: ' "$log" || true)
        if [ "$rc" -ne 1 ] || [ -z "$failed" ] || printf '%s\n' "$failed" | grep -qv 'the target cannot be placed'; then
            tail -5 "$log" >&2
            echo "train_shipped_model: corpus $spec failed (exit $rc); its log is $log" >&2
            exit 1
        fi
        echo "train_shipped_model: $name: $(printf '%s\n' "$failed" | wc -l) items left out (no room for the target)" >&2
    fi
    tail -1 "$log" | grep -E 'built' >&2 || grep -E ' built, ' "$log" >&2 || true
    corpora+=("$work/$name")
done

# 4. The model: the second feature set and the terrain levelling (train's defaults).
#    Two threads: the same corpora and build then write the same bytes.
run "$ladarvr" train "${corpora[@]}" --out "$out" --threads 2 --memory-mb 2048
echo "train_shipped_model: wrote $out in $(($(date +%s) - start)) s" >&2
