#!/usr/bin/python3
"""Read the methods' calibration off uncalibrated runs of the calibration study.

    skypol tradeoff calibration --out DIR --seed 1 --count 500 --binning 16 \
        --max-uncertainty inf --uncalibrated
    scripts/calibration_tune.py S1/calibration.csv [S3/calibration.csv ...] [--bound 2.5] [--margin 0.9]
        [--apply committed|FILE] [--auto MODE] [--replace RERUN.csv ...] [--only METHOD ...] [--min-sky-coverage 0.8]

An uncalibrated run keeps every answer the method itself gives (no gates, no bound) with its raw
jackknife covariances -- over frame groups and, for the methods that have one, over sky sectors --
and the readings the gates and the sigma terms read (residual, window, unpolarized and clipped
shares, ring anisotropy, model misfit, the suns' elevation misfit, pixel angle). So every
calibration can be tried here without running anything again. This script only searches and
scores: the calibration model itself -- the sigma and cone a calibration states, its gates, the
uncertainty bound, the Wilson interval and auto's rule -- is the C++ that states the estimates
(skypole/uncertainty.h), called through the Python module (python/bind_calibration.cpp:
skypol._skypol.CalibrationRows, wilson_interval95, auto_choice). A calibration is a dict keyed by
MethodCalibration's fields (inflation, sector_inflation, floor_deg, ..., max_residual_deg; each
method's committed one is its registry entry, skypole/*_method.cpp, as skypol.methods() gives it).

Several runs (seeds) are pooled. Per method it prints the calibration with zero lies (counted at
err > 5*margin*sigma) and coverage in the band [0.90, --max-coverage] (and, with
--min-sky-coverage C, at least C for every sky model with 10 answers or more, and with --sky-wilson
no sky model with fewer whose coverage's 95 % Wilson interval tops out below C) that keeps the most
answers (within 5 %: the fewest gates, then the fewest sigma terms, then coverage nearest 95 %), its
figures per sky model and per seed, and what auto makes of the calibrated answers.
--apply committed|FILE: evaluate the committed calibrations (the registry's) or those in FILE
instead of searching, e.g. on the uncalibrated run of a seed the search did not read. FILE: JSON, either
{method: {field: value}} (missing fields: MethodCalibration's defaults; null: an unbounded gate)
or the array `skypol methods --json` prints.
--auto ranked|sharpest|ephemeris|ephemeris_mean|mean|mean_raw: which agreeing answer auto returns,
the agreeing group being auto_choice's (the C++ rule): the first method's in RANK (a fixed order
of methods), the sharpest, sun_vector_ephemeris' when it agrees and else the sharpest
(ephemeris) or else the inverse-variance mean (ephemeris_mean: what combine_estimates does), or the
inverse-variance mean of the agreeing answers weighted by the calibrated sigma (mean) or by the
uncalibrated sigma (mean_raw), stated with the sharpest member's sigma; all six are printed with
--auto both (the default), each also as for a stack that does not know its site (no
sun_vector_ephemeris: an imported capture without [site]).
--replace RERUN.csv ...: the rows of the (seed, method) pairs that `--methods` re-runs of the same
seeds and counts hold replace the runs' (a method changed after the run).
--only METHOD ...: search or apply these methods only.
--grid FIELD=V,V,...: search only these values of one MethodCalibration field (inf for no gate;
max_clipped_share and sector_clipped are searched only when given), to make a search with many
dimensions affordable.
--plot FILE.png: the reliability diagram (stated 95 % cone against error; share inside per bin).
"""
import argparse
import csv
import itertools
import json
import math
import os
import sys

import numpy as np

try:
    import skypol  # Debian's python3 with skypol.pth, or PYTHONPATH
except ImportError:
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "build", "python"))
    import skypol
from skypol import _skypol

