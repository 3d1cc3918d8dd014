"""Precompute time of the working tree against earlier commits, measured in one run (an A/B).

    python benchmarks/precompute_ab.py [--commits 21830d0 cf86fba] [--atmosphere earth] [--quality standard] \\
        [--rounds 6] [--repeat 3]

Each commit is checked out in a temporary git worktree (its shaders/ and assets/ linked into its package, as an
install places them). Every round runs one fresh process per tree, in turn, each timing ``--repeat`` precomputes of
the atmosphere at the quality level with no cache (``precompute(atm, QUALITY[level], cache=None)``); the trees
alternate within the round so that this machine's drift (10-30% between minutes) falls on all of them alike.
Printed: per tree, the mean, median, min and max seconds per precompute and the mean's standard error.
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
import sys, time
from planetviz import load_atmosphere
from planetviz.tables import QUALITY, precompute
atm = load_atmosphere(sys.argv[1])
for _ in range(int(sys.argv[3])):
    t = time.perf_counter()
    precompute(atm, QUALITY[sys.argv[2]], cache=None)
    print(time.perf_counter() - t)
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
    """Seconds of ``args.repeat`` precomputes in one fresh process importing planetviz from ``tree``."""
    out = subprocess.run([sys.executable, "-c", TIMER, args.atmosphere, args.quality, str(args.repeat)],
                         env={**os.environ, "PYTHONPATH": str(tree)}, cwd=tempfile.gettempdir(),
                         check=True, capture_output=True, text=True)
    return [float(x) for x in out.stdout.split()]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--commits", nargs="*", default=["21830d0", "cf86fba"])
    parser.add_argument("--atmosphere", default="earth")
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
            for _ in range(args.rounds):
                for name, tree in trees.items():
                    seconds[name] += times(tree, args)
            print(f"{args.atmosphere} {args.quality}: {args.rounds} rounds x {args.repeat} precomputes per tree")
            for name, s in seconds.items():
                s = np.array(s)
                print(f"{name:>14}: mean {s.mean():.2f} s (se {s.std(ddof=1) / np.sqrt(len(s)):.2f})  "
                      f"median {np.median(s):.2f}  min {s.min():.2f}  max {s.max():.2f}")
        finally:
            for commit in args.commits:
                subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(Path(tmp) / commit)],
                               capture_output=True)
            subprocess.run(["git", "-C", str(ROOT), "worktree", "prune"], capture_output=True)


if __name__ == "__main__":
    main()
