#!/usr/bin/python3
"""scripts/calibration_tune.py reads an uncalibrated run as the C++ states a calibrated one.

The calibration is tried in scripts/calibration_tune.py on the rows of uncalibrated runs (each
answer's raw jackknives and readings, as calibration.csv writes them) and applied by run_method;
both call the one calibration model (skypole/uncertainty.h; the script through the Python module)
with the committed calibration (each method's registry entry, skypole/*_method.cpp). This runs the
same small random scenes twice -- once calibrated, once uncalibrated -- and checks that the script,
applying the committed calibration to the uncalibrated answers at the study's bound, declines the
same answers and states the same sigma as the C++ did: so what the study writes is all a calibration
reads, and the script's loading of it (units, empty fields, groups) cannot drift unnoticed.

    calibration_script_check.py SKYPOL SOURCE_DIR      (the module on PYTHONPATH)
"""
import csv
import os
import subprocess
import sys
import tempfile

skypol, source = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(source, "scripts"))
import calibration_tune as ct  # noqa: E402

BOUND = 2.5  # the study's default --max-uncertainty (studies/tradeoff_studies.h)
with tempfile.TemporaryDirectory() as tmp:
    env = dict(os.environ, SKYPOL_CACHE_DIR=os.path.join(tmp, "tables"))
    common = ["tradeoff", "calibration", "--small", "--count", "16", "--seed", "7"]
    subprocess.run([skypol, *common, "--out", os.path.join(tmp, "cal")], check=True, env=env)
    subprocess.run([skypol, *common, "--uncalibrated", "--max-uncertainty", "inf", "--out", os.path.join(tmp, "unc")],
                   check=True, env=env)
    cal = ct.read_calibrations("committed")
    by = ct.load([os.path.join(tmp, "unc", "calibration.csv")])
    cpp = {(r["method"], int(r["stack"])): r for r in csv.DictReader(open(os.path.join(tmp, "cal", "calibration.csv")))}

compared = valid = mismatches = 0
for m, d in by.items():
    ok, sigma, cone = ct.apply(d, cal[m], BOUND)
    for i, k in enumerate(d["stack"]):
        r = cpp[(m, int(k))]
        c_valid = r["valid"] == "1"
        compared += 1
        valid += c_valid
        same = c_valid == bool(ok[i])
        if same and c_valid:
            same = (abs(float(r["sigma_deg"]) - sigma[i]) <= 1e-4 * sigma[i] + 1e-9
                    and abs(float(r["cone95_deg"]) - cone[i]) <= 1e-4 * cone[i] + 1e-9)
        if not same:
            mismatches += 1
            print(f"{m} stack {k}: C++ valid {c_valid} sigma {r['sigma_deg']} ({r['why_invalid'][:90]}); "
                  f"script valid {bool(ok[i])} sigma {sigma[i]:.6g}")
print(f"{compared} answers compared, {valid} valid in C++, {mismatches} mismatches")
# A check that compares nothing proves nothing: the small run must hold valid answers.
sys.exit(1 if mismatches or valid < 5 else 0)