LIE_DEG, LIE_SIGMA = 5.0, 5.0  # a lie: a valid answer this far off, or this many of its own sigma (the study's)
MAX_COVERAGE = 0.98
MARGIN = 1.0  # the search counts a lie at err > 5·MARGIN·σ: MARGIN < 1 leaves room for seeds it did not read
# A calibration must also hold for each sky model it answers on, not only pooled: a sky model with
# at least SKY_MIN_ANSWERS answers must see at least MIN_SKY_COVERAGE of its truths inside the cone
# (0: no such rule).
MIN_SKY_COVERAGE = 0.0
GRID = {}  # --grid: a search grid's values, replacing the default's
SKY_MIN_ANSWERS = 10
# --sky-wilson: a sky model with fewer answers fails the rule too when the top of its coverage's 95 %
# Wilson interval is below MIN_SKY_COVERAGE.
SKY_WILSON = False
# --auto ranked: the agreeing answer of the first method in this order, the methods by the median
# error of their calibrated answers (measured in docs/calibration-history.md §7e).
RANK = ["sun_vector_ephemeris", "great_circle", "sun_vector", "sun_dolp", "invariance", "classic"]
# The gates, each a MethodCalibration field.
GATES = ("max_residual_deg", "min_window_min", "max_unpolarized_share", "max_ring_anisotropy", "max_model_misfit",
         "max_clipped_share")
# The sigma model's factors and terms the search varies, each a MethodCalibration field.
TERMS = ("inflation", "sector_inflation", "floor_deg", "unpolarized_deg", "residual_share", "residual_pixels",
         "elevation_share", "misfit_deg", "sector_unpolarized", "sector_clipped")


def registry():
    """The registered methods' entries (skypol.methods(): traits and committed calibration), by name."""
    return {m["name"]: m for m in skypol.methods()}


def names(keep):
    return [n for n, m in registry().items() if keep(m)]


def fnum(s):
    return float(s) if s not in ("", None) else math.nan


# The calibration.csv columns CalibrationRows reads (python/bind_calibration.cpp), and what a row
# that lacks one counts: the jackknives of an invalid answer are 0, a reading it lacks is 0.
JACKKNIFE_COLUMNS = ("frames_aa_deg2", "frames_ab_deg2", "frames_bb_deg2", "sectors_aa_deg2", "sectors_ab_deg2",
                     "sectors_bb_deg2")
READING_COLUMNS = ("residual_deg", "pixel_deg", "unpolarized_share", "clipped_share", "sun_elevation_misfit_deg",
                   "model_misfit", "window_min", "ring_anisotropy")


def load(paths, replace=()):
    """The answers of one or more runs (seeds), every method's rows in the same (seed, stack) order."""
    rows = []
    for p in paths:
        with open(p) as f:
            reader = csv.DictReader(f)
            missing = [c for c in ("offset_az_deg", "frame_groups", *JACKKNIFE_COLUMNS) if c not in reader.fieldnames]
            if missing:
                raise SystemExit(f"{p}: no column {', '.join(missing)} (a run made before the study wrote its raw "
                                 "jackknives: run it again)")
            rows += list(reader)
    if replace:
        # `--methods` re-runs: their (seed, method) rows replace the runs' (same seed and count: the
        # same scenes).
        extra = [r for p in replace for r in csv.DictReader(open(p)) if not r["method"].startswith("auto")]
        redo = {(r["seed"], r["method"]) for r in extra}
        rows = [r for r in rows if (r["seed"], r["method"]) not in redo] + extra
    rows.sort(key=lambda r: (int(r["seed"]), int(r["stack"])))
    sectors = {n: m["sector_jackknife"] for n, m in registry().items()}
    by = {}
    for r in rows:
        m = r["method"]
        if m not in sectors:  # auto's rows (with and without the site): combinations, not methods
            continue
        d = by.setdefault(m, {k: [] for k in ("stack", "sky", "valid", "err", "off", "seed", "sector_groups",
                                               "frame_groups", *JACKKNIFE_COLUMNS, *READING_COLUMNS)})
        d["stack"].append(int(r["stack"]))
        d["sky"].append(r["sky"])
        v = r["valid"] == "1"
        d["valid"].append(v)
        d["err"].append(fnum(r["angular_error_deg"]) if v else math.nan)
        for c in JACKKNIFE_COLUMNS:
            d[c].append(fnum(r[c]) if v else 0.0)
        d["off"].append([fnum(r["offset_az_deg"]), fnum(r["offset_alt_deg"])] if v else [math.nan, math.nan])
        d["frame_groups"].append(int(r["frame_groups"] or 0) if v else 0)
        d["sector_groups"].append(_skypol.sky_sectors if sectors.get(m) else 0)
        # The gates and terms read an invalid answer's residual as none, and a missing share or
        # misfit (a run before the column, an empty field) as 0.
        d["residual_deg"].append(fnum(r["residual_deg"]) if v else math.nan)
        d["window_min"].append(fnum(r["window_min"]))
        d["pixel_deg"].append(fnum(r["pixel_deg"]))
        for c in ("unpolarized_share", "clipped_share", "ring_anisotropy"):
            d[c].append(np.nan_to_num(fnum(r.get(c, "0") or "0")))
        for c in ("model_misfit", "sun_elevation_misfit_deg"):
            d[c].append(fnum(r.get(c, "0") or "0") if v else 0.0)
        d["seed"].append(int(r["seed"]))
    for m, d in by.items():
        for k in d:
            d[k] = np.array(d[k])
        d["rows"] = _skypol.CalibrationRows({k: d[k] for k in ("frame_groups", "sector_groups", *JACKKNIFE_COLUMNS,
                                                                *READING_COLUMNS)})
    return by


