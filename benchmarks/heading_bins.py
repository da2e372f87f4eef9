"""Print the heading error per bin of the true heading, with front/back flips, from run summaries.

    python benchmarks/heading_bins.py results/runs/<train>/<rig>/<desc>/<feat>/sets/<set>/summary.json [...]

One table per summary and method (``heading_by_bin`` of ``voxpose.evaluation.metrics``): the bin, its frames,
the RMS heading error and the fraction of frames more than 135 degrees off.
"""

import json
import sys


def main(paths):
    for path in paths:
        methods = json.load(open(path))["methods"]
        for method, errors in methods.items():
            print(f"\n{path} :: {method} (heading RMS {errors['heading']:.1f} deg)")
            print(f"{'bin (deg)':>12} {'frames':>7} {'RMS':>7} {'flips':>7}")
            for row in errors.get("heading_by_bin", []):
                print(f"{row['from']:5.0f}-{row['to']:<6.0f} {row['frames']:7d} {row['rms']:7.1f} {row['flips']:7.1%}")


if __name__ == "__main__":
    main(sys.argv[1:])
