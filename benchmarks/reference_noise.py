"""Are the reference solver's standard errors honest where they matter most (twilight)?

    python benchmarks/reference_noise.py [--preset earth] [--paths 3000]

Solves the twilight rays of benchmarks/tables_pareto.py's query set twice with different seeds and compares
the RMS relative difference of the two with the one their reported standard errors predict. The Pareto
benchmark removes the reference's noise from the tables' RMS error using these standard errors, so they
must not be underestimated.
"""
import argparse

import numpy as np

from planetviz import load_atmosphere
from planetviz.reference import solve
from tables_pareto import query_set


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--preset", default="earth")
    ap.add_argument("--paths", type=int, default=3000)
    args = ap.parse_args()
    atm = load_atmosphere(args.preset)
    queries = query_set(atm)
    twilight = queries[3] < 2
    a, b = (solve(atm, *(x[twilight] for x in queries[:3]), samples=args.paths, seed=s) for s in (11, 12))
    ok = (a.radiance > 1e-5) & (b.radiance > 1e-5)
    diff = (a.radiance[ok] - b.radiance[ok]) / (0.5 * (a.radiance[ok] + b.radiance[ok]))
    predicted = np.sqrt((a.stderr[ok] / a.radiance[ok]) ** 2 + (b.stderr[ok] / b.radiance[ok]) ** 2)
    print(f"{args.preset}: {ok.sum()} twilight ray-wavelengths, {args.paths} paths: RMS relative difference "
          f"between two seeds {np.sqrt(np.mean(diff ** 2)):.4f}, predicted from the standard errors "
          f"{np.sqrt(np.mean(predicted ** 2)):.4f}; 95th percentile of |difference| / predicted "
          f"{np.percentile(np.abs(diff) / predicted, 95):.2f} (1.96 for Gaussian errors)")


if __name__ == "__main__":
    main()
