#!/usr/bin/env bash
# The render farm on a real Slurm cluster (docs/farm.md; .ci/run starts a one-node one with
# scripts/slurm-local.sh): a 12-frame walkthrough as a 3-task job array is bit-identical to local renders, a task
# killed midway (SIGKILL, or scancel of its array index) is made good by a second submission that renders exactly
# the missing frames, `farm status` names the frames of a cancelled task with Slurm's state, a bad flag submits
# nothing, and a task that cannot run makes --wait fail and `farm status` name its frames.
# Usage: farm_cluster_test.sh CHCRT_BINARY. Exit 77 (skipped) when no cluster answers.
set -uo pipefail
chcrt=$(realpath "${1:?usage: farm_cluster_test.sh path/to/chcrt}") || exit 1

if ! command -v sbatch > /dev/null || ! timeout 10 sinfo -h -o %T 2> /dev/null | grep -qE 'idle|mix|alloc'; then
  echo "SKIP: no Slurm cluster answers (scripts/slurm-local.sh start sets up a one-node one)"
  exit 77
fi

work=$(mktemp -d /tmp/chcrt_farm_cluster.XXXXXX)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
check() { # check DESCRIPTION COMMAND...: the command must succeed
  local what=$1; shift
  "$@" || fail "$what"
}
scene=(--scene city:10k --width 64 --height 40 --spp 1)

# Frames 0-11 in one local process each, as `chcrt render --frames k` renders them.
mkdir local
for k in $(seq 0 11); do
  "$chcrt" render "${scene[@]}" --frames "$k" -o "local/f_####.png" -q || fail "local render of frame $k"
done
identical_to_local() { # identical_to_local DIR: every frame of DIR equals the local one
  local k name ok=0
  for k in $(seq 0 11); do
    name=$(printf 'f_%04d.png' "$k")
    cmp -s "local/$name" "$1/$name" || { echo "  frame $k of $1 differs from the local render"; ok=1; }
  done
  return $ok
}
frames_listed_once() { # frames_listed_once STATS_JSON: frames 0..11 in order, each once
  python3 -c 'import json,sys; f=[x["frame"] for x in json.load(open(sys.argv[1]))["frames"]]; sys.exit(f != list(range(12)))' "$1"
}
tasks_of() { # tasks_of SBATCH_SCRIPT: its array size
  sed -n 's/^#SBATCH --array=0-\([0-9]*\)$/\1/p' "$1" | awk '{ print $1 + 1 }'
}

echo "== 12 frames as 3 array tasks"
check "farm submit --wait" "$chcrt" farm submit "${scene[@]}" --frames 0-11 --chunk 4 \
  -o farm/f_####.png --stats-json farm/stats.json --job-name chcrt-test --wait
[[ $(tasks_of farm/stats.farm/job-0.sbatch) == 3 ]] || fail "expected 3 array tasks"
check "farm status after the run" "$chcrt" farm status farm/stats.json
check "farm collect" "$chcrt" farm collect farm/stats.json
check "farm frames equal local frames" identical_to_local farm
check "collected stats list every frame once" frames_listed_once farm/stats.json
python3 -c 'import json,sys; t=json.load(open(sys.argv[1]))["tasks"]; sys.exit(not (len(t) == 3 and all(x["exit_code"] == 0 and x["host"] and x["startup_s"] > 0 for x in t)))' \
  farm/stats.json || fail "collected tasks: 3 with host, start-up and exit 0"

echo "== fault: the task of frames 4-7 is killed after frame 5"
CHCRT_FAULT_KILL_AFTER_FRAME=5 "$chcrt" farm submit "${scene[@]}" --frames 0-11 --chunk 4 \
  -o fault/f_####.png --stats-json fault/stats.json --job-name chcrt-test --wait
rc=$?
[[ $rc != 0 ]] || fail "--wait returned 0 although a task was killed"
[[ ! -e fault/f_0006.png && ! -e fault/f_0007.png ]] || fail "the killed task left frames after frame 5"
ls fault | grep -q tmp && fail "a temporary image was left behind"
status=$("$chcrt" farm status fault/stats.json)
rc=$?
echo "$status"
[[ $rc == 4 ]] || fail "farm status of an incomplete run exits 4 (got $rc)"
grep -q "frames 6-7" <<< "$status" || fail "farm status names the missing frames 6-7"
"$chcrt" farm collect fault/stats.json > /dev/null 2>&1 && fail "collect of an incomplete run succeeded"
[[ ! -e fault/stats.json ]] || fail "collect of an incomplete run wrote its output"
check "resubmission --wait" "$chcrt" farm submit "${scene[@]}" --frames 0-11 --chunk 4 \
  -o fault/f_####.png --stats-json fault/stats.json --job-name chcrt-test --wait
[[ $(tasks_of fault/stats.farm/job-1.sbatch) == 1 ]] || fail "the resubmission is one task"
grep -q "'--frames' '6-7'" fault/stats.farm/job-1.sbatch || fail "the resubmission renders exactly frames 6-7"
check "farm collect after the resubmission" "$chcrt" farm collect fault/stats.json
check "fault run frames equal local frames" identical_to_local fault
check "fault run stats list every frame once" frames_listed_once fault/stats.json

