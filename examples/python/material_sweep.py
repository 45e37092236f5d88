"""A material sweep into a pandas table: Young's modulus x Poisson's ratio for a box dropped
on the floor, on Ray when it is installed (a local cluster, or the one `RAY_ADDRESS` names),
on local processes otherwise.

    python examples/python/material_sweep.py [--frames 300] [--no-ray] [--csv out.csv]
"""

import argparse

import tetrasim


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--no-ray", action="store_true")
    parser.add_argument("--csv")
    args = parser.parse_args()
    settings = [
        {"mesh": "meshes/box", "method": "volume", "springs": "implicit", "density": 1000.0,
         "youngs_modulus": e, "poisson_ratio": nu, "frames": args.frames}
        for e in (1e4, 1e5, 1e6)
        for nu in (0.3, 0.45, 0.49)
    ]
    table = tetrasim.sweep(settings, use_ray=False if args.no_ray else None)
    columns = ["youngs_modulus", "poisson_ratio", "min_volume_pct", "avg_local_error_pct", "max_inverted_tets", "ms_per_frame"]
    print(table[columns].to_string(index=False))
    if args.csv:
        table[columns].to_csv(args.csv, index=False)


if __name__ == "__main__":
    main()
