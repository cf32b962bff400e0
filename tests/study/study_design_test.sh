#!/usr/bin/env bash
# tests/study/study_design_test.sh LADARVR SCENARIO: `ladarvr study DESIGN.json
# --participant P --out DIR` driven headless (--no-xr, Xvfb from tests/viewer/headless_env.sh)
# by a script, checked by check_design.py. The design: three conditions (colours, eye-dome
# lighting, candidates on or off, a time limit, one starting in free mode), a practice trial and two blocks of one
# trial each, a break before the second and third condition, two participants, a Latin
# square. Every trial designates the tank and confirms: 9 trials per participant.
#   run      P01 and P02 each run their session: trials.csv's participant, condition,
#            block and practice columns follow each one's row of the Williams square, the
#            frames of each trial show its condition's colours, the breaks held the ready
#            screen, candidates.csv has rows only where the condition shows candidates;
#            `study --replay` of one of P02's trials finds its cloud through the design and
#            shows it in its condition's colours.
#   resume   P01's session is killed (SIGKILL) once trial 4 has started (its line on
#            stderr), then run again with the same command: the files equal an
#            uninterrupted run's (times aside); the folder is refused to P02 and to a
#            changed design, with one line each.
#   questionnaires  a design of two conditions (one trial each) with the SSQ, the TLX, a
#            Likert item after each condition and a free-text item after the session: the
#            script answers every item (one answer refused as out of range first), the
#            checker compares questionnaires.csv's rows with the script's answers and the
#            SSQ scores the session prints with its own computation; then the session is
#            killed after 5 of the post-session SSQ's items and resumed: only the rest is
#            asked and the files equal the uninterrupted run's (times aside); a copy of the
#            stopped folder with one answer changed out of range is refused.
#   detector P01's two conditions take their candidates from a detector run on the trial's
#            cloud (the shipped trained model, and the clustering baseline): candidates.csv
#            holds what `ladarvr detect` finds in that cloud, and the tank's box (c1) is
#            confirmed in both.
#   tools    a condition that offers no tools: the operator's grab_scale 2 changes the world
#            scale in the condition with every tool and is ignored (scale 1, no action
#            logged) in the one without, whose cutting volume the condition turns on: on
#            in its every frame (out of the operator's reach), off in the other's; run
#            again with `--cut --cut-radius 12`, the condition that sets no `cut` has it on
#            in its every frame too (the command's options reach the trials).
#   questionnaires_xr  on Monado's simulated HMD: two conditions of one trial each, the SSQ
#            before and after the session and a Likert item after each condition answered
#            by clicking the headset panel: the script stands in for the controller
#            (`point_answer N`: a ray from the head to rating N's button on the panel, and
#            the trigger), which goes through the panel's ray-quad hit and ImGui's click;
#            the desktop-only text item is skipped with an empty row. The `next` right
#            after the first condition's Likert answer waits for the click to go through,
#            and then starts the second trial (it is not spent on the questionnaire).
# Event-driven: `next` waits for the trial's cloud and for the end of a break, +N counts
# frames from the previous action, and the kill waits for the viewer's own line.
set -euo pipefail
bin=$(realpath "$1")
scenario=$2
here=$(cd "$(dirname "$0")" && pwd)
env_sh="$here/../viewer/headless_env.sh"
assets=$(cd "$here/../../assets" && pwd)
work=$(mktemp -d /tmp/ladarvr-designtest.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/../viewer/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

# One small labelled cloud of the demo scene, made once: every trial loads it from disk.
"$bin" generate --scene "$assets/demo/scene.json" --out "$work/demo.pcd" --xres 64 --yres 64 --views 40 \
  >/dev/null 2>"$work/generate.err" || { cat "$work/generate.err"; exit 1; }
cat >"$work/candidates.json" <<'CANDIDATES'
{"candidates": [{"id": "tank", "centre": [0, 0, 1.2], "size_m": [7, 3.5, 2.5], "yaw_deg": 20, "score": 0.9},
                {"id": "far", "centre": [80, -80, 2], "size_m": [7, 3.5, 2.5], "yaw_deg": 0, "score": 0.1}]}
CANDIDATES
cat >"$work/design.json" <<'DESIGN'
{"conditions": [{"name": "heightedl", "colour": "height", "eye_dome": true, "candidates": true},
                {"name": "white", "colour": "white", "eye_dome": false, "candidates": false},
                {"name": "label", "colour": "label", "eye_dome": true, "candidates": false, "time_limit_s": 250,
                 "start": "free"}],
 "practice": [{"cloud": "demo.pcd", "name": "practice"}],
 "blocks": [{"name": "first", "trials": [{"cloud": "demo.pcd", "candidates": "candidates.json", "name": "one"}]},
            {"name": "second", "trials": [{"cloud": "demo.pcd", "candidates": "candidates.json", "name": "two"}]}],
 "break_s": 0.5,
 "order": "latin",
 "participants": ["P01", "P02"],
 "orbit": {"radius_m": 60, "height_m": 40, "period_s": 100000}}
DESIGN
# Each trial: start it, designate the tank, confirm (the candidate's box where shown).
{
  echo "1 next"
  echo "+8 aim 0 0 1.2"; echo "+1 designate"; echo "+6 confirm"
  for _ in 2 3 4 5 6 7 8 9; do
    echo "+2 next"; echo "+8 aim 0 0 1.2"; echo "+1 designate"; echo "+6 confirm"
  done
} >"$work/script.txt"

run() {  # run PARTICIPANT OUT LOG
  "$env_sh" --timeout 220 -- "$bin" study "$work/design.json" --participant "$1" --out "$2" --no-xr \
    --width 320 --height 180 --timeout 200 --script "$work/script.txt" --log-json "$3" --no-metric
}

case "$scenario" in
  run)
    for p in P01 P02; do
      run "$p" "$work/$p" "$work/$p.log.json" 2>"$work/$p.err" || { echo "FAIL: $p's run exited $?"; cat "$work/$p.err"; exit 1; }
    done
    # --replay finds a session's trial through study.json and the design (P02's trial 5:
    # condition label, block first).
    "$env_sh" --timeout 220 -- "$bin" study --replay "$work/P02" --trial 5 --width 320 --height 180 \
      --log-json "$work/replay.json" 2>"$work/replay.err" || { echo "FAIL: replay"; cat "$work/replay.err"; exit 1; }
    grep -q '"exit": *"replay done"' "$work/replay.json" || { echo "FAIL: the replay did not end as 'replay done'"; exit 1; }
    # In the trial's condition's colours (label), as the participant saw it, not --colour's.
    python3 -c 'import json,sys; c={f["colour"] for f in json.load(open(sys.argv[1]))["frames"]}; sys.exit(c != {"label"})' \
      "$work/replay.json" || { echo "FAIL: the replay is not in the condition's colours"; exit 1; }
    ;;
  resume)
    run P01 "$work/whole" "$work/whole.log.json" 2>"$work/whole.err" || { echo "FAIL: uninterrupted run"; cat "$work/whole.err"; exit 1; }
    # The killed run's script starts trial 4 and gives it nothing more to do, so trial 4 waits
    # for its operator; the run is killed as soon as it says that trial started (stderr read
    # line by line through a FIFO: no polling, no sleep).
    head -n 13 "$work/script.txt" >"$work/script_to_4.txt"
    rm -f "$work/killed.fifo" "$work/killed.err"
    mkfifo "$work/killed.fifo"
    cat >"$work/kill.sh" <<RUN
