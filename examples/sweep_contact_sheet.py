#!/usr/bin/env python3
"""A parameter sweep to a contact sheet: one picture per solver stiffness (Choe & Ko Fig. 9),
laid out left to right in one PNG.

    PYTHONPATH=build/release/python python3 examples/sweep_contact_sheet.py sheet.png
"""
import argparse

import numpy as np

import wisp


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", help="the contact sheet, .png")
    parser.add_argument("--preset", default="long-straight")
    parser.add_argument("--values", default="0.5,1,2,4", help="solve.stiffness values")
    parser.add_argument("--strands", type=int, default=30000)
    parser.add_argument("--size", type=int, default=384, help="pixels per picture")
    args = parser.parse_args()

    head = wisp.Head.builtin()  # loaded once, shared by every run
    style = wisp.Style.preset(args.preset)
    style.roots.wisps = min(style.roots.wisps, args.strands)  # first: strands >= wisps
    style.roots.strands = args.strands
    pictures = []
    for value in map(float, args.values.split(",")):
        style.solve.stiffness = value  # ValueError naming the range if out of it
        hair = wisp.generate(style, head=head, seed=1)
        pictures.append(wisp.render(hair, view="front", size=args.size))
        print(f"stiffness {value}: {len(hair)} strands, solve "
              f"{hair.stats['time_ms']['solve']:.0f} ms")
    sheet = np.concatenate(pictures, axis=1)  # H×(n·W)×3 uint8
    with open(args.output, "wb") as f:
        f.write(wisp._wisp.encode_png(sheet))
    print(f"wrote {args.output} ({sheet.shape[1]}×{sheet.shape[0]})")


if __name__ == "__main__":
    main()
