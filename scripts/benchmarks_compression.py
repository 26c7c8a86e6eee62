"""The compression section of docs/benchmarks.md (scripts/benchmarks): `skypol tradeoff compression`'s
two tables turned into a plot, two tables and the recommended pixel type, compression and zip level.
Kept apart from scripts/benchmarks, which is long enough; it passes its own helpers in `h`."""
import os

# The defaults scene/scene.h sets (OutputSpec) and docs/scenes.md states; this section says why.
DEFAULT = ("half", "zip", 4.0)


def setting_name(r):
    z = f" {int(r['zip_level'])}" if r.get("zip_level") is not None else ""
    return f"{r['pixel_type']} {r['compression']}{z}"


def estimator_change(est, pixel_type, compression, stack):
    """Largest |angular error − float lossless's| over headings and methods; None if a row is missing
    or the setting made a valid estimate invalid."""
    ref = {(r["heading_deg"], r["method"]): r for r in est
           if r["pixel_type"] == "float" and r["compression"] == "lossless" and r["stack"] == stack}
    worst = 0.0
    rows = [r for r in est if r["pixel_type"] == pixel_type and r["compression"] == compression and r["stack"] == stack]
    if not rows:
        return None
    for r in rows:
        f = ref.get((r["heading_deg"], r["method"]))
        if f is None or f["valid"] != 1:
            continue
        if r["valid"] != 1:
            return float("inf")
        worst = max(worst, abs(r["angular_error_deg"] - f["angular_error_deg"]))
    return worst


def sensor_effect(est):
    """What the DoFP sensor itself does to each estimate: the largest |error(sensor) − error(ideal)|."""
    ideal = {(r["heading_deg"], r["method"]): r for r in est
             if r["pixel_type"] == "float" and r["compression"] == "lossless" and r["stack"] == "ideal"}
    out = 0.0
    for r in est:
        if r["pixel_type"] == "float" and r["compression"] == "lossless" and r["stack"] == "sensor" and r["valid"] == 1:
            i = ideal.get((r["heading_deg"], r["method"]))
            if i and i["valid"] == 1:
                out = max(out, abs(r["angular_error_deg"] - i["angular_error_deg"]))
    return out


