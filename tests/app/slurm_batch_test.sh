#!/usr/bin/env bash
# tissu batch --executor slurm against a real one-node Slurm cluster
# (scripts/slurm-test-cluster.sh): a small batch goes through sbatch --array and the
# gathering job; its summary and stills must match those of the local executor, and
# `tissu batch status` must list every job. Fails, with the reason, when the cluster
# cannot start. Usage: slurm_batch_test.sh TISSU_BINARY SOURCE_DIR
set -euo pipefail

tissu=$1
source_dir=$2
# A guard against a hung scheduler only: a healthy run takes seconds.
DEADLINE_S=${SLURM_TEST_DEADLINE_S:-600}

work=$(mktemp -d "${TMPDIR:-/tmp}/tissu_slurm_test.XXXXXX")
chmod 755 "$work"
cluster="$work/cluster"
cleanup() {
  "$source_dir/scripts/slurm-test-cluster.sh" stop "$cluster" || true
  rm -rf "$work"
}
trap cleanup EXIT

fail() {
  echo "slurm_batch_test: FAILED: $*" >&2
  for f in "$work"/on\ slurm/slurm/*.out "$cluster"/log/slurmctld.log; do
    [ -f "$f" ] && { echo "--- $f:" >&2; tail -n 15 "$f" >&2; }
  done
  exit 1
}

"$source_dir/scripts/slurm-test-cluster.sh" start "$cluster" || fail "the one-node cluster did not start (reason above)"
# shellcheck disable=SC1091
. "$cluster/env.sh"

cat >"$work/fall.json" <<'EOF'
{
  "name": "fall", "dt": 0.004, "duration": 0.1, "integrator": "backward_euler",
  "cloth": {"mesh": {"generate": "rectangle", "size": [0.2, 0.2], "triangles": 50,
                     "irregular": true, "seed": 3},
            "material": "silk"},
  "gravity": [0, 0, -9.81],
  "render": {"width": 64, "height": 48, "msaa": 1, "fps": 30}
}
EOF
cat >"$work/batch.json" <<'EOF'
{
  "scene": "fall.json",
  "produce": "stills", "stills": 2,
  "list": [{"cloth.material": "silk"}, {"cloth.material": "cotton"}, {"cloth.material": "velvet"}],
  "slurm": {"cpus_per_task": 1, "mem": "200M", "time": "00:10:00"}
}
EOF

# A directory name with a space: sbatch splits #SBATCH lines at spaces unless quoted.
"$tissu" batch "$work/batch.json" --out "$work/on slurm" --executor slurm ||
  fail "tissu batch --executor slurm exited $?"
[ -x "$work/on slurm/slurm/array.sh" ] || fail "no array.sh"
grep -q -- "--cpus-per-task=1" "$work/on slurm/slurm/array.sh" || fail "array.sh asks for no CPUs per task"
grep -q -- "--mem=200M" "$work/on slurm/slurm/array.sh" || fail "array.sh asks for no memory"

# Status right after submission: every job queued, running or done, and the gathering job.
"$tissu" batch status "$work/on slurm" >"$work/status-early.txt" || fail "early tissu batch status exited $?"
grep -q "gathering job" "$work/status-early.txt" || fail "early status: no gathering job"
[ "$(grep -cE '^material-[a-z]+  (queued|running|done|failed)' "$work/status-early.txt")" = 3 ] ||
  { cat "$work/status-early.txt"; fail "early status: not every job listed"; }

# While it is on Slurm, the same batch is not started again in the same directory.
if "$tissu" batch "$work/batch.json" --out "$work/on slurm" --quiet 2>"$work/again.txt"; then
  fail "a second run started while the batch was on Slurm"
fi
if ! grep -q "still queued or running on Slurm" "$work/again.txt"; then
  # Only when the whole batch ended meanwhile may the local run go ahead (and find it complete).
  [ -z "$(timeout 30 squeue -h -o %i)" ] || { cat "$work/again.txt"; fail "no refusal while queued"; }
fi

# Wait for the gathering job: it writes the summary once every task has ended.
gather_job=$(sed -n 's/.*"gather_job": "\([0-9]*\)".*/\1/p' "$work/on slurm/slurm/submitted.json")
[ -n "$gather_job" ] || fail "no gathering job recorded in submitted.json"
waited=0
while [ -n "$(timeout 30 squeue -h -j "$gather_job" -o %i 2>/dev/null)" ] || [ ! -f "$work/on slurm/summary.csv" ]; do
  [ $waited -lt $((DEADLINE_S * 5)) ] || fail "the batch did not finish within $DEADLINE_S s"
  sleep 0.2
  waited=$((waited + 1))
done

"$tissu" batch status "$work/on slurm" >"$work/status.txt" || fail "tissu batch status exited $?"
cat "$work/status.txt"
grep -q "material-silk  done" "$work/status.txt" || fail "status: silk not done"
grep -q "material-velvet  failed" "$work/status.txt" || fail "status: velvet not failed"
grep -q "gathering job $gather_job" "$work/status.txt" || fail "status: no gathering job"

for job in material-silk material-cotton; do
  grep -q '"executor": "slurm"' "$work/on slurm/jobs/$job/state.json" || fail "$job did not run as a Slurm task"
done

# The same batch through the local executor gives the same rows and pictures.
"$tissu" batch "$work/batch.json" --out "$work/local" --quiet && fail "local: the failing job went unnoticed"
columns() { cut -d, -f1-4,8,9,11- "$1"; }  # all but times: started, finished, wall_s, ms_per_step
diff <(columns "$work/local/summary.csv") <(columns "$work/on slurm/summary.csv") ||
  fail "summary.csv differs between the local and the slurm executor"
for job in material-silk material-cotton; do
  "$tissu" compare "$work/local/jobs/$job/stills" "$work/on slurm/jobs/$job/stills" ||
    fail "$job: stills differ between the executors"
done
"$tissu" compare "$work/local/contact_sheet.png" "$work/on slurm/contact_sheet.png" ||
  fail "the contact sheets differ"

# A second submission of the same batch skips the complete jobs: only velvet is submitted.
"$tissu" batch "$work/batch.json" --out "$work/on slurm" --executor slurm 2>"$work/resubmit.txt" ||
  fail "resubmission exited $?"
grep -q "1 jobs submitted (2 complete, skipped)" "$work/resubmit.txt" || { cat "$work/resubmit.txt"; fail "resubmission did not skip"; }
grep -q '"indices": \[' "$work/on slurm/slurm/submitted.json" || fail "no indices recorded"
echo "slurm_batch_test: ok"
