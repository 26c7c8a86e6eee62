"""Report scripts: a --small run writes under build/, never over the committed docs/ (issue 16),
and a full run still regenerates docs/. Each script is asked where it would write (--print-paths,
which runs nothing), in each mode."""
import os
import subprocess
import sys

ROOT = sys.argv[1]
failures = []


def paths(script, *flags):
    out = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", script), *flags, "--print-paths"],
                         check=True, stdout=subprocess.PIPE, text=True).stdout
    return dict(line.split(" ", 1) for line in out.splitlines())


def under(path, folder):
    return os.path.commonpath([os.path.realpath(path), os.path.realpath(folder)]) == os.path.realpath(folder)


docs, build = os.path.join(ROOT, "docs"), os.path.join(ROOT, "build")
for script, report_key in (("benchmarks", "report"), ("reproduce", "report")):
    for key, p in paths(script, "--small").items():
        if not under(p, build) or under(p, docs):
            failures.append(f"{script} --small writes {key} to {p}, not under build/")
    full = paths(script)
    if not under(full[report_key], docs):
        failures.append(f"{script} (full) writes its report to {full[report_key]}, not under docs/")
    for key, p in paths(script, "--small", "--out", "/tmp/skypol-out").items():
        if not under(p, "/tmp/skypol-out"):
            failures.append(f"{script} --small --out /tmp/skypol-out writes {key} to {p}")

for f in failures:
    print("FAILED:", f)
sys.exit(1 if failures else 0)
