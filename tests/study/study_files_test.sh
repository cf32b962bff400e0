#!/usr/bin/env bash
# tests/study/study_files_test.sh LADARVR: `ladarvr study` and `study report` over files
# crafted by hand (no display, no session run):
#   - session folders whose trials.csv names clouds '=HYPERLINK(...)', with ESC and
#     U+202E, and '-x.pcd': every table of the report shows them as text (a leading ',
#     escapes), and numbers, negative ones too, stay numbers;
#   - a study.json whose participant breaks the id rules ('=1+2', an HTML tag) is refused;
#   - a folder holding only study.json (empty) and one with 2 of its 8 trials (partial): a
#     warning each naming the folder, the empty one left out of the participants, the
#     counts in the summary line; only empty sessions: refused;
#   - --out over an earlier report holding a link, a folder or a FIFO under a report
#     file's name: one line naming it, exit 1, nothing moved, no hidden folder beside;
#   - a design with a duplicate key, NaN or trailing text given with --participant is
#     reported for what is wrong with it, not as a plan;
#   - a replay of a folder whose trial order is empty is refused, saying so;
#   - a run that fails before its first trial (no display: the desktop window cannot open)
#     leaves --out as it found it: no study.json, no folder it made; the same command
#     then fails the same way rather than finding a study there;
#   - --screenshot and --trial without --replay are usage errors; --help lists the colours.
set -euo pipefail
bin=$(realpath "$1")
work=$(mktemp -d /tmp/ladarvr-studyfiles.XXXXXX)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

header="trial,cloud,decision,designated_x,designated_y,designated_z,target_distance_m,hit,"
header+="time_to_first_designation_s,time_to_decision_s,designations,mode_switches,seconds_in_free_mode,"
header+="visibility_metric,participant,condition,block,practice"
esc=$'\x1b'
rlo=$'\xe2\x80\xae'  # U+202E, right-to-left override
session() {  # session DIR PARTICIPANT
  mkdir -p "$1"
  printf '{"design": "/d.json", "design_sha256": "aaaa", "participant": "%s", "condition_order": ["a", "b"], "order": []}\n' \
    "$2" >"$1/study.json"
  {
    echo "$header"
    echo "1,\"=HYPERLINK(\"\"http://x\"\",\"\"y\"\")\",confirm,-3.5,0,1,0.2,1,1.5,2.5,1,0,0,,$2,a,b1,0"
    echo "2,${esc}[2Jevil${rlo}gpj.pcd,no_target,,,,,,,4.0,0,0,0,,$2,b,b1,0"
    echo "3,-x.pcd,confirm,5,5,1,7.1,0,1.0,3.0,2,1,0.5,0.4,$2,b,b1,0"
  } >"$1/trials.csv"
}
session "$work/results/P01" P01
session "$work/results/P02" P02

"$bin" study report "$work/results" --out "$work/report" 2>"$work/err.txt" || fail "report: $(cat "$work/err.txt")"
python3 - "$work/report" <<'PY'
import csv, pathlib, sys
report = pathlib.Path(sys.argv[1])
def fail(m):
    print("FAIL:", m)
    sys.exit(1)
clouds = {row["cloud"] for row in csv.DictReader(open(report / "clouds.csv", newline=""))}
want = {"'=HYPERLINK(\"http://x\",\"y\")", "\\x1b[2Jevil\\u202egpj.pcd", "'-x.pcd"}
if clouds != want:
    fail(f"clouds.csv names {clouds}, not {want}")
for table in sorted(report.glob("*.csv")):
    text = table.read_text(encoding="utf-8")
    if any(c in text for c in "\x1b\u202e"):
        fail(f"{table.name} holds a raw control or bidi character")
    for row in csv.reader(text.splitlines()):
        for cell in row:
            if cell[:1] in ("=", "+", "@") or (cell[:1] == "-" and not cell[1:2].isdigit()):
                fail(f"{table.name}: cell {cell!r} reads as a formula")
            if cell[:1] == "-":
                float(cell)  # a negative number, written as one
print("report: every text cell is text")
PY
ls -A "$work" | grep -q '^\.ladarvr-tmp-' && fail "a temporary folder is left beside the report"

