"""Precompute time and peak memory of the working tree against earlier commits, measured in one run (an A/B).

    python benchmarks/precompute_ab.py [--commits 21830d0 cf86fba] [--atmosphere earth] [--wavelengths I ...] \\
        [--quality standard] [--rounds 6] [--repeat 3]

Each commit is checked out in a temporary git worktree (its shaders/ and assets/ linked into its package, as an
install places them). Every round runs one fresh process per tree, in turn, each timing ``--repeat`` precomputes of
the atmosphere at the quality level with no cache (``precompute(atm, QUALITY[level], cache=None)``); the trees
alternate within the round so that this machine's drift (10-30% between minutes) falls on all of them alike.
``--atmosphere`` is named as in orders_sum.py (a preset, random-SEED, twin-SEED, conservative); ``--wavelengths``
keeps only the wavelengths of those indices (``validation.disort.only_wavelengths``).
Printed: per tree, the mean, median, min and max seconds per precompute, the mean's standard error, and the
largest peak resident memory of its processes (``resource.getrusage``'s ``ru_maxrss``).
"""
import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

TIMER = """
import resource, sys, time
sys.path.insert(0, sys.argv[4])
from orders_sum import atmosphere
from planetviz.tables import QUALITY, precompute
atm = atmosphere(sys.argv[1])
if sys.argv[5:]:
    from planetviz.validation.disort import only_wavelengths
    atm = only_wavelengths(atm, [int(i) for i in sys.argv[5:]])
for _ in range(int(sys.argv[3])):
    t = time.perf_counter()
    precompute(atm, QUALITY[sys.argv[2]], cache=None)
    print(time.perf_counter() - t)
print("peak", resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024)
"""


def checkout(commit, folder):
    """A worktree of ``commit`` in ``folder`` whose package finds its shaders and assets, as installed."""
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-f", str(folder), commit],
                   check=True, capture_output=True)
    for name in ("shaders", "assets"):
        link = folder / "planetviz" / name
        if not link.exists():
            link.symlink_to(folder / name)


def times(tree, args):
    """(seconds of ``args.repeat`` precomputes, peak resident bytes) in one fresh process importing planetviz from
    ``tree``."""
    out = subprocess.run([sys.executable, "-c", TIMER, args.atmosphere, args.quality, str(args.repeat),
                          str(ROOT / "benchmarks")] + [str(i) for i in args.wavelengths],
                         env={**os.environ, "PYTHONPATH": str(tree)}, cwd=tempfile.gettempdir(),
                         capture_output=True, text=True)
    if out.returncode:
        raise SystemExit(f"{tree}: the precompute failed:\n{out.stderr}")
    lines = out.stdout.split("\n")
    peak = next(int(line.split()[1]) for line in lines if line.startswith("peak"))
    return [float(x) for x in lines if x and not x.startswith("peak")], peak


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--commits", nargs="*", default=["21830d0", "cf86fba"])
    parser.add_argument("--atmosphere", default="earth")
    parser.add_argument("--wavelengths", type=int, nargs="*", default=[])
    parser.add_argument("--quality", default="standard")
    parser.add_argument("--rounds", type=int, default=6)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        trees = {"working tree": ROOT}
        try:
            for commit in args.commits:
                trees[commit] = Path(tmp) / commit
                checkout(commit, trees[commit])
            seconds = {name: [] for name in trees}
            peaks = {name: 0 for name in trees}
            for _ in range(args.rounds):
                for name, tree in trees.items():
                    s, peak = times(tree, args)
                    seconds[name] += s
                    peaks[name] = max(peaks[name], peak)
            kept = f" wavelengths {args.wavelengths}" if args.wavelengths else ""
            print(f"{args.atmosphere}{kept} {args.quality}: {args.rounds} rounds x {args.repeat} precomputes per tree")
            for name, s in seconds.items():
                s = np.array(s)
                se = s.std(ddof=1) / np.sqrt(len(s)) if len(s) > 1 else float("nan")
                print(f"{name:>14}: mean {s.mean():.2f} s (se {se:.2f})  median {np.median(s):.2f}  "
                      f"min {s.min():.2f}  max {s.max():.2f}  peak memory {peaks[name] / 1e9:.2f} GB")
        finally:
            for commit in args.commits:
                subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(Path(tmp) / commit)],
                               capture_output=True)
            subprocess.run(["git", "-C", str(ROOT), "worktree", "prune"], capture_output=True)


if __name__ == "__main__":
    main()