set -u
"$bin" study "$work/design.json" --participant P01 --out "$work/resumed" --no-xr --width 320 --height 180 \
  --timeout 200 --script "$work/script_to_4.txt" --no-metric 2>"$work/killed.fifo" &
viewer=\$!
while IFS= read -r line; do
  printf '%s\\n' "\$line" >>"$work/killed.err"
  case "\$line" in *"study: trial 4 started"*) kill -KILL \$viewer; break ;; esac
done <"$work/killed.fifo"
rc=0
wait \$viewer || rc=\$?
echo "exit \$rc" >"$work/rc"
RUN
    "$env_sh" --timeout 220 -- bash "$work/kill.sh"
    rc=$(cut -d' ' -f2 "$work/rc")
    [ "$rc" = 137 ] || { echo "FAIL: the killed run exited $rc, expected 137"; cat "$work/killed.err"; exit 1; }
    grep -c . "$work/resumed/trials.csv" | grep -qx 4 || { echo "FAIL: the killed run wrote $(($(grep -c . "$work/resumed/trials.csv") - 1)) trials, expected 3"; exit 1; }
    [ -f "$work/resumed/trace_4.csv" ] || { echo "FAIL: the killed run left no trace_4.csv"; exit 1; }
    cp "$work/resumed/trials.csv" "$work/killed_trials.csv"
    # Another participant, or a changed design, is refused with one line; nothing changes.
    for refused in P02 changed; do
      if [ "$refused" = changed ]; then cp "$work/design.json" "$work/design2.json"; echo " " >>"$work/design2.json"
        args=("$work/design2.json" --participant P01); want="holds a session of another design"
      else args=("$work/design.json" --participant P02); want="holds participant P01's session"; fi
      status=0
      "$bin" study "${args[@]}" --out "$work/resumed" --no-xr --no-metric 2>"$work/refused.err" || status=$?
      echo "refused ($refused): exit $status: $(cat "$work/refused.err")"
      [ "$status" = 1 ] && [ "$(wc -l <"$work/refused.err")" = 1 ] && grep -q "$want" "$work/refused.err" ||
        { echo "FAIL: not refused with one line saying '$want'"; exit 1; }
      cmp -s "$work/resumed/trials.csv" "$work/killed_trials.csv" || { echo "FAIL: a refused run changed trials.csv"; exit 1; }
    done
    run P01 "$work/resumed" "$work/resumed.log.json" 2>"$work/resumed.err" || { echo "FAIL: resumed run"; cat "$work/resumed.err"; exit 1; }
    grep -q "resuming participant P01's session at trial 4 of 9" "$work/resumed.err" || { echo "FAIL: no resume line"; cat "$work/resumed.err"; exit 1; }
    # The resumed run numbers its trials as the session does: 4 to 9 of 9.
    grep -q "study: trial 4 of 9 (practice): ready screen" "$work/resumed.err" &&
      grep -q "study: trial 9 ended: confirm" "$work/resumed.err" || { echo "FAIL: resumed trials misnumbered"; cat "$work/resumed.err"; exit 1; }
    ;;
  questionnaires)
    cat >"$work/qdesign.json" <<'QDESIGN'
{"conditions": [{"name": "white", "colour": "white"}, {"name": "label", "colour": "label"}],
 "blocks": [{"name": "only", "trials": [{"cloud": "demo.pcd", "name": "one"}]}],
 "participants": ["P01", "P02"],
 "orbit": {"radius_m": 60, "height_m": 40, "period_s": 100000},
 "questionnaires": {"ssq": true, "tlx": true,
   "likert": [{"id": "sure", "statement": "I was sure of my answers.", "points": 5, "when": "after_condition"}],
   "text": [{"id": "remarks", "question": "Any remarks?", "when": "post"}]}}
