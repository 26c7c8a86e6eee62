"""The estimators' registry as the binary states it (`skypol methods --json`, skypole/method_registry.h):
names, traits and calibrations, so that no script keeps a copy of the method list.

    import skypol_methods
    skypol_methods.names()                          # in the order `-m all` runs them
    skypol_methods.names(lambda m: m["needs_site"])  # those that read the stack's site

The binary: skypol_methods.use(PATH), else $SKYPOL_BIN, else build/skypol of this checkout.
"""
import functools
import json
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_binary = None


def use(path):
    """Read the registry from this skypol binary (e.g. a script's --skypol)."""
    global _binary
    _binary = path
    registry.cache_clear()


@functools.lru_cache(maxsize=None)
def registry():
    exe = _binary or os.environ.get("SKYPOL_BIN") or os.path.join(ROOT, "build", "skypol")
    if not os.path.exists(exe):
        raise SystemExit(f"{exe}: no skypol binary to read the estimators from (build it, or set SKYPOL_BIN)")
    out = subprocess.run([exe, "methods", "--json"], check=True, stdout=subprocess.PIPE, text=True).stdout
    return json.loads(out)


def names(keep=None):
    """The registered methods' names (not "auto"), those `keep(entry)` accepts when given."""
    return [m["name"] for m in registry() if keep is None or keep(m)]