def apply(d, c, bound):
    """Calibrated (valid, sigma, cone95) of every row of one method under calibration c: what
    run_method states (CalibrationRows.stated) and keeps (its gates and the bound)."""
    s = d["rows"].stated(c, bound)
    ok = d["valid"] & d["rows"].gates(c) & s["within_bound"]
    return ok, s["sigma_deg"], s["cone95_deg"]


def wilson95(hits, n):
    """The 95 % Wilson score interval of a share of hits in n (skypole/uncertainty.h), to 3 digits."""
    if not n:
        return None
    low, high = _skypol.wilson_interval95(np.asarray(float(hits)), np.asarray(float(n)))
    return (round(float(low), 3), round(float(high), 3))


def stats(d, ok, sigma, cone, sel=None):
    if sel is not None:
        ok = ok & sel
    n = int(sel.sum()) if sel is not None else len(ok)
    err = d["err"][ok]
    sg = sigma[ok]
    lies = int(np.sum((err > LIE_DEG) | (err > LIE_SIGMA * sg)))
    inside = int(np.sum(err <= cone[ok]))
    v = int(ok.sum())
    return {"n": n, "valid": v, "yield": round(v / n, 4) if n else math.nan, "lies": lies,
            "coverage": round(inside / v, 4) if v else math.nan, "cov95": wilson95(inside, v), "median": float(np.median(err)) if v else math.nan,
            "max": float(err.max()) if v else math.nan}


