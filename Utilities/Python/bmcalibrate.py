"""Cutting-coefficient calibration from ParaView's Python shell (pvpython) or any Python 3.

    import sys; sys.path.append("PREFIX/share/BoneMachining/python")
    import bmcalibrate
    result = bmcalibrate.calibrate("PREFIX/share/BoneMachining/Calibration/drilling-published.csv",
                                   "/tmp/cal", bones=["bovine femur"], name="my-bovine-set")
    result["coefficients"]["lips"]        # the fitted set, as a scene names it
    result["files"]["coefficients"]       # its path: "force_model": {"coefficients": PATH}

The fit is `bmsim calibrate` itself (Logic/Core/bmCalibration.h through Logic/CLI), run as a child
process, so the Python shell and the command line give the same coefficients to the last digit;
Docs/Calibration.md describes the data, the options and the outputs. bmsim is looked for, in order:
the `bmsim` argument, the BM_BMSIM environment variable, PREFIX/bin/bmsim of the install this
module lies in (PREFIX/share/BoneMachining/python), then PATH.
"""
import csv
import json
import os
import shutil
import subprocess

_CHISEL = ("shared", "scaled", "fixed")
_BONE_FACTORS = ("auto", "fit", "none")


def find_bmsim(bmsim=None):
    """Path of the bmsim executable (see the module's docs); raises FileNotFoundError naming
    every place looked in."""
    tried = []
    candidates = [bmsim, os.environ.get("BM_BMSIM")]
    here = os.path.dirname(os.path.abspath(__file__))
    candidates.append(os.path.normpath(os.path.join(here, "..", "..", "..", "bin", "bmsim")))
    candidates.append(shutil.which("bmsim"))
    for c in candidates:
        if not c:
            continue
        tried.append(c)
        if os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    raise FileNotFoundError("bmcalibrate: no bmsim executable (looked at: %s; set BM_BMSIM)"
                            % (", ".join(tried) or "nothing: BM_BMSIM unset, none on PATH"))


def _terms(value, what):
    if isinstance(value, str):
        value = [value]
    terms = [str(t) for t in value]
    if not terms or any(not t or "," in t for t in terms):
        raise ValueError("bmcalibrate: %s must be a non-empty list of names without commas, got %r"
                         % (what, value))
    return ",".join(terms)


def calibrate(data_csv, out_dir, basis=None, zheng_basis=None, bones=None, name=None,
              chisel=None, bone_factors=None, bmsim=None):
    """Fits ours and Zheng et al.'s cutting coefficients to measured thrust (N) and torque (N mm).

    data_csv: the measurements (columns: Logic/Core/bmCalibrationData.h); out_dir: where
    coefficients.json, zheng.json, folds.csv, predictions.csv and chart.svg are written (created;
    files replaced). Options as `bmsim calibrate`, None = its default: basis / zheng_basis (lists
    of basis terms, default ["1000/n_per_rpm"] / ["1", "1/V_min_per_m"]), bones (bone labels to
    keep), name (the set's name, default the data file's), chisel ("shared" default, "scaled",
    "fixed"), bone_factors ("auto" default, "fit", "none").

    Returns {"coefficients": ours (dict, a force model a scene can name), "zheng": dict,
    "folds": list of dicts (folds.csv: method, condition, RMS errors, minimum torque),
    "files": {"coefficients", "zheng", "folds", "predictions", "chart"} paths, "log": bmsim's
    report}. Raises ValueError for a bad option and RuntimeError with bmsim's message when the
    data are refused (the message names the file, line and column).
    """
    if not os.path.isfile(data_csv):
        raise ValueError("bmcalibrate: data file %r not found" % data_csv)
    args = [find_bmsim(bmsim), "calibrate", data_csv, "--out", out_dir]
    if basis is not None:
        args += ["--basis", _terms(basis, "basis")]
    if zheng_basis is not None:
        args += ["--zheng-basis", _terms(zheng_basis, "zheng_basis")]
    if bones is not None:
        args += ["--bones", _terms(bones, "bones")]
    if name is not None:
        args += ["--name", str(name)]
    if chisel is not None:
        if chisel not in _CHISEL:
            raise ValueError("bmcalibrate: chisel must be one of %s, got %r" % (_CHISEL, chisel))
        args += ["--chisel", chisel]
    if bone_factors is not None:
        if bone_factors not in _BONE_FACTORS:
            raise ValueError("bmcalibrate: bone_factors must be one of %s, got %r"
                             % (_BONE_FACTORS, bone_factors))
        args += ["--bone-factors", bone_factors]
    run = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         universal_newlines=True, check=False)
    if run.returncode != 0:
        raise RuntimeError("bmcalibrate: bmsim calibrate failed (exit %d): %s"
                           % (run.returncode, run.stderr.strip() or run.stdout.strip()))
    files = {key: os.path.join(out_dir, f) for key, f in
             (("coefficients", "coefficients.json"), ("zheng", "zheng.json"),
              ("folds", "folds.csv"), ("predictions", "predictions.csv"),
              ("chart", "chart.svg"))}
    with open(files["coefficients"]) as f:
        ours = json.load(f)
    with open(files["zheng"]) as f:
        zheng = json.load(f)
    with open(files["folds"], newline="") as f:
        folds = list(csv.DictReader(f))
    return {"coefficients": ours, "zheng": zheng, "folds": folds, "files": files,
            "log": run.stdout}
