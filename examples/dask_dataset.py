#!/usr/bin/env python3
"""A dataset loop on Dask's LocalCluster: sample k is a pure function of (preset, k), so
workers generate in any order and the set is the same every time. Each worker writes one
`.npz` (strands resampled to 32 points) and returns a few figures.

    PYTHONPATH=build/release/python python3 examples/dask_dataset.py out/ --samples 8
"""
import argparse
import os
import pathlib


def make_sample(k, preset, strands, out_dir):
    import wisp  # imported in the worker process

    style = wisp.Style.preset(preset)
    style.roots.wisps = min(style.roots.wisps, strands)  # first: strands >= wisps
    style.roots.strands = strands
    # The sample's own parameters, drawn from its index alone.
    style.solve.stiffness = 0.5 + (k % 4) * 0.5
    style.color.value = 0.2 + 0.1 * (k % 5)
    hair = wisp.generate(style, seed=1000 + k, threads=1)
    path = pathlib.Path(out_dir) / f"sample_{k:05d}.npz"
    hair.write(str(path))
    return {"k": k, "strands": len(hair), "points": hair.point_count, "file": str(path)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("--samples", type=int, default=8)
    parser.add_argument("--preset", default="wavy-bob")
    parser.add_argument("--strands", type=int, default=20000)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)

    from dask.distributed import Client, LocalCluster

    # Processes, one thread each: wisp releases the GIL, but one process per core keeps
    # each sample's memory separate and the workers' output independent.
    with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        futures = [client.submit(make_sample, k, args.preset, args.strands, args.out_dir,
                                 pure=False) for k in range(args.samples)]
        for result in client.gather(futures):
            print(f"sample {result['k']}: {result['strands']} strands -> {result['file']}")


if __name__ == "__main__":
    main()