def search_with(d, bound, combos, err, gate_grid):
    """The calibrations of search() that meet its rules: each combination of terms (combos, tuples
    in TERMS' order) under each combination of gates (gate_grid, lists in GATES' order)."""
    gates, masks = [], []
    for values in itertools.product(*gate_grid):
        g = dict(zip(GATES, values))
        gates.append(g)
        masks.append(d["valid"] & d["rows"].gates(g))
    G = np.array(masks, dtype=np.float64)  # gates x rows
    ngates = np.array([sum(1 for k in GATES if k != "min_window_min" and math.isfinite(g[k])) + (g["min_window_min"] > 0)
                       for g in gates])
    found = []
    chunk = 512
    for start in range(0, len(combos), chunk):
        part = combos[start:start + chunk]
        cone_ok, lie_v, inside_v = [], [], []
        for values in part:
            s = d["rows"].stated(dict(zip(TERMS, values)), bound)
            ok = s["within_bound"]
            cone_ok.append(ok)
            lie_v.append(ok & ((err > LIE_DEG) | (err > LIE_SIGMA * MARGIN * s["sigma_deg"])))
            inside_v.append(ok & (err <= s["cone95_deg"]))
        V = G @ np.array(cone_ok, dtype=np.float64).T  # gates x combos
        L = G @ np.array(lie_v, dtype=np.float64).T
        I = G @ np.array(inside_v, dtype=np.float64).T
        with np.errstate(invalid="ignore", divide="ignore"):
            cov = np.where(V > 0, I / np.maximum(V, 1), np.nan)
        good = (V > 0) & (L == 0) & (cov >= 0.90) & (cov <= MAX_COVERAGE)
        if MIN_SKY_COVERAGE > 0 and good.any():
            gi, ji = np.nonzero(good)
            cone_a, inside_a = np.array(cone_ok, dtype=bool), np.array(inside_v, dtype=bool)
            for sky in set(d["sky"]):
                at = d["sky"] == sky
                for lo in range(0, len(gi), 4096):  # the passing pairs only, in blocks
                    g_, j_ = gi[lo:lo + 4096], ji[lo:lo + 4096]
                    rows_ok = G[g_].astype(bool) & at
                    vs = np.sum(rows_ok & cone_a[j_], axis=1)
                    ins = np.sum(rows_ok & inside_a[j_], axis=1)
                    bad = (vs >= SKY_MIN_ANSWERS) & (ins < MIN_SKY_COVERAGE * vs)
                    if SKY_WILSON:  # fewer answers: not even the interval's top reaches the rule
                        top = _skypol.wilson_interval95(ins.astype(np.float64), vs.astype(np.float64))[1]
                        bad |= (vs > 0) & (top < MIN_SKY_COVERAGE)
                    good[g_[bad], j_[bad]] = False
        for g, j in zip(*np.nonzero(good)):
            terms = sum(1 for x in part[j] if x > 0) - (part[j][TERMS.index("residual_pixels")] > 0)
            found.append((int(V[g, j]), float(cov[g, j]), int(ngates[g]), int(terms),
                          {**dict(zip(TERMS, part[j])), **gates[g]}))
    return found


