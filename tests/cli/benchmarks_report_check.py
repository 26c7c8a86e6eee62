#!/usr/bin/python3
"""docs/benchmarks.md is generated whole by scripts/benchmarks from its committed data.

    benchmarks_report_check.py SKYPOL ROOT

1. `scripts/benchmarks --replot` on a copy of docs/figures/benchmarks/ writes docs/benchmarks.md
   byte for byte: every section, the hand-measured ones included from their docs/benchmarks-*.md
   files, comes from the run's CSVs, its run.json and `skypol methods` (a section edited by hand, or
   a calibration changed without regenerating the page, fails here).
2. Section 7's figures against the calibration CSV read here, independently of the report's code:
   the number of scenes, each method's answers and lies, and the population's sky shares.
"""
import csv
import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections import Counter

skypol, root = sys.argv[1], sys.argv[2]
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


committed = os.path.join(root, "docs", "benchmarks.md")
with open(committed) as f:
    page = f.read()

with tempfile.TemporaryDirectory() as out:
    shutil.copytree(os.path.join(root, "docs", "figures", "benchmarks"), os.path.join(out, "figures", "benchmarks"))
    subprocess.run(["/usr/bin/python3", os.path.join(root, "scripts", "benchmarks"), "--replot", "--out", out,
                    "--skypol", skypol], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "benchmarks.md")) as f:
        regenerated = f.read()
if regenerated != page:
    a, b = page.splitlines(), regenerated.splitlines()
    first = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
    failures.append(f"scripts/benchmarks --replot does not regenerate docs/benchmarks.md: first difference at line "
                    f"{first + 1}:\n  committed:   {a[first] if first < len(a) else '(end)'}\n"
                    f"  regenerated: {b[first] if first < len(b) else '(end)'}")

# Section 7 against the CSV, counted here.
with open(os.path.join(root, "docs", "figures", "benchmarks", "calibration.csv")) as f:
    rows = list(csv.DictReader(f))
scenes = {r["stack"]: r for r in rows}
n = len(scenes)
section = page[page.index("## 7. Calibration"):page.index("## 8.")]
check(re.search(rf"^{n} scenes of the `realistic` population \(seed {rows[0]['seed']}, binning "
                rf"{rows[0]['binning']}\)", section, re.M),
      f"section 7 does not open with the {n} scenes of the CSV")
skies = Counter(r["sky"] for r in scenes.values())
for sky, count in skies.items():
    share = f"{sky} {round(100 * count / n)} %"
    check(share in section, f"section 7 lacks the sky share '{share}'")
for method in sorted({r["method"] for r in rows}):
    mine = [r for r in rows if r["method"] == method]
    valid = sum(r["valid"] == "1" for r in mine)
    lies = sum(r["lie"] == "1" for r in mine)
    row = re.search(rf"^\| {method} \| (\d+)/(\d+) \| [^|]+ \| (\d+) \|", section, re.M)
    check(row is not None, f"section 7 has no row for {method}")
    if row:
        check((int(row[1]), int(row[2]), int(row[3])) == (valid, len(mine), lies),
              f"section 7's {method}: {row[1]}/{row[2]} valid, {row[3]} lies; the CSV: {valid}/{len(mine)}, {lies}")

for f in failures:
    print("FAIL:", f)
print(f"benchmarks report: {len(failures)} failure(s); {n} scenes, {len(skies)} skies checked")
sys.exit(1 if failures else 0)
