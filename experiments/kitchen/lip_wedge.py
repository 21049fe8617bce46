"""Why hook_oracle's lip wedge catches no finger pull: how far a Franka fingertip can rise behind
a lip at a given hand pitch, from each part's measured channel (assets/catch_geometry.py).

Geometry (part frame: z out of the front, y up; the lip hangs down at z = edge_z, the channel
behind it runs back to z = back): the hand tipped up by p leads with its lower finger, whose pad
(9 mm thick, PAD_THICKNESS) lies with its upper face on the lip's bottom edge. Its tip corner on
the upper face sits at z_top behind the lip; the corner on the lower face is 9 mm * sin p nearer
the front and must keep `clearance` from the channel's back wall. The upper face rises
tan p per metre towards the front, so the tip rises above the lip's bottom edge by at most
tan p * (edge_z - back - clearance - 9 mm * sin p), capped by the channel's roof. That height is
the hook's bearing; under 2 mm (MIN_ROOM) a pad rolls off (catch_geometry's measured sink).

    python experiments/kitchen/lip_wedge.py            # test parts; --split all for every part
"""

import argparse
import math

from realikea.assets.catalog import Catalog
from realikea.assets.catch_geometry import MIN_ROOM, LipCatch, catch_features_at
from realikea.config import load_config
from realikea.files import repo_path
from realikea.policies.hook_oracle import OracleParams
from realikea.sim.robot import PAD_THICKNESS

PITCHES = (0.25, 0.56, 0.8, 1.0)  # rad: the oracle's lip pitch, the reach limit, steeper


def bearing(f: LipCatch, pitch: float, clearance: float) -> float:
    """m the pad's tip can rise above the lip's bottom edge at `pitch` (0 if it cannot)."""
    run = f.channel - clearance - PAD_THICKNESS * math.sin(pitch)
    return max(0.0, min(math.tan(pitch) * run, f.top - f.edge_y - clearance))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--split", default="test", choices=("train", "test", "all"))
    args = parser.parse_args()
    catalog = Catalog.load()
    parts = [p.id for p in catalog.parts_of_split(catalog.parts_in("finger_pull"), args.split)]
    library = repo_path(load_config([]).paths.library)
    clearance = OracleParams().clearance
    print(f"split {args.split}; bearing (mm) of the pad behind the lip at hand pitch p (rad)")
    print("| part | channel (mm) | drop (mm) | " + " | ".join(f"p={p}" for p in PITCHES) + " |")
    print("|---|---:|---:|" + "---:|" * len(PITCHES))
    for part in parts:
        mesh = next(library.glob(f"{part}__drawer*/meshes/visual.obj"), None)
        if mesh is None:
            raise SystemExit(f"{part}: not built; run `realikea assets build --all` first")
        f = catch_features_at(str(mesh), "finger_pull")
        if not isinstance(f, LipCatch):
            print(f"| {part} | {f.reason} |")
            continue
        cells = []
        for p in PITCHES:
            b = bearing(f, p, clearance)
            cells.append(f"{b * 1e3:.1f}" + ("" if b >= MIN_ROOM else " x"))
        print(
            f"| {part} | {f.channel * 1e3:.1f} | {(f.top - f.edge_y) * 1e3:.1f} | "
            + " | ".join(cells)
            + " |"
        )
    print(f"x: under {MIN_ROOM * 1e3:.0f} mm of bearing, the pad rolls off the edge")


if __name__ == "__main__":
    main()