# Empty and partial sessions: one warning each, the empty one not a participant.
mkdir -p "$work/mixed"
cp -r "$work/results/P01" "$work/results/P02" "$work/mixed/"
mkdir -p "$work/mixed/P03" "$work/mixed/P04"
planned='"order": [0, 1, 2, 3, 4, 5, 6, 7]'
printf '{"design": "/d.json", "design_sha256": "aaaa", "participant": "P03", "condition_order": ["a", "b"], %s}\n' \
  "$planned" >"$work/mixed/P03/study.json"
printf '{"design": "/d.json", "design_sha256": "aaaa", "participant": "P04", "condition_order": ["b", "a"], %s}\n' \
  "$planned" >"$work/mixed/P04/study.json"
{
  echo "$header"
  echo "1,x.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P04,b,b1,0"
  echo "2,y.pcd,no_target,,,,,,,4.0,0,0,0,,P04,b,b1,0"
} >"$work/mixed/P04/trials.csv"
"$bin" study report "$work/mixed" --out "$work/mixed_report" 2>"$work/mixed.err" || fail "mixed report: $(cat "$work/mixed.err")"
cat >"$work/mixed.want" <<WANT
ladarvr: warning: study report: $work/mixed/P03: no trial recorded; left out
ladarvr: warning: study report: $work/mixed/P04: 2 of 8 trials recorded; its figures count those 2
study report: 3 participant(s), 2 condition(s); sessions: 2 complete, 1 partial, 1 empty; wrote $work/mixed_report/index.html
WANT
diff "$work/mixed.want" "$work/mixed.err" || fail "mixed report: not the warnings and summary above"
python3 - "$work/mixed_report" <<'PY' || fail "mixed report: figures"
import json, sys
fig = json.load(open(sys.argv[1] + "/figures.json"))
assert fig["participants"] == ["P01", "P02", "P04"], fig["participants"]
s = fig["sessions"]
assert (s["complete"], s["partial"], s["empty"]) == (2, 1, 1), s
assert [(x["participant"], x["state"]) for x in s["list"]] == [
    ("P01", "complete"), ("P02", "complete"), ("P03", "empty"), ("P04", "partial")], s["list"]
html = open(sys.argv[1] + "/index.html").read()
assert "3 participants" in html and "Sessions: 2 complete, 1 partial" in html
PY
status=0
"$bin" study report "$work/mixed/P03" --out "$work/empty_report" 2>"$work/empty.err" || status=$?
[ "$status" = 1 ] && [ "$(wc -l <"$work/empty.err")" = 1 ] && [ ! -e "$work/empty_report" ] &&
  grep -q "none of the 1 session(s) recorded a trial that is not practice" "$work/empty.err" ||
  fail "a report of empty sessions only: exit $status, $(cat "$work/empty.err")"

refused() {  # refused WANT ARGS...: exit 1, one line holding WANT
  local want=$1 status=0
  shift
  "$bin" "$@" 2>"$work/refused.err" >/dev/null || status=$?
  echo "refused: exit $status: $(cat "$work/refused.err")"
  [ "$status" = 1 ] && [ "$(wc -l <"$work/refused.err")" = 1 ] && grep -q -F -- "$want" "$work/refused.err" ||
    fail "not refused with one line saying '$want'"
}

for bad in '=1+2' '<img src=x onerror=alert(1)>'; do
  rm -rf "$work/badid" && session "$work/badid/X" "P01"
  python3 -c 'import json,sys; p=sys.argv[1]; r=json.load(open(p)); r["participant"]=sys.argv[2]; json.dump(r, open(p,"w"))' \
    "$work/badid/X/study.json" "$bad"
  refused "is not an id of 1 to 40 letters" study report "$work/badid/X" --out "$work/badreport"
  [ ! -e "$work/badreport" ] || fail "a refused report made its folder"
done

# An earlier report with someone's things under a report file's name: refused, untouched.
snapshot() { (cd "$work/report" && find . -printf '%p %y %s\n' | sort); }
plant() {  # plant NAME KIND
  rm -rf "$work/report"
  "$bin" study report "$work/results" --out "$work/report" 2>/dev/null
  rm -f "$work/report/$1"
  case $2 in
    link) ln -s /etc/hostname "$work/report/$1" ;;
    folder) mkdir "$work/report/$1" && echo "years of work" >"$work/report/$1/thesis.tex" ;;
    fifo) mkfifo "$work/report/$1" ;;
  esac
}
for planted in figures.json:link:"a symbolic link" index.html:folder:"a directory" tests.csv:fifo:"a FIFO (named pipe)"; do
  IFS=: read -r name kind words <<<"$planted"
  plant "$name" "$kind"
  before=$(snapshot)
  refused "holds '$name', which is $words, not a file this command writes" \
    study report "$work/results" --out "$work/report"
  [ "$(snapshot)" = "$before" ] || fail "the refused report changed the folder holding $name"
  ls -A "$work" | grep -q '^\.ladarvr-tmp-' && fail "a temporary folder is left beside the report ($name)"
