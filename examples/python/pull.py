"""Pull a bar: one end clamped, the other end's nodes dragged sideways by setting their
velocity every frame (pinned nodes move exactly as they are told), then held there.

    python examples/python/pull.py [--backend cpu|cpu-ref|vulkan]

A soft, damped material (E = 20 kPa, damping time 0.2 s, no gravity): once it settles, the
middle of the bar sits about halfway between the clamped end and the pulled one. Prints
both displacements and the volume kept; exits 1 unless the middle settled between 40 and
60 % of the pull and the volume stayed within 1 %.
"""

import argparse
import sys

import numpy as np

import tetrasim


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--backend", default="cpu", choices=tetrasim.BACKENDS)
    parser.add_argument("--frames", type=int, default=600)
    args = parser.parse_args()

    # The bundled box (1 x 0.5 x 0.5 m), 0.3 m above the floor; both end faces pinned.
    mesh = tetrasim.read_mesh("meshes/box")
    sim = tetrasim.Simulation(
        mesh, backend=args.backend, method="volume", springs="implicit",
        youngs_modulus=2e4, damping=0.2, density=1000.0, drop_height=0.3, gravity=0.0,
        pin_boxes=[((-1, -1, -1), (-0.49, 2, 1)), ((0.49, -1, -1), (1, 2, 1))],
    )
    x0 = sim.positions
    moving = x0[:, 0] >= 0.49
    speed = np.array([0.0, 0.0, 0.5])  # m/s along +Z
    for frame in range(args.frames):
        x, v = sim.positions, sim.velocities
        pulling = frame < 150  # 0.15 s at 0.5 m/s: 75 mm
        v[moving] = speed if pulling else 0.0
        sim.set_state(x, v)
        sim.step()
    x = sim.positions
    middle = np.abs(x0[:, 0]) < 0.05
    record = sim.record()
    print(
        f"pulled end moved {x[moving, 2].mean() - x0[moving, 2].mean():.3f} m, the middle "
        f"{x[middle, 2].mean() - x0[middle, 2].mean():.3f} m; volume {record['volume_pct'][-1]:.3f} %"
    )
    pull = x[moving, 2].mean() - x0[moving, 2].mean()
    followed = 0.4 < (x[middle, 2].mean() - x0[middle, 2].mean()) / pull < 0.6
    kept = abs(record["volume_pct"][-1] - 100.0) < 1.0
    return 0 if followed and kept else 1


if __name__ == "__main__":
    sys.exit(main())
