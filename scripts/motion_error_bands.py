#!/usr/bin/env python3
"""Where V's error lies: es_eval's motion_gt.csv binned along one world axis.

Per band of the axis (width W world units): the points, their share of the
relative EPE (the band's summed error over all points' summed true speed;
the shares add up to es_eval's rel. EPE), the mean true and model speed and
the band's own relative EPE.
"""
import argparse
import csv
import math
import sys


def main():
    parser = argparse.ArgumentParser(
        prog="scripts/motion_error_bands.py",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", help="es_eval's OUT/motion_gt.csv")
    parser.add_argument("--axis", choices="xyz", default="y",
                        help="world axis to bin along (default y)")
    parser.add_argument("--width", type=float, default=0.5,
                        help="band width in world units (default 0.5)")
    args = parser.parse_args()
    if args.width <= 0:
        sys.exit("motion_error_bands.py: --width must be > 0")
    try:
        with open(args.csv, newline="") as f:
            rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"motion_error_bands.py: {args.csv}: {e}")
    if not rows:
        sys.exit(f"motion_error_bands.py: {args.csv}: no points")

    def vec(r, prefix):
        return [r[prefix + c] for c in ("x", "y", "z")]

    total_speed = sum(math.hypot(*vec(r, "true_v")) for r in rows)
    bands = {}
    for r in rows:
        key = math.floor(r[args.axis] / args.width)
        err = math.dist(vec(r, "model_v"), vec(r, "true_v"))
        b = bands.setdefault(key, [0, 0.0, 0.0, 0.0])
        b[0] += 1
        b[1] += err
        b[2] += math.hypot(*vec(r, "true_v"))
        b[3] += math.hypot(*vec(r, "model_v"))
    print(f"| {args.axis} band | points | share of rel. EPE | true speed "
          "| model speed | band rel. EPE |")
    print("|---|---|---|---|---|---|")
    for key in sorted(bands):
        n, err, true, model = bands[key]
        lo = key * args.width
        print(f"| {lo:.2f} .. {lo + args.width:.2f} | {n} | "
              f"{err / total_speed:.3f} | {true / n:.3f} | {model / n:.3f} | "
              f"{err / true if true > 0 else float('nan'):.2f} |")
    print(f"all: {len(rows)} points, rel. EPE "
          f"{sum(b[1] for b in bands.values()) / total_speed:.3f}")


if __name__ == "__main__":
    main()
