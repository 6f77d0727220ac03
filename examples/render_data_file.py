#!/usr/bin/env python3
"""Reads a USC-HairSalon `.data` file (100-point strands in metres; wisp converts them to
centimetres) and renders it on the built-in head.

    PYTHONPATH=build/release/python python3 examples/render_data_file.py strands00001.data out.png
"""
import argparse

import numpy as np

import wisp


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", help="a .data file")
    parser.add_argument("output", help="the picture, .png")
    parser.add_argument("--view", default="three-quarter")
    parser.add_argument("--size", type=int, default=512)
    args = parser.parse_args()

    hair = wisp.read(args.data)  # FileNotFoundError / wisp.Error name the file
    lengths = np.diff(hair.offsets.astype(np.int64))
    lo, hi = hair.bounds()
    print(f"{len(hair)} strands, {hair.point_count} points ({lengths.min()}-{lengths.max()} "
          f"per strand), bounds {np.round(lo, 1)} to {np.round(hi, 1)} cm")
    image = wisp.render(hair, view=args.view, size=args.size)
    with open(args.output, "wb") as f:
        f.write(wisp._wisp.encode_png(image))
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