QDESIGN
    # The answers (check_design.py reads the same values from answers.json).
    pre=(1 0 2 1 0 0 1 0 3 0 1 0 0 1 0 2); post=(2 1 3 2 1 0 2 1 3 1 2 1 0 2 1 3)
    tlx_white=(35 10 50 20 45 15); tlx_label=(60 5 40 30 55 25)
    remarks='the label colours helped, mostly "a lot"'
    trial() { echo "+2 next"; echo "+8 aim 0 0 1.2"; echo "+1 designate"; echo "+6 confirm"; }
    {
      echo "1 answer 4"  # out of the SSQ's 0..3: refused, the item stays up
      for a in "${pre[@]}"; do echo "+1 answer $a"; done
      trial
      for a in "${tlx_white[@]}"; do echo "+1 answer $a"; done; echo "+1 answer 4"
      trial
      for a in "${tlx_label[@]}"; do echo "+1 answer $a"; done; echo "+1 answer 2"
      for a in "${post[@]}"; do echo "+1 answer $a"; done
      echo "+1 answer $remarks"
    } >"$work/qscript.txt"
    python3 -c 'import json,sys; a=sys.argv[1:]; print(json.dumps({"pre": a[0:16], "tlx_white": a[16:22], "tlx_label": a[22:28], "post": a[28:44], "remarks": a[44]}))' \
      "${pre[@]}" "${tlx_white[@]}" "${tlx_label[@]}" "${post[@]}" "$remarks" >"$work/answers.json"
    qrun() {  # qrun OUT SCRIPT LOG
      "$env_sh" --timeout 220 -- "$bin" study "$work/qdesign.json" --participant P01 --out "$1" --no-xr \
        --width 640 --height 360 --timeout 200 --script "$2" --log-json "$3" --no-metric
    }
    qrun "$work/qwhole" "$work/qscript.txt" "$work/qwhole.log.json" 2>"$work/qwhole.err" ||
      { echo "FAIL: uninterrupted run"; cat "$work/qwhole.err"; exit 1; }
    grep -q "warning: study: answer '4' to 'General discomfort' refused: allowed a whole number from 0 to 3" \
      "$work/qwhole.err" || { echo "FAIL: the out-of-range answer was not refused"; cat "$work/qwhole.err"; exit 1; }
    # Killed once 5 of the post-session SSQ's items are answered: the script stops there, so
    # the run waits on item 6 when the kill comes (stderr read through a FIFO, no polling).
    head -n $((1 + 16 + 4 + 7 + 4 + 7 + 5)) "$work/qscript.txt" >"$work/qscript_killed.txt"
    rm -f "$work/q.fifo"; mkfifo "$work/q.fifo"
    cat >"$work/qkill.sh" <<RUN
