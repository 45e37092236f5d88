"""Drop a mesh (a scan, or the bundled sphere) on the floor and plot its volume.

    python examples/python/drop.py                                  # the bundled sphere
    python examples/python/drop.py ../shared/meshes/bun_zipper.ply  # a scan, meshed here
    python examples/python/drop.py MESH --backend vulkan --frames 800 --out drop.png

Writes the plot (matplotlib, when installed) and prints the volume kept; exits with status 1
unless the body landed with its volume within 1 %.
"""

import argparse
import sys

import tetrasim


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", nargs="?", default="meshes/sphere")
    parser.add_argument("--backend", default="cpu", choices=tetrasim.BACKENDS)
    parser.add_argument("--method", default="volume")
    parser.add_argument("--frames", type=int, default=400)
    parser.add_argument("--target-tets", type=int, default=5000)
    parser.add_argument("--out", default="drop.png")
    args = parser.parse_args()

    mesh = tetrasim.read_mesh(args.mesh, target_tets=args.target_tets if args.mesh.endswith((".ply", ".obj", ".off", ".stl")) else None)
    print(f"{mesh.label}: {len(mesh.nodes)} nodes, {len(mesh.tets)} tets")
    sim = tetrasim.Simulation(mesh, backend=args.backend, method=args.method)
    lowest = []
    for _ in range(args.frames):
        sim.step()
        if sim.frames % 10 == 0:
            lowest.append((sim.time, sim.positions[:, 1].min()))
    record = sim.record()
    print(
        f"{args.method} on {sim.backend}: volume {record['min_volume_pct']:.3f} % at worst, "
        f"{record['volume_pct'][-1]:.3f} % at the end; local error {record['avg_local_error_pct']:.3f} % "
        f"on average; {record['ms_per_frame']:.2f} ms per frame"
    )
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot (pip install matplotlib)")
    else:
        fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(6, 5))
        a.plot(record["time_s"], record["volume_pct"], label="total volume")
        a.plot(record["time_s"], [100 - e for e in record["local_error_pct"]], label="100 - local error")
        a.set_ylabel("% of rest")
        a.legend()
        b.plot(*zip(*lowest))
        b.set_ylabel("lowest node [m]")
        b.set_xlabel("time [s]")
        fig.suptitle(f"{mesh.label}: {args.method} on {sim.backend}")
        fig.savefig(args.out, dpi=100)
        print(f"wrote {args.out}")
    landed = min(y for _, y in lowest) < 0.01
    kept = abs(record["volume_pct"][-1] - 100.0) < 1.0
    return 0 if landed and kept and not record["diverged"] else 1


if __name__ == "__main__":
    sys.exit(main())
