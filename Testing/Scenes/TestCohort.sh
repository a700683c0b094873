#!/bin/sh
# BMCohort: a cohort of generated shoulder CTs with known truth planned into one table, on this
# machine (bmsim cohort --jobs 2) and on a one-node Dask cluster started here on loopback
# (dask-scheduler and one dask-worker from Debian's python3-distributed;
# Utilities/cohort-dask.py). Three scapula phantoms (a right one at the default version and
# inclination, one anteverted, a left one more retroverted; 2 mm slices) and a folder that is not
# a CT: the three are planned with their 3D version and inclination within 2 deg of the truth,
# the broken one fails with its reason without stopping the others (exit 1), a rerun skips the
# done cases, and the cluster's table holds the same results.
#   sh TestCohort.sh BMSIM WORK_DIR SOURCE_DIR
set -eu
BMSIM=$1
WORK=$2
SOURCE=$3
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"
fail() { echo "BMCohort: $*" >&2; exit 1; }
PY=/usr/bin/python3 # Debian's, with python3-distributed (not a python3 earlier on PATH)

"$BMSIM" phantom scapula --pixel-mm 1.0 --slice-mm 2.0 --out p1 --quiet > /dev/null
"$BMSIM" phantom scapula --pixel-mm 1.0 --slice-mm 2.0 --version 5 --inclination -4 --out p2 --quiet > /dev/null
"$BMSIM" phantom scapula --pixel-mm 1.0 --slice-mm 2.0 --left --version -20 --out p3 --quiet > /dev/null
mkdir bad
echo "not a CT" > bad/a.dcm
printf 'id,ct,side\nright-default,p1,\nanteverted,p2,right\nleft,p3,\nbroken,bad,\n' > cases.csv

# Checks a table: the three phantoms planned against their truth, the broken case failed with a
# reason.
check() { # TABLE
  $PY - "$1" <<'EOF' || fail "the table $1 is wrong"
import csv, json, sys
rows = {r["id"]: r for r in csv.DictReader(open(sys.argv[1]))}
truth = {"right-default": "p1", "anteverted": "p2", "left": "p3"}
ok = True
for case, folder in truth.items():
    r, t = rows[case], json.load(open(folder + "/truth.json"))
    if r["status"] != "planned":
        print("case %s: %s (%s)" % (case, r["status"], r["reason"])); ok = False; continue
    for key in ("version_3d_deg", "inclination_deg"):
        if abs(float(r[key]) - t[key]) > 2.0:
            print("case %s: %s %s against the truth's %.2f" % (case, key, r[key], t[key])); ok = False
if rows["left"]["side"] != "left" or rows["right-default"]["side"] != "right":
    print("sides: %s, %s" % (rows["left"]["side"], rows["right-default"]["side"])); ok = False
if rows["broken"]["status"] != "failed" or "a.dcm" not in rows["broken"]["reason"]:
    print("broken case: %s (%s)" % (rows["broken"]["status"], rows["broken"]["reason"])); ok = False
sys.exit(0 if ok else 1)
EOF
}

# On this machine, two cases at a time; a failed case does not stop the others (exit 1).
set +e
"$BMSIM" cohort cases.csv --out local --jobs 2 > local.txt 2>&1
rc=$?
set -e
cat local.txt
[ $rc -eq 1 ] || fail "bmsim cohort with a broken case exited $rc"
check local/cohort.csv
# A rerun skips the three done cases and tries the broken one again.
set +e
"$BMSIM" cohort cases.csv --out local --jobs 2 > rerun.txt 2>&1
set -e
grep -q "1 run now, 3 done before (skipped)" rerun.txt || fail "the rerun did not skip the done cases: $(cat rerun.txt)"

# On a one-node Dask cluster on loopback.
port() { $PY -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
[ -x /usr/bin/dask-scheduler ] || fail "dask-scheduler is not installed (python3-distributed, Utilities/setup-debian.sh)"
PORT=$(port)
/usr/bin/dask-scheduler --host 127.0.0.1 --port "$PORT" --no-dashboard > scheduler.log 2>&1 &
SCHED=$!
/usr/bin/dask-worker "tcp://127.0.0.1:$PORT" --host 127.0.0.1 --nworkers 1 --nthreads 2 --no-dashboard > worker.log 2>&1 &
WORKER=$!
trap 'kill $WORKER $SCHED 2>/dev/null; wait $WORKER $SCHED 2>/dev/null || true' EXIT
set +e
$PY "$SOURCE/Utilities/cohort-dask.py" --scheduler "tcp://127.0.0.1:$PORT" --bmsim "$BMSIM" cases.csv --out cluster > cluster.txt 2>&1
rc=$?
set -e
cat cluster.txt
[ $rc -eq 1 ] || fail "cohort-dask.py with a broken case exited $rc (see $WORK/scheduler.log, worker.log)"
check cluster/cohort.csv
# The same results as on this machine (the plans are deterministic).
cut -d, -f1-10 local/cohort.csv > a.csv
cut -d, -f1-10 cluster/cohort.csv > b.csv
cmp -s a.csv b.csv || fail "the cluster's table differs from this machine's: $(diff a.csv b.csv)"
echo "BMCohort: planned on this machine and on a Dask cluster, the same table"