echo "== fault: the task of frames 4-7 stalls after frame 5 and is cancelled with scancel"
# CHCRT_FAULT_STALL_AFTER_FRAME=5 stops the render after frame 5's record until a signal ends it; scancel kills the
# task with its script, so no exit line is appended and status learns from Slurm (sacct, else scontrol) why it ended.
CHCRT_FAULT_STALL_AFTER_FRAME=5 "$chcrt" farm submit "${scene[@]}" --frames 0-7 --chunk 4 \
  -o cancel/f_####.png --stats-json cancel/stats.json --job-name chcrt-test > /dev/null
job=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["submissions"][0]["job"])' \
  cancel/stats.farm/manifest.json 2> /dev/null)
[[ $job =~ ^[0-9]+$ ]] || fail "no job id in the manifest (got '$job')"
has_frame_5() { python3 -c 'import json,sys; sys.exit(not any(json.loads(l).get("frame") == 5 for l in open(sys.argv[1]) if l.strip().startswith("{")))' "cancel/stats.farm/parts/${job}_1.jsonl" 2> /dev/null; }
for _ in $(seq 600); do has_frame_5 && break; sleep 0.2; done # a bound, not a timing: the task may wait in the queue
has_frame_5 || fail "task ${job}_1 never recorded frame 5"
scancel "${job}_1" || fail "scancel ${job}_1"
for _ in $(seq 600); do [[ -z $(squeue -h -j "$job" 2> /dev/null) ]] && break; sleep 0.2; done
[[ -z $(squeue -h -j "$job" 2> /dev/null) ]] || fail "job $job still queued after scancel"
[[ -e cancel/f_0005.png && ! -e cancel/f_0006.png && ! -e cancel/f_0007.png ]] ||
  fail "the cancelled task wrote frame 5 and nothing after it"
status=$("$chcrt" farm status cancel/stats.json)
rc=$?
echo "$status"
[[ $rc == 4 ]] || fail "farm status of a cancelled run exits 4 (got $rc)"
grep -q "failed   2: frames 6-7" <<< "$status" || fail "farm status names frames 6-7 as failed"
grep -q "task ${job}_1: Slurm CANCELLED" <<< "$status" || fail "farm status names the task and Slurm's state"
grep -q "missing  0" <<< "$status" || fail "no frame of the cancelled run is just missing"
check "resubmission after scancel --wait" "$chcrt" farm submit "${scene[@]}" --frames 0-7 --chunk 4 \
  -o cancel/f_####.png --stats-json cancel/stats.json --job-name chcrt-test --wait
[[ $(tasks_of cancel/stats.farm/job-1.sbatch) == 1 ]] || fail "the resubmission after scancel is one task"
grep -q "'--frames' '6-7'" cancel/stats.farm/job-1.sbatch || fail "the resubmission renders exactly frames 6-7"
check "farm status after the resubmission" "$chcrt" farm status cancel/stats.json
check "farm collect after scancel and resubmission" "$chcrt" farm collect cancel/stats.json
for k in $(seq 0 7); do
  name=$(printf 'f_%04d.png' "$k")
  cmp -s "local/$name" "cancel/$name" || fail "frame $k of the cancelled run differs from the local render"
done
python3 -c 'import json,sys; f=[x["frame"] for x in json.load(open(sys.argv[1]))["frames"]]; sys.exit(f != list(range(8)))' \
  cancel/stats.json || fail "cancelled run's stats list frames 0-7 once each"

echo "== a bad flag submits nothing"
jobs_before=$(squeue -h -n chcrt-test | wc -l)
"$chcrt" farm submit "${scene[@]}" --spp banana --frames 0-11 -o bad/f_####.png --stats-json bad/stats.json \
  --job-name chcrt-test > /dev/null 2>&1
rc=$?
[[ $rc == 2 ]] || fail "a bad flag exits 2 (got $rc)"
[[ ! -e bad ]] || fail "a bad flag left files"
[[ $(squeue -h -n chcrt-test | wc -l) == "$jobs_before" ]] || fail "a bad flag submitted a job"

echo "== a task that fails: the scene is missing on the node"
"$chcrt" farm submit --scene "$work/missing/scene.gltf" --width 64 --height 40 --frames 0-7 --chunk 4 \
  -o missing/f_####.png --stats-json missing/stats.json --job-name chcrt-test --wait
rc=$?
[[ $rc != 0 ]] || fail "--wait returned 0 although every task failed"
status=$("$chcrt" farm status missing/stats.json)
echo "$status"
grep -q "failed   8: frames 0-7" <<< "$status" || fail "farm status names the 8 failed frames"
[[ $(grep -c "on .*: exit 2" <<< "$status") == 2 ]] || fail "farm status names both failed tasks and their exit code"

if ((failures)); then
  echo "$failures check(s) failed; logs:"
  cat "$work"/*/stats.farm/logs/*.out 2> /dev/null | tail -40
  exit 1
fi
echo "all farm cluster checks passed"
