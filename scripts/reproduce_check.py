"""Checks of scripts/reproduce --check: values that could be wrong, each against something other
than the code that computed it (an identity, a closed form, the papers' numbers, an invariant).
Never timings. Returns the list of failures (empty when everything holds)."""
import math
import os
import re


def check(r, g, report, figdir):
    fails = []

    def need(ok, what):
        if not ok:
            fails.append(what)

    # Sun et al.: ERFA against the paper's SPA elevations (refraction on, as SPA): within 0.05°.
    need(sorted(p["time_local"] for p in r["positions"]) == sorted(g["SUN_T1"]), "sun2019: not the times of Table 1")
    for p in r["positions"]:
        d = abs(float(p["elevation_deg"]) - float(p["paper_elevation_deg"]))
        need(d < 0.05, f"sun elevation at {p['time_local']}: ERFA {p['elevation_deg']} vs paper {p['paper_elevation_deg']}")

    eps = r["eps"]
    need(len(eps) == len(r["times"]) * 2 * 2 * 7, f"epsilon rows: {len(eps)}")
    for (t, norm, region, cam, model), (e, n) in eps.items():
        key = f"ε({cam}, {model}) {t} {norm} {region}"
        need(n > 0, key + ": no pixels")
        need(0 <= e <= 100, key + f" = {e} outside [0, 100]")
        if cam == model:
            need(e == 100, key + f" = {e}, expected 100 % (a mode against itself)")
    for t in r["times"]:
        for norm in ("fov_circle", "horizon_circle"):
            full = lambda cam, model: eps[(t, norm, "full", cam, model)][0]  # noqa: E731
            # The modes do differ over 140°, and in the paper's order (their Table 3):
            # equisolid is closest to an equidistant camera, then stereographic, then VP
            # (ties at 100 % where the whole field agrees within 5°).
            need(full("equidistant", "orthographic") < 99, f"ε(EI, VP) {t} {norm}: the modes should differ")
            ea, st, vp = (full("equidistant", m) for m in ("equisolid", "stereographic", "orthographic"))
            need(ea >= st >= vp and ea > vp, f"ε order EA ≥ S ≥ VP for an equidistant camera at {t} {norm}")
        # With the field-of-view edge on one image circle all modes see the same 140° disk: the
        # pixel count is the same for every camera.
        counts = {eps[(t, "fov_circle", "full", m, "orthographic")][1] for m in g["MODES"]}
        need(len(counts) == 1, f"fov_circle pixel counts differ at {t}: {counts}")

    # Fig. 7: the vertical projection against itself is identically 0; the DoP ranges of the modes
    # agree (same sky, other pixels): ΔDoP within [−1, 1].
    need(r["fig7"]["orthographic"][0] == 0 and r["fig7"]["orthographic"][1] == 0, "Fig. 7: VP − VP not zero")
    for m in g["MODES"]:
        need(0 <= r["fig7"][m][0] <= 1, f"Fig. 7: |ΔDoP| of {m} = {r['fig7'][m][0]}")

    # Magnification: numerical derivatives of project() against eqs. 23–28 (and the same closed
    # forms for perspective and orthographic), in units of f: central differences with h = 1e-5
    # are good to ~1e-9 inside, one-sided at the field edge to ~h.
    edge = {}
    for row in r["mag"]:
        edge[row["mode"]] = max(edge.get(row["mode"], 0.0), float(row["theta_deg"]))
    for row in r["mag"]:
        at_edge = float(row["theta_deg"]) == edge[row["mode"]]
        for k in ("radial", "tangential"):
            closed = float(row[k + "_closed"])
            dev = abs(float(row[k + "_numeric"]) - closed)
            # Inside: central differences, ~1e-9 relative. At the field edge one-sided, error
            # ≈ (h/2)·|dβ/dθ|: up to 6e-5 relative for perspective at 80° (β_r = sec²θ).
            tol = (1e-4 if at_edge else 1e-6) * max(1.0, closed)
            need(dev <= tol, f"magnification {row['mode']} {k} at {row['theta_deg']}°: {row[k + '_numeric']} vs closed {closed}")
    need({row["mode"] for row in r["mag"]} == {"equidistant", "equisolid", "stereographic", "orthographic", "perspective"},
         "magnification: a mode is missing")
    # The paper's quoted values: equidistant β_t(90°) = 1.57 f, equisolid β_r(90°) = 0.707 f and
    # β_t(90°) = 1.414 f, stereographic β(90°) = 2 f.
    at90 = {row["mode"]: row for row in r["mag"] if float(row["theta_deg"]) == 90}
    for mode, key, want in [("equidistant", "tangential", 1.5708), ("equisolid", "radial", 0.7071),
                            ("equisolid", "tangential", 1.4142), ("stereographic", "radial", 2.0)]:
        need(abs(float(at90[mode][key + "_numeric"]) - want) < 1e-3, f"β of {mode} at 90° vs the paper's {want}")

    # SkyPole SI Set 1: every radial curve passes through the pole (altitude = latitude at α = 0),
    # Rayleigh's DoLP is equal at the two times along it (up to the declination's drift), and the
    # rendered |ΔDoLP| along it is far below the image's typical value.
    lat = float(r["setup"]["latitude_deg"])
    for st in r["set1"]:
        need(abs(float(st["pole_altitude_on_curve_deg"]) - lat) < 1e-6, f"Set 1 pair {st['pair']}: curve misses the pole")
        need(float(st["max_rayleigh_absdiff_on_curve"]) < 2e-3, f"Set 1 pair {st['pair']}: analytic ΔDoLP on the curve")
        need(int(st["curve_points"]) > 20, f"Set 1 pair {st['pair']}: too few curve points in the image")
        need(float(st["max_absdiff_on_curve"]) < 0.15 * float(st["median_absdiff_image"]),
             f"Set 1 pair {st['pair']}: rendered |ΔDoLP| on the curve {st['max_absdiff_on_curve']}")

    # Fig. 1D: thresholds positive and finite.
    for k, v in r["fig1d"].items():
        if k.startswith("threshold."):
            need(0 < float(v) < 1, f"Fig. 1D {k} = {v}")

    # Fig. 3 protocol: every (heading, method) row present for the day with and without the sensor
    # and for every window; valid rows finite; noise-free better estimators within 0.05°.
    rows = r["protocol_rows"]
    headings = {row["heading_deg"] for row in rows}
    need(len(headings) == int(r["setup"]["headings"]), "protocol: headings missing")
    for run, sensor in (("day", "0"), ("day", "1"), ("window", "1")):
        for m in g["METHODS"]:
            got = [row for row in rows if row["run"] == run and row["sensor"] == sensor and row["method"] == m]
            need(len(got) >= len(headings), f"protocol rows missing: {run} sensor={sensor} {m}")
    for row in rows:
        if row["valid"] == "1":
            for k in ("latitude_error_deg", "angular_error_deg", "seconds"):
                need(row[k] != "" and math.isfinite(float(row[k])), f"protocol row not finite: {row}")
        else:
            need(row["why_invalid"] != "", f"protocol: invalid row without a reason: {row}")
    # Every method but the paper's classic and invariance (whose sub-pixel model leaves a numerical
    # error of its own) reaches the noise-free target.
    for m in (m for m in g["METHODS"] if m not in ("classic", "invariance")):
        for row in rows:
            if row["run"] == "day" and row["sensor"] == "0" and row["method"] == m:
                need(row["valid"] == "1" and float(row["angular_error_deg"]) < g["NOISE_FREE_TARGET"],
                     f"noise-free {m} at heading {row['heading_deg']}: {row['angular_error_deg']}")
    for row in rows:
        if row["method"] in g["SITE"] and row["valid"] == "1":
            need(abs(float(row["latitude_error_deg"])) < 1e-9, f"{row['method']} latitude must be the site's")

    # The VRTE sky: multiple scattering and aerosol lower the pole's DoLP below single scattering's at every
    # time; every value finite; the maximum DoLP falls as the aerosol load grows at every wavelength; a Babinet
    # point exists (within 40° of the sun) at every sun elevation; every estimator has rows, with reasons when invalid.
    v = r["vrte"]
    for x in v["pole"]:
        need(0 < float(x["dolp_vrte"]) < float(x["dolp_single"]), f"vrte pole DoLP not below single scattering: {x}")
    for x in v["neutral"]:
        need(x["babinet_from_sun_deg"] != "" and 0 < float(x["babinet_from_sun_deg"]) < 40,
             f"vrte Babinet point missing or far: {x}")
    mx = v["max_dolp"]
    for w in {x["wavelength_nm"] for x in mx}:
        rr = sorted((float(x["tau_550"]), float(x["max_dolp"])) for x in mx if x["wavelength_nm"] == w)
        need(all(a[1] > b[1] for a, b in zip(rr, rr[1:])), f"vrte max DoLP does not fall with aerosol at {w} nm: {rr}")
        need(all(0 < d < 1 for _, d in rr), f"vrte max DoLP outside (0, 1) at {w} nm")
    methods = {x["method"] for x in v["protocol_rows"]}
    need(methods >= set(g["METHODS"]), f"vrte protocol methods: {sorted(methods)}")
    for row in v["protocol_rows"]:
        if row["valid"] != "1":
            need(row["why_invalid"] != "", f"vrte protocol: invalid row without a reason: {row}")

    # The report and its figures.
    text = open(report).read()
    for name in ("sun2019_fig7", "sun2019_epsilon", "sun2019_magnification", "skypole_fig1d", "skypole_set1",
                 "skypole_fig3", "skypole_windows", "vrte_sky"):
        path = os.path.join(figdir, name + ".png")
        need(os.path.exists(path), f"figure {name} missing")
        if os.path.exists(path):
            need(os.path.getsize(path) < 200_000, f"figure {name} is {os.path.getsize(path)} bytes (> 200 kB)")
        need(name + ".png" in text, f"report does not show {name}")
    need(re.search(r"\bnan\b|\binf\b", text, re.IGNORECASE) is None, "report contains NaN or Inf")
    # Files are named relative to the repository: the generating machine's absolute path means
    # nothing to a reader (docs/reproduction.md once named /work/main/scenes/…).
    root = os.path.abspath(g["ROOT"])
    need(root not in text, f"report names a file by its absolute path under {root}")
    return fails