def search(m, d, bound):
    inflation = [0.5, 0.75, 1, 1.25, 1.5, 2, 3, 4, 6, 8, 12, 16]
    # A method with a sector jackknife counts it (b > 0): the errors that live in one part of the sky
    # are what it is there for, and a tuning set that happens to hold few of them must not drop it.
    sector_inflation = [0.0] if m not in names(lambda e: e["sector_jackknife"]) else [0.25, 0.5, 0.75, 1, 1.5, 2, 3]
    # The smallest floors are numerical: a noise-free stack's answers agree with the truth to
    # 1e-6..1e-4 deg (float32 Stokes, the solvers' tolerances), below what a jackknife resolves.
    floor_deg = [1e-4, 3e-4, 1e-3, 3e-3, 0.01, 0.03, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 1.25, 1.5, 2.0]
    unpolarized_deg = [0.0, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0]
    # The residual term: the fit's residual is the scatter of what the frames (or pixels) say about
    # the same thing; where that scatter is shared by every frame and every part of the sky (the
    # colour sensor's demosaicked AoLP), neither jackknife sees it and the residual does.
    residual_share = [0.0, 0.1, 0.25, 0.5] if m != "classic" else [0.25, 0.5, 1.0]
    residual_pixels = [0.0] if m != "classic" else [0, 2, 4, 6]
    # The elevation term, for the methods that measure one (PoleEstimate::sun_elevation_misfit_deg:
    # sun_vector_ephemeris' suns against the ephemeris, an error its frames share).
    elevation_share = [0.0] if not np.any(d["sun_elevation_misfit_deg"] > 0) else [0.0, 0.25, 0.5, 1.0, 2.0]
    # Candidate gate thresholds (none, or one of a few round values). Every method but classic
    # keeps a residual gate: a tuning seed cannot show every way a fit fails (a residual of 180° is
    # invariance's unsettled fit; a saturated mono sensor gives an ephemeris fit whose residual is
    # as large as its error, which neither jackknife sees: every frame and part of the sky alike).
    max_residual_deg = [5.0, 2.0, 1.0, 0.5, 0.3, 0.2, 0.1, 0.05]
    if m == "classic":
        max_residual_deg = [math.inf]
    min_window_min = [0.0, 60, 120]
    max_unpolarized_share = [math.inf, 0.5, 0.4, 0.3, 0.25]
    max_ring_anisotropy = [math.inf, 0.5, 0.4, 0.3, 0.2, 0.1]
    # The model-misfit gate, for the methods that measure one (PoleEstimate::model_misfit: sun_dolp's
    # Rayleigh fit, where a clear Rayleigh sky reads 0-0.002 and Berry's and vrte's skies 0.016-0.08).
    misfit = np.any(d["model_misfit"] > 0)
    max_model_misfit = [math.inf] if not misfit else [math.inf, 0.03, 0.02, 0.01, 0.005]
    # The misfit's sigma term (degrees per unit of misfit): a multiply scattering sky's departure from
    # the law moves the suns alike in every frame and sector, by more the further it departs.
    misfit_deg = [0.0] if not misfit else [0.0, 10.0, 20.0, 40.0, 80.0]
    # The clipped-sky gate and the sector factor's growth with the clipped and the unpolarized
    # shares: not searched unless asked (--grid max_clipped_share=..., sector_clipped=...,
    # sector_unpolarized=...), so that a search without them reads only the other terms.
    max_clipped_share = [math.inf]
    sector_clipped = [0.0]
    sector_unpolarized = [0.0]
    grids = {"inflation": inflation, "sector_inflation": sector_inflation, "floor_deg": floor_deg,
             "unpolarized_deg": unpolarized_deg, "residual_share": residual_share, "residual_pixels": residual_pixels,
             "elevation_share": elevation_share, "misfit_deg": misfit_deg, "sector_unpolarized": sector_unpolarized,
             "sector_clipped": sector_clipped, "max_residual_deg": max_residual_deg, "min_window_min": min_window_min,
             "max_unpolarized_share": max_unpolarized_share, "max_ring_anisotropy": max_ring_anisotropy,
             "max_model_misfit": max_model_misfit, "max_clipped_share": max_clipped_share}
    for k, v in GRID.items():
        grids[k][:] = v
    err = np.nan_to_num(d["err"], nan=1e9)
    combos = list(itertools.product(*(grids[k] for k in TERMS)))
    found = search_with(d, bound, combos, err, [grids[k] for k in GATES])
    if not found:
        return None
    # Within 5 % of the most answers any calibration keeps: the fewest gates (each is a chance to
    # fit a tuning seed's accidents), the fewest sigma terms, then the coverage nearest 95 % (the
    # middle of the band, so that a seed the search did not read has room either side), then the
    # most answers.
    most = max(x[0] for x in found)
    near = [x for x in found if x[0] >= 0.95 * most]
    near.sort(key=lambda x: (x[2], x[3], round(abs(x[1] - 0.95), 3), -x[0], x[4]["floor_deg"], x[4]["inflation"]))
    return near[0][0], near[0][4]