def report(d, fig_dir, h):
    path = os.path.join(d, "compression.csv")
    if not os.path.exists(path):
        return None
    rows = h.read_csv(path)
    est = h.read_csv(os.path.join(d, "compression_estimates.csv"))
    ideal = [r for r in rows if r["stack"] == "ideal"]
    sensor = {setting_name(r): r for r in rows if r["stack"] == "sensor"}
    base = next(r for r in ideal if r["pixel_type"] == "float" and r["compression"] == "none")
    r0 = ideal[0]

    def cls(r):
        return "lossless" if r["exact"] == 1 else r["compression"]

    # Plot: file size against the worst AoLP error, lossless settings at the floor.
    floor = 1e-4
    fig, ax = h.figure(1, 7.5, 4.2)
    for r in ideal:
        x, y = r["file_mb"], h.floor_pos(r["AoLP_deg_max"], floor)
        color = "#1f77b4" if r["pixel_type"] == "float" else "#d62728"
        ax.scatter([x], [y], color=color, marker="o" if r["exact"] == 1 else "x", zorder=3,
                   label=f"{r['pixel_type']}, " + ("exact" if r["exact"] == 1 else "lossy"))
        ax.annotate(setting_name(r).split(" ", 1)[1], (x, y), textcoords="offset points", xytext=(3, 3), fontsize=6)
    h.draw_front(ax, [(r["file_mb"], h.floor_pos(r["AoLP_deg_max"], floor)) for r in ideal])
    dflt = [r for r in ideal if (r["pixel_type"], r["compression"], r.get("zip_level")) == DEFAULT]
    if dflt:
        h.mark_default(ax, dflt[0]["file_mb"], h.floor_pos(dflt[0]["AoLP_deg_max"], floor))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("file size per stack (MB)")
    ax.set_ylabel(f"max AoLP error (°; exact float drawn at {floor:g})")
    ax.grid(alpha=0.3, which="both")
    h.legend_below(fig, ax, ncol=5)
    h.save(fig, os.path.join(fig_dir, "compression.png"))

    tab = []
    for r in ideal:
        s = sensor.get(setting_name(r))
        tab.append([setting_name(r), h.fmt(r["file_mb"]), h.fmt(base["file_mb"] / r["file_mb"]),
                    h.fmt(r["write_s"]), h.fmt(r["read_s"]), "yes" if r["exact"] == 1 else "**no**",
                    h.fmt(r["S0_max"]), h.fmt(r["DoLP_max"]), h.fmt(r["AoLP_deg_max"]),
                    h.fmt(estimator_change(est, r["pixel_type"], cls(r), "ideal")),
                    h.fmt(s["file_mb"]) if s else "—",
                    h.fmt(estimator_change(est, s["pixel_type"], cls(s), "sensor")) if s else "—"])
    noise = sensor_effect(est)
    half_zip = next((r for r in ideal if (r["pixel_type"], r["compression"], r.get("zip_level")) == DEFAULT), None)
    float_zip = next((r for r in ideal if (r["pixel_type"], r["compression"], r.get("zip_level")) ==
                      ("float", "zip", 4.0)), None)
    lossy = [r for r in ideal if r["exact"] != 1]
    body = [
        f"The paper's day, {h.day_text(rows)}, at {int(r0['width'])}×{int(r0['height'])} "
        f"(the 2448×2048 sensor binned {2448 // int(r0['width'])}×), {h.headings_text(est)} of the "
        "Fig. 3 protocol, written by `stack::write_stack` with each pixel type × compression, read back "
        "by `stack::read_stack`, and compared with the floats that were written: the ideal stack the default "
        "scene writes (S0 S1 S2 DoLP AoLP mask) and the DoFP sensor's (DoLP AoLP mask, 1 ms). Sizes and "
        "times are means over the headings; errors are maxima over the sky pixels. *exact*: every decoded "
        "pixel equals the written value rounded to the pixel type, so the compression itself lost nothing. "
        "*Δ estimators*: the largest change of any estimator's angular error against float lossless, over "
        f"headings and methods. For scale, the DoFP sensor itself changes them by up to {h.fmt(noise)}°.",
        "",
        "```sh",
        "skypol tradeoff compression --out DIR   # --binning B for another size; --small: seconds",
        "```",
        "",
        "![compression](figures/benchmarks/compression.png)",
        "",
        h.table(["setting", "MB", "× smaller", "write s", "read s", "exact", "S0 max", "DoLP max", "AoLP max °",
                 "Δ estimators °", "sensor MB", "sensor Δ °"], tab),
        "",
        "Lossy on Stokes channels, so a scene needs `[output] allow_lossy = true` to write them "
        "(scene/scene_output.cpp names the loss): " +
        ", ".join(f"{setting_name(r)} (AoLP {h.fmt(r['AoLP_deg_max'])}°)" for r in lossy) + ".",
    ]
    rec = "half, zip, level 4 (OpenEXR's default)"
    why = "—"
    if half_zip and float_zip:
        why = (f"{h.fmt(float_zip['file_mb'] / half_zip['file_mb'])}× smaller than float zip and "
               f"{h.fmt(base['file_mb'] / half_zip['file_mb'])}× smaller than float none; exact (half's own "
               f"rounding: AoLP ≤ {h.fmt(half_zip['AoLP_deg_max'])}°, DoLP ≤ {h.fmt(half_zip['DoLP_max'])}); "
               f"estimators move by ≤ {h.fmt(estimator_change(est, 'half', 'lossless', 'ideal'))}° against the "
               f"sensor's {h.fmt(noise)}°; higher zip levels save a few per cent for several times the write time")
    return "\n".join(body), (rec, why)