done

# A design that is not strict JSON is reported as such, --participant or not.
mkdir -p "$work/designs"
printf '{"conditions": [{"name": "a"}], "conditions": []}\n' >"$work/designs/dup.json"
printf '{"conditions": [{"name": "a", "time_limit_s": NaN}]}\n' >"$work/designs/nan.json"
printf '{"conditions": [{"name": "a"}]} and more\n' >"$work/designs/trailing.json"
refused "duplicate key 'conditions'" study "$work/designs/dup.json" --participant P01 --no-xr --out "$work/s1"
for d in nan trailing; do
  refused "$d.json: JSON syntax error" study "$work/designs/$d.json" --participant P01 --no-xr --out "$work/s1"
  refused "$d.json: JSON syntax error" study "$work/designs/$d.json" --no-xr --out "$work/s1"
done
[ ! -e "$work/s1" ] || fail "a refused study made its folder"

# A replay of a folder whose study.json orders no trial says so (not "allowed 1..0").
mkdir -p "$work/empty"
printf 'VERSION .7\n' >"$work/empty/c.pcd"
printf '{"trials": [{"cloud": "c.pcd", "name": "one"}]}\n' >"$work/empty/plan.json"
printf '{"plan": "%s", "order": []}\n' "$work/empty/plan.json" >"$work/empty/study.json"
refused "study.json's trial order is empty; allowed a study folder with at least one trial" \
  study --replay "$work/empty" --trial 1
# No display: the run fails as the window opens, before its first trial. Nothing of it
# stays, so the same command runs again there (and fails for the same reason).
mkdir -p "$work/one"
printf 'VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n0 0 0\n' \
  >"$work/one/c.pcd"
printf '{"trials": [{"cloud": "c.pcd", "name": "one"}]}\n' >"$work/one/plan.json"
nodisplay() {  # nodisplay OUT: `study` without a display, one line saying so, exit 1
  local status=0
  # No runtime folder either: the window goes straight to X11, so no Wayland client adds a
  # line of its own about a missing XDG_RUNTIME_DIR.
  env -u DISPLAY -u WAYLAND_DISPLAY -u XDG_RUNTIME_DIR \
    "$bin" study "$work/one/plan.json" --no-xr --out "$1" 2>"$work/nodisplay.err" >/dev/null || status=$?
  echo "no display: exit $status: $(cat "$work/nodisplay.err")"
  [ "$status" = 1 ] && [ "$(wc -l <"$work/nodisplay.err")" = 1 ] &&
    grep -q "cannot open the desktop window" "$work/nodisplay.err" || fail "not refused for want of a display"
}
nodisplay "$work/fresh/sub"
[ ! -e "$work/fresh" ] || fail "a run that failed at start left the folders it made: $(find "$work/fresh")"
mkdir "$work/kept" && echo "mine" >"$work/kept/notes.txt"
for attempt in 1 2; do
  nodisplay "$work/kept"
  [ "$(ls -A "$work/kept")" = notes.txt ] || fail "attempt $attempt left $(ls -A "$work/kept") in --out"
done

# Options that only a replay uses are refused without --replay (exit 2, one line).
usage() {  # usage WANT ARGS...
  local want=$1 status=0
  shift
  "$bin" "$@" 2>"$work/usage.err" >/dev/null || status=$?
  [ "$status" = 2 ] && [ "$(wc -l <"$work/usage.err")" = 1 ] && grep -q -F -- "$want" "$work/usage.err" ||
    fail "exit $status, not a one-line usage error saying '$want': $(cat "$work/usage.err")"
}
usage "--screenshot requires --replay" study "$work/one/plan.json" --out "$work/s2" --screenshot "$work/s.png"
usage "--trial requires --replay" study "$work/one/plan.json" --out "$work/s2" --trial 2
[ ! -e "$work/s2" ] && [ ! -e "$work/s.png" ] || fail "a usage error left an output"
"$bin" study --help | grep -q -- "--colour.*file, height, white, label, above-ground" ||
  fail "study --help does not list above-ground among the colours"
echo "PASS"