def combine(by, cal, bound, mode="sharpest", site_known=True):
    """auto over the calibrated answers, per stack: the agreeing group of auto_choice (the C++
    rule, skypole/uncertainty.h); which of its answers, or what mean, is returned depends on the
    mode (see --auto). Answers are placed by their offsets from the truth in the tangent plane
    there, so that the mean's error is its offset's length."""
    site = set(names(lambda e: e["needs_site"]))
    alone = set(names(lambda e: e["auto_answers_alone"]))
    methods = [m for m in by if (site_known or m not in site) and m in cal]
    n = len(next(iter(by.values()))["stack"])
    out_ok = np.zeros(n, bool)
    out_err = np.full(n, math.nan)
    out_sigma = np.full(n, math.nan)
    out_cone = np.full(n, math.nan)
    applied = {m: apply(by[m], cal[m], bound) for m in methods}
    raw = {m: by[m]["rows"].uncalibrated()["sigma_deg"] for m in methods}
    for k in range(n):
        cands = [(m, by[m]["off"][k], cone[k], sigma[k], by[m]["err"][k], raw[m][k])
                 for m, (ok, sigma, cone) in applied.items() if ok[k]]
        if not cands:
            continue
        choice = _skypol.auto_choice(np.array([c[1] for c in cands]), np.array([c[2] for c in cands]),
                                     np.array([c[3] for c in cands]), [c[0] in alone for c in cands],
                                     np.array([c[5] for c in cands]) if mode == "mean_raw" else None)
        if not choice["decided"]:
            continue
        members = [cands[i] for i in choice["members"]]
        pick = cands[choice["sharpest"]]
        if mode == "ranked":  # the most accurate method of the calibration study that agrees
            pick = min(members, key=lambda b: RANK.index(b[0]) if b[0] in RANK else len(RANK))
        if mode in ("ephemeris", "ephemeris_mean"):  # the ephemeris' answer if it agrees, else the
            pick = cands[choice["chosen"]]            # sharpest, or (ephemeris_mean) their mean
        mean = choice["mean"] if mode == "ephemeris_mean" else (mode in ("mean", "mean_raw") and len(members) > 1)
        out_ok[k] = True
        out_sigma[k] = pick[3]
        out_cone[k] = pick[2]
        out_err[k] = float(np.hypot(*choice["mean_offset_deg"])) if mean else pick[4]
    return out_ok, out_err, out_sigma, out_cone


def auto_report(by, cal, bound, mode, site_known=True):
    ok, err, sigma, cone = combine(by, cal, bound, mode, site_known)
    v = int(ok.sum())
    e = err[ok]
    print(f"auto ({mode}{'' if site_known else ', no site'}) all", {"valid": v, "yield": round(v / len(ok), 4),
                                 "lies": int(np.sum((e > LIE_DEG) | (e > LIE_SIGMA * sigma[ok]))),
                                 "coverage": round(float(np.mean(e <= cone[ok])), 4) if v else math.nan,
                                 "median": float(np.median(e)) if v else math.nan})
    # auto against each method on the stacks where both answer.
    site = set(names(lambda e: e["needs_site"]))
    for m, d in by.items():
        if m not in cal or (m in site and not site_known):
            continue
        mok, _, _ = apply(d, cal[m], bound)
        both = ok & mok
        if both.sum() == 0:
            continue
        print(f"  vs {m}: common {int(both.sum())}, medians {float(np.median(d['err'][both])):.4g} (method) "
              f"{float(np.median(err[both])):.4g} (auto); method only {int((mok & ~ok).sum())}, auto only "
              f"{int((ok & ~mok).sum())}")