set -u
"$bin" study "$work/qdesign.json" --participant P01 --out "$work/qresumed" --no-xr --width 640 --height 360 \
  --timeout 200 --script "$work/qscript_killed.txt" --no-metric 2>"$work/q.fifo" &
viewer=\$!
post=0
while IFS= read -r line; do
  printf '%s\\n' "\$line" >>"$work/qkilled.err"
  case "\$line" in
    *"questionnaire: Simulator sickness, after the session"*) post=1 ;;
    *"question 5 of 16 answered"*) [ \$post = 1 ] && { kill -KILL \$viewer; break; } ;;
  esac
done <"$work/q.fifo"
rc=0
wait \$viewer || rc=\$?
echo "exit \$rc" >"$work/qrc"
RUN
    "$env_sh" --timeout 220 -- bash "$work/qkill.sh"
    rc=$(cut -d' ' -f2 "$work/qrc")
    [ "$rc" = 137 ] || { echo "FAIL: the killed run exited $rc, expected 137"; cat "$work/qkilled.err"; exit 1; }
    cp "$work/qresumed/questionnaires.csv" "$work/qkilled.csv"
    # A folder whose answers are not this session's (one rating changed out of range) is
    # refused with one line, before any window.
    cp -r "$work/qresumed" "$work/qtampered"
    sed -i '3s/^\(P01,,ssq,pre,fatigue,\)0,/\19,/' "$work/qtampered/questionnaires.csv"
    grep -q '^P01,,ssq,pre,fatigue,9,' "$work/qtampered/questionnaires.csv" || { echo "FAIL: tampering"; exit 1; }
    status=0
    "$bin" study "$work/qdesign.json" --participant P01 --out "$work/qtampered" --no-xr --no-metric \
      2>"$work/qtampered.err" || status=$?
    [ "$status" = 1 ] && [ "$(wc -l <"$work/qtampered.err")" = 1 ] &&
      grep -q "questionnaires.csv: line 3: not the answer to this session's question 2 (ssq fatigue, pre)" \
        "$work/qtampered.err" || { echo "FAIL: tampered answers not refused: exit $status"; cat "$work/qtampered.err"; exit 1; }
    # The resumed run has no trial left: it asks the 11 SSQ items and the remark only.
    tail -n 12 "$work/qscript.txt" | sed '1s/^+1/1/' >"$work/qscript_rest.txt"
    qrun "$work/qresumed" "$work/qscript_rest.txt" "$work/qresumed.log.json" 2>"$work/qresumed.err" ||
      { echo "FAIL: resumed run"; cat "$work/qresumed.err"; exit 1; }
    grep -q "resuming participant P01's session at its last questions (35 of 47 answered)" "$work/qresumed.err" ||
      { echo "FAIL: no resume line"; cat "$work/qresumed.err"; exit 1; }
    grep "SSQ" "$work/qwhole.err" >"$work/qwhole.ssq"; grep "SSQ" "$work/qresumed.err" >"$work/qresumed.ssq" || true
    ;;
  questionnaires_xr)
    cat >"$work/xdesign.json" <<'XDESIGN'
{"conditions": [{"name": "white", "colour": "white"}, {"name": "label", "colour": "label"}],
 "blocks": [{"trials": [{"cloud": "demo.pcd", "name": "one"}]}],
 "participants": ["P01"],
 "orbit": {"radius_m": 60, "height_m": 40, "period_s": 100000},
 "questionnaires": {"ssq": true,
   "likert": [{"id": "sure", "statement": "I was sure of my answer.", "points": 5, "when": "after_condition"}],
   "text": [{"id": "expect", "question": "What do you expect?", "when": "pre"}]}}
