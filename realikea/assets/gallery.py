"""Contact sheet of the library rendered offscreen on the CPU with MuJoCo's renderer."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import trimesh
from omegaconf import DictConfig
from PIL import Image, ImageDraw
from tqdm import tqdm

from realikea.assets.build import WorkflowSettings, build_library, ensure_part
from realikea.assets.catalog import Catalog, Configuration
from realikea.files import atomic_path, repo_path
from realikea.sources import SOURCES, model_path

TILE = 200
COLUMNS = 10


def _part_xml(visual: Path, floor: float) -> str:
    return f"""<mujoco>
  <visual><headlight ambient="0.45 0.45 0.45" diffuse="0.5 0.5 0.5"/></visual>
  <asset><mesh name="part" file="{visual}"/></asset>
  <worldbody>
    <light pos="0.3 -0.3 0.6" dir="-0.4 0.4 -1"/>
    <geom type="mesh" mesh="part" rgba="0.62 0.64 0.68 1"/>
    <geom type="box" size="{floor} {floor} 0.001" pos="0 0 -0.001" rgba="0.85 0.78 0.66 1"/>
  </worldbody>
</mujoco>"""


def _render(model: mujoco.MjModel, data: mujoco.MjData, lookat, distance: float, size=TILE):
    renderer = mujoco.Renderer(model, size, size)
    try:
        camera = mujoco.MjvCamera()
        camera.lookat[:] = lookat
        camera.distance, camera.azimuth, camera.elevation = distance, 210.0, -30.0
        option = mujoco.MjvOption()
        option.geomgroup[:] = [1, 1, 1, 0, 1, 1]  # hide collision pieces (group 3)
        renderer.update_scene(data, camera, option)
        return renderer.render()
    finally:
        renderer.close()


def part_tile(visual: Path) -> np.ndarray:
    """One part's visual mesh on a patch of front, seen from above and to the side."""
    vertices = trimesh.load_mesh(visual).vertices
    extent = float(np.max(vertices.max(0) - vertices.min(0)))
    model = mujoco.MjModel.from_xml_string(_part_xml(visual.resolve(), 2 * extent))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    centre = (vertices.max(0) + vertices.min(0)) / 2
    return _render(model, data, centre, 1.8 * extent + 0.03)


def configuration_tile(mjcf: Path, opening: float = 0.35) -> np.ndarray:
    """A configuration with its front opened to `opening` of the joint range."""
    model = mujoco.MjModel.from_xml_path(str(mjcf))
    data = mujoco.MjData(model)
    data.qpos[0] = opening * model.jnt_range[0, 1]
    mujoco.mj_forward(model, data)
    lo = np.array([g for g in data.geom_xpos]).min(0)
    hi = np.array([g for g in data.geom_xpos]).max(0)
    return _render(model, data, (lo + hi) / 2, 2.2 * float(np.max(hi - lo)))


def sample_configurations(catalog: Catalog, n: int) -> list[Configuration]:
    """A deterministic spread over bases and categories."""
    configs = list(catalog.configurations())
    step = max(1, len(configs) // max(n, 1))
    return configs[::step][:n] if n else []


def _label(tile: np.ndarray, text: str) -> Image.Image:
    image = Image.fromarray(tile)
    draw = ImageDraw.Draw(image)
    draw.rectangle((0, TILE - 16, TILE, TILE), fill=(255, 255, 255))
    draw.text((4, TILE - 14), text[:34], fill=(0, 0, 0))
    return image


def render_gallery(cfg: DictConfig, out: Path, n_configs: int = 12) -> Path:
    """Build what is missing, render every part and a sample of configurations, save a PNG."""
    catalog = Catalog.load()
    settings = WorkflowSettings.from_config(cfg)
    cache, library = repo_path(cfg.paths.cache), repo_path(cfg.paths.library)
    sample = sample_configurations(catalog, n_configs)
    per_part = [next(catalog.configurations(part=p)) for p in catalog.parts]
    build_library(sample + per_part, settings, SOURCES, cache, library)
    tiles = []
    for config in tqdm(per_part, desc="render parts"):
        _, meshes, _ = ensure_part(config.part, settings, cache)
        tiles.append(_label(part_tile(meshes.visual), config.part.id))
    for config in tqdm(sample, desc="render configurations"):
        mjcf = model_path(library, config.id, "coacd")
        tiles.append(_label(configuration_tile(mjcf), config.id))
    rows = -(-len(tiles) // COLUMNS)
    sheet = Image.new("RGB", (COLUMNS * TILE, rows * TILE), "white")
    for i, tile in enumerate(tiles):
        sheet.paste(tile, ((i % COLUMNS) * TILE, (i // COLUMNS) * TILE))
    out = Path(out)
    with atomic_path(out) as tmp:
        sheet.save(tmp, format="PNG")
    return out