def read_calibrations(spec):
    """--apply: the registry's calibrations ("committed") or a JSON file's (see the module's doc)."""
    if spec == "committed":
        return {n: m["calibration"] for n, m in registry().items()}
    with open(spec) as f:
        data = json.load(f)
    if isinstance(data, list):  # `skypol methods --json`
        data = {m["name"]: m["calibration"] for m in data}
    fields = set(_skypol.calibration_fields())
    for m, c in data.items():
        unknown = sorted(set(c) - fields)
        if unknown:
            raise SystemExit(f"{spec}: {m}: unknown key {', '.join(unknown)} (expected MethodCalibration's fields: "
                             f"{', '.join(_skypol.calibration_fields())})")
    return data


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv", nargs="+", help="calibration.csv of one or more uncalibrated runs (seeds), pooled")
    ap.add_argument("--bound", type=float, default=2.5, help="largest 95 %% cone an answer may have (the study's "
                    "--max-uncertainty, default 2.5)")
    ap.add_argument("--apply", help="committed (the registry's calibrations) or a JSON file of calibrations")
    ap.add_argument("--replace", nargs="*", default=[], help="calibration.csv of --methods re-runs of the same seeds and counts: their "
                    "methods' rows replace those of CSV")
    ap.add_argument("--plot", help="write the reliability diagram of the calibration (PNG) here")
    ap.add_argument("--auto", default="both", choices=["sharpest", "ranked", "ephemeris", "ephemeris_mean", "mean", "mean_raw", "both"])
    ap.add_argument("--max-coverage", type=float, default=0.98,
                    help="upper end of the coverage band the search accepts (1: any zero-lie calibration)")
    ap.add_argument("--margin", type=float, default=1.0,
                    help="the search counts a lie at error > 5·margin·σ (0.7: room for seeds the search does not read)")
    ap.add_argument("--only", nargs="*", help="search (or apply) these methods only")
    ap.add_argument("--min-sky-coverage", type=float, default=0.0,
                    help=f"the search also requires this coverage of each sky model with at least {SKY_MIN_ANSWERS} "
                    "answers (0: pooled only)")
    ap.add_argument("--sky-wilson", action="store_true",
                    help="with --min-sky-coverage: a sky model with fewer answers also fails when the top of its "
                    "coverage's 95 %% Wilson interval is below the rule")
    ap.add_argument("--grid", action="append", default=[], metavar="FIELD=V,V,...",
                    help=f"search only these values of one MethodCalibration field ({', '.join(TERMS + GATES)})")
    a = ap.parse_args()
    global MAX_COVERAGE, MARGIN, MIN_SKY_COVERAGE, SKY_WILSON
    for g in a.grid:
        name, _, values = g.partition("=")
        if name not in TERMS + GATES:
            ap.error(f"--grid {g}: no grid named {name!r} (one of {', '.join(TERMS + GATES)})")
        GRID[name] = [float(x) for x in values.split(",")]
    MAX_COVERAGE = a.max_coverage
    MARGIN = a.margin
    MIN_SKY_COVERAGE = a.min_sky_coverage
    SKY_WILSON = a.sky_wilson
    by = load(a.csv, a.replace)
    if a.only:
        by = {m: d for m, d in by.items() if m in a.only}
    if a.apply:
        cal = read_calibrations(a.apply)
    else:
        cal = {}
        for m, d in by.items():
            best = search(m, d, a.bound)
            if best is None:
                print(f"{m}: no calibration meets zero lies and 90-{100 * MAX_COVERAGE:.0f} % coverage")
                continue
            cal[m] = best[1]
        print(json.dumps(cal, indent=1))
    skies = sorted(set(next(iter(by.values()))["sky"]))
    for m, d in by.items():
        if m not in cal:
            continue
        ok, sigma, cone = apply(d, cal[m], a.bound)
        print(m, "all", stats(d, ok, sigma, cone))
        for sky in skies:
            print(m, sky, stats(d, ok, sigma, cone, d["sky"] == sky))
        seeds = sorted(set(d["seed"]))
        for seed in seeds if len(seeds) > 1 else []:
            print(m, f"seed {seed}", stats(d, ok, sigma, cone, d["seed"] == seed))
    site = names(lambda e: e["needs_site"])
    for mode in (["sharpest", "ranked", "ephemeris", "ephemeris_mean", "mean", "mean_raw"] if a.auto == "both"
                 else [a.auto]):
        auto_report(by, cal, a.bound, mode)
        if any(m in by for m in site) and len(by) > 2:
            auto_report(by, cal, a.bound, mode, site_known=False)
    if a.plot:
        plot(by, cal, a.bound, a.plot, a.auto if a.auto != "both" else "sharpest")


def plot(by, cal, bound, path, mode):
    """The reliability diagram of scripts/benchmarks' section 7 for this calibration: each valid
    answer's stated 95 % cone against its error, and the share inside the cone per bin of cone."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    series = []
    for m, d in by.items():
        if m in cal:
            ok, _, cone = apply(d, cal[m], bound)
            series.append((m, cone[ok], d["err"][ok]))
    ok, err, _, cone = combine(by, cal, bound, mode)
    series.append(("auto", cone[ok], err[ok]))
    import benchmarks_calibration  # scripts/benchmarks_calibration.py: the same diagram as section 7
    benchmarks_calibration.draw_reliability(axes, [(m, f"{m} ({len(x)})", x, y) for m, x, y in series], colors)
    axes[0].legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=110)
    os.replace(path + ".tmp.png", path)


if __name__ == "__main__":
    main()
