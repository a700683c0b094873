#!/usr/bin/python3
"""Plans a cohort on a Dask cluster (Debian's python3-distributed): one task per case, each
running `bmsim cohort CASES --out DIR --case ID` on a worker, then `bmsim cohort ... --collect`
writes DIR/cohort.csv here. The workers must see the same files (bmsim, the case list, the CTs,
DIR: a shared filesystem, as on a cluster's nodes). Cases already done are skipped by bmsim
itself, so a rerun goes on where the last one stopped; a case that fails is recorded in its
folder and does not stop the others.

    Utilities/cohort-dask.py --scheduler tcp://HOST:8786 [--bmsim build/bin/bmsim] CASES.csv --out DIR

A cluster: `dask-scheduler` on one node, `dask-worker tcp://HOST:8786 --nthreads 1` on each
(one plan per worker thread; a plan uses up to 2 GiB for a 512-slice CT). Exit status: bmsim
cohort --collect's (1 when a case failed), 2 when a task could not run at all.
"""
import argparse
import csv
import os
import subprocess
import sys

from distributed import Client


def run_case(bmsim, cases, out, case_id):
    """One case on a worker: bmsim's own skip-if-done, plan, record."""
    done = subprocess.run([bmsim, "cohort", cases, "--out", out, "--case", case_id],
                          capture_output=True, text=True)
    return case_id, done.returncode, (done.stdout + done.stderr).strip()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cases", help="the case list (CSV: id, ct[, side])")
    parser.add_argument("--out", required=True, help="the cohort's folder")
    parser.add_argument("--scheduler", required=True, help="the Dask scheduler, tcp://HOST:PORT")
    parser.add_argument("--bmsim", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                        "..", "build", "bin", "bmsim"))
    args = parser.parse_args()
    bmsim, cases, out = (os.path.abspath(p) for p in (args.bmsim, args.cases, args.out))
    with open(cases, newline="") as f:
        ids = [row["id"] for row in csv.DictReader(f) if row.get("id")]
    client = Client(args.scheduler, timeout="30s")
    try:
        futures = client.map(run_case, [bmsim] * len(ids), [cases] * len(ids), [out] * len(ids),
                             ids, pure=False)
        broken = 0
        for case_id, code, said in client.gather(futures):
            print("%s: %s" % (case_id, said.splitlines()[-1] if said else "exit %d" % code))
            broken += code != 0
    finally:
        client.close()
    if broken:
        print("cohort-dask: %d task(s) could not run bmsim" % broken, file=sys.stderr)
        return 2
    return subprocess.run([bmsim, "cohort", cases, "--out", out, "--collect"]).returncode


if __name__ == "__main__":
    sys.exit(main())
