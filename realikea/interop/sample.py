"""The sample both cross-simulator checks pull (`experiments/interop/pybullet_parity.py` in
PyBullet, `sapien_check.py` in SAPIEN): six configurations, two per kind and every category
twice, built into a scratch library and exported to URDF and MJCF at each resistance mode."""

from __future__ import annotations

import argparse
import json
from dataclasses import dataclass
from pathlib import Path

from realikea.assets.build import WorkflowSettings, build_library
from realikea.assets.catalog import Catalog, Configuration
from realikea.config import load_config
from realikea.export.driver import export_configurations, export_folder
from realikea.export.model import read_articulation
from realikea.files import repo_path
from realikea.interop.pull import breakaway_force
from realikea.sim.resistance import mode as resistance_mode
from realikea.sources import SOURCES, model_name

SAMPLE = (  # (part, base): two per kind, each category twice
    ("tp_round_bar_128", "drawer_w60_h20"),
    ("knob_mushroom_26", "drawer_w80_h40"),
    ("tp_d_handle_128", "door_left_w40_h80"),
    ("fp_edge_128", "door_right_w60_h80"),
    ("knob_round_30", "flap_w60_h40"),
    ("fp_cup_128", "flap_w60_h40"),
)
SAMPLE_MODES = ("high", "smooth")
MULTIPLES = (0.5, 1.2, 2.0)  # x the breakaway force; 1.2x is mid-travel after 1 s
UNIT = {"slide": "m", "hinge": "rad"}  # of a front's opening


@dataclass(frozen=True)
class Prepared:
    """One configuration exported at one resistance mode: paths and what the pull needs."""

    config: Configuration
    mode: str
    mjcf: Path
    urdf: Path
    metadata: dict
    handle: list[float]

    @property
    def joint(self) -> dict:
        """metadata.json's `joint`: type, anchor, axis and range in the cabinet frame."""
        return self.metadata["joint"]

    @property
    def breakaway(self) -> float:
        """N at the handle that balance the joint's friction as exported."""
        joint = self.joint
        frictionloss = self.metadata["resistance"]["exported"]["frictionloss"]
        return breakaway_force(
            joint["type"], frictionloss, joint["anchor"], joint["axis"], self.handle
        )


def prepare(configs, mode, sources, work: Path, settings, cache_root) -> dict[tuple, Prepared]:
    """Build `configs` and export their URDFs and MJCFs for `sources` in resistance `mode`."""
    resistance = resistance_mode(mode)
    library, exports = work / "library", work / f"export_{mode}"
    build_library(configs, settings, SOURCES, cache_root, library, progress=False)
    prepared = {}
    for source in sources:
        for fmt in ("urdf", "mjcf"):
            export_configurations(
                configs, fmt, source, library, exports, resistance=resistance, progress=False
            )
        for c in configs:
            folder = export_folder(exports, "urdf", source, c.id)
            mjcf = export_folder(exports, "mjcf", source, c.id) / model_name(source)
            prepared[(c.id, source)] = Prepared(
                c,
                mode,
                mjcf,
                folder / model_name(source, ".urdf"),
                json.loads((folder / "metadata.json").read_text()),
                read_articulation(mjcf).handle.tolist(),
            )
    return prepared


def sample_context() -> tuple[WorkflowSettings, Path, Catalog, list[Configuration]]:
    """The workflow settings, the mesh cache, the catalog and SAMPLE's configurations."""
    cfg = load_config()
    catalog = Catalog.load()
    sample = [next(catalog.configurations(part=p, base=b)) for p, b in SAMPLE]
    return WorkflowSettings.from_config(cfg), repo_path(cfg.paths.cache), catalog, sample


def sample_arguments(description: str, out: Path, argv=None) -> argparse.Namespace:
    """The options both checks take: a scratch folder and the report's path."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--work", type=Path, help="scratch folder (default: a temporary one)")
    parser.add_argument("--out", type=Path, default=out)
    return parser.parse_args(argv)