XDESIGN
    pre=(1 0 2 1 0 0 1 0 3 0 1 0 0 1 0 2); post=(2 1 3 2 1 0 2 1 3 1 2 1 0 2 1 3)
    {
      for a in "${pre[@]}"; do echo "+1 point_answer $a"; done
      echo "+2 next"; echo "+8 aim 0 0 1.2"; echo "+1 designate"; echo "+6 confirm"
      echo "+1 point_answer 4"
      echo "+2 next"; echo "+8 aim 0 0 1.2"; echo "+1 designate"; echo "+6 confirm"
      echo "+1 point_answer 2"
      for a in "${post[@]}"; do echo "+1 point_answer $a"; done
    } >"$work/xscript.txt"
    python3 -c 'import json,sys; a=sys.argv[1:]; print(json.dumps({"pre": a[0:16], "post": a[16:32]}))' \
      "${pre[@]}" "${post[@]}" >"$work/answers.json"
    "$env_sh" --monado --timeout 220 -- "$bin" study "$work/xdesign.json" --participant P01 --out "$work/xr" \
      --width 640 --height 360 --timeout 200 --script "$work/xscript.txt" --log-json "$work/xr.log.json" \
      --no-metric 2>"$work/xr.err" || { echo "FAIL: the XR session exited $?"; cat "$work/xr.err"; exit 1; }
    ;;
  detector)
    cat >"$work/ddesign.json" <<DDESIGN
{"conditions": [{"name": "atr", "detector": "$assets/detect/model.ldm"}, {"name": "base", "detector": "baseline"}],
 "blocks": [{"trials": [{"cloud": "demo.pcd", "name": "one"}]}],
 "participants": ["P01"],
 "orbit": {"radius_m": 60, "height_m": 40, "period_s": 100000}}
DDESIGN
    printf '1 next\n+8 aim 0 0 1.2\n+1 designate\n+6 confirm\n+2 next\n+8 aim 0 0 1.2\n+1 designate\n+6 confirm\n' \
      >"$work/dscript.txt"
    "$env_sh" --timeout 220 -- "$bin" study "$work/ddesign.json" --participant P01 --out "$work/det" --no-xr \
      --width 320 --height 180 --timeout 200 --script "$work/dscript.txt" --no-metric 2>"$work/det.err" ||
      { echo "FAIL: the detector session exited $?"; cat "$work/det.err"; exit 1; }
    # The same detectors as `ladarvr detect` runs them, for the checker.
    "$bin" detect "$work/demo.pcd" --model "$assets/detect/model.ldm" --out "$work/atr.json" 2>/dev/null
    "$bin" detect "$work/demo.pcd" --out "$work/base.json" 2>/dev/null
    ;;
  tools)
    cat >"$work/tdesign.json" <<'TDESIGN'
{"conditions": [{"name": "all"}, {"name": "none", "tools": [], "cut": true, "cut_radius_m": 8}],
 "blocks": [{"trials": [{"cloud": "demo.pcd", "name": "one"}]}],
 "participants": ["P01"],
 "orbit": {"radius_m": 60, "height_m": 40, "period_s": 100000}}
TDESIGN
    # Each trial: the operator sets the world scale to 2, then designates and confirms.
    printf '1 next\n+4 grab_scale 2\n+4 aim 0 0 1.2\n+1 designate\n+6 confirm\n+2 next\n+4 grab_scale 2\n+4 aim 0 0 1.2\n+1 designate\n+6 confirm\n' \
      >"$work/tscript.txt"
    "$env_sh" --timeout 220 -- "$bin" study "$work/tdesign.json" --participant P01 --out "$work/tools" --no-xr \
      --width 320 --height 180 --timeout 200 --script "$work/tscript.txt" --log-json "$work/tools.log.json" \
      --no-metric 2>"$work/tools.err" || { echo "FAIL: the tools session exited $?"; cat "$work/tools.err"; exit 1; }
    "$env_sh" --timeout 220 -- "$bin" study "$work/tdesign.json" --participant P01 --out "$work/tools_cut" --no-xr \
      --width 320 --height 180 --timeout 200 --script "$work/tscript.txt" --log-json "$work/tools_cut.log.json" \
      --no-metric --cut --cut-radius 12 2>"$work/tools_cut.err" ||
      { echo "FAIL: the --cut session exited $?"; cat "$work/tools_cut.err"; exit 1; }
    ;;
  *) echo "study_design_test: unknown scenario '$scenario'" >&2; exit 2 ;;
esac
python3 "$here/check_design.py" "$scenario" "$work"
