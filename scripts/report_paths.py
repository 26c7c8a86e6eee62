"""Where a report script writes. A full run regenerates the committed report under docs/; a
--small run proves the pipeline on tiny images and its numbers must never replace the committed
ones, so it writes under build/reports/NAME/ instead; --out DIR overrides both."""
import os


def report_dir(root, name, small, out=None):
    if out:
        return out
    if small:
        return os.path.join(root, "build", "reports", name)
    return os.path.join(root, "docs")


def print_paths(paths):
    """--print-paths: one `key path` line each, absolute, so that a test can check them."""
    for key, path in paths.items():
        print(key, os.path.abspath(path))
