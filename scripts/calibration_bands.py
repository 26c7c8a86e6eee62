#!/usr/bin/python3
"""Per method and cloud band: yield, lies, median error, coverage; and the unpolarized-share gate
each method would still need (largest share threshold under which no valid answer lies)."""
import csv, sys, statistics as st
rows = list(csv.DictReader(open(sys.argv[1])))
methods = []
for r in rows:
    if r["method"] not in methods: methods.append(r["method"])
bands = [("all", lambda c: True), ("0", lambda c: c == 0), ("0-20", lambda c: 0 < c <= 0.2), ("20-50", lambda c: c > 0.2)]
def summ(sel):
    n = len(sel); v = [r for r in sel if r["valid"] in ("1", "true")]
    lies = sum(1 for r in v if r["lie"] in ("1", "true"))
    inside = sum(1 for r in v if r["inside_cone"] in ("1", "true"))
    errs = [float(r["angular_error_deg"]) for r in v]
    return n, len(v), lies, (st.median(errs) if errs else float("nan")), (inside / len(v) if v else float("nan"))
print("| method | band | stacks | yield | lies | median err (deg) | coverage |")
print("|---|---|---|---|---|---|---|")
for m in methods:
    for name, f in bands:
        sel = [r for r in rows if r["method"] == m and f(float(r["cloud"]))]
        n, v, lies, med, cov = summ(sel)
        print(f"| {m} | {name} | {n} | {v/n if n else 0:.3f} | {lies} | {med:.3f} | {cov:.3f} |")
print()
print("| method | lies: unpolarized share, error | gate needed (share <) | yield with it |")
print("|---|---|---|---|")
for m in methods:
    sel = [r for r in rows if r["method"] == m]
    v = [r for r in sel if r["valid"] in ("1", "true")]
    lies = sorted((float(r["unpolarized_share"]), float(r["angular_error_deg"])) for r in v if r["lie"] in ("1", "true"))
    if not lies:
        print(f"| {m} | none | none | {len(v)/len(sel):.3f} |"); continue
    t = lies[0][0]
    kept = sum(1 for r in v if float(r["unpolarized_share"]) < t)
    print(f"| {m} | {', '.join(f'{s:.2f}:{e:.1f}' for s, e in lies)} | {t:.2f} | {kept/len(sel):.3f} |")
