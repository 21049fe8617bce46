"""The Franka Panda's visual meshes, read at run time from pybullet's package data, for MuJoCo.

Source: `pybullet_data/franka_panda/meshes/` of the installed `pybullet` package (a dependency),
the meshes its `panda.urdf` draws: `visual/link1..6.obj`, `visual/hand.obj`, `visual/finger.obj`,
and `collision/link0.obj`, `collision/link7.obj` (the package ships no visual mesh for those two;
its URDF draws the collision meshes). Licence: the Apache License 2.0, the file
`pybullet_data/franka_panda/LICENSE.txt` beside the meshes (it names no copyright holder). The
meshes are Franka's `franka_description` meshes from `franka_ros`, whose NOTICE reads
"Copyright 2023 Franka Robotics GmbH" (formerly Franka Emika GmbH), Apache-2.0.
Nothing of them is committed to this repository.

Each mesh is in the URDF's link frame, Craig's modified DH frame i, the frame robot.py gives
body `link{i}` (the hand's frame and the fingers' are the URDF's too), so it is drawn at the
body's origin unturned. MuJoCo loads only the first object of an OBJ file and no materials,
so each file is split by its materials' diffuse colour into single-object OBJs (positions,
normals and triangles as they are) under the project's cache (`REALIKEA_CACHE`, default
`.cache/realikea`), keyed by the sources' content, and each piece is drawn in its colour.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import tempfile
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from realikea.errors import RealIkeaError
from realikea.files import repo_path

CONVERTER_VERSION = "1"  # bump when the split's output changes (part of the cache key)
# robot.py's bodies -> the mesh panda.urdf draws for them (relative to franka_panda/meshes/)
SOURCES = {
    "link0": "collision/link0.obj",
    **{f"link{i}": f"visual/link{i}.obj" for i in range(1, 7)},
    "link7": "collision/link7.obj",
    "hand": "visual/hand.obj",
    "finger": "visual/finger.obj",
}
DEFAULT_RGBA = (1.0, 1.0, 1.0, 1.0)  # panda.urdf's panda_white, for faces without a material


@dataclass(frozen=True)
class Piece:
    """One single-colour part of a link's mesh: its OBJ file (absolute) and colour."""

    name: str
    file: Path
    rgba: tuple[float, float, float, float]


def panda_dir() -> Path:
    """The installed `pybullet_data/franka_panda/` folder (meshes, URDF and LICENSE.txt)."""
    try:
        import pybullet_data
    except ImportError as err:  # pybullet is a dependency; a visual-free robot needs none
        raise RealIkeaError("the Panda's meshes come from pybullet_data: pip install pybullet "
                            "(or build the robot with visuals=False)") from err  # fmt: skip
    folder = Path(pybullet_data.getDataPath()) / "franka_panda"
    if not folder.is_dir():
        raise RealIkeaError(f"no franka_panda folder in pybullet_data ({folder})")
    return folder


def _materials(obj: Path, lines: list[str]) -> dict[str, tuple[float, ...]]:
    """Material name -> diffuse RGBA from the OBJ's `mtllib` files (missing files: none)."""
    colours: dict[str, tuple[float, ...]] = {}
    for line in lines:
        if not line.startswith("mtllib "):
            continue
        mtl = obj.parent / line.split(maxsplit=1)[1].strip()
        if not mtl.is_file():
            continue
        name = None
        for entry in mtl.read_text().splitlines():
            words = entry.split()
            if words[:1] == ["newmtl"]:
                name = words[1]
            elif words[:1] == ["Kd"] and name is not None:
                colours[name] = (*(round(float(v), 2) for v in words[1:4]), 1.0)
    return colours


def _index(ref: str, count: int) -> int:
    """An OBJ index (1-based, or negative from the end of what is read so far), 0-based."""
    k = int(ref)
    return k - 1 if k > 0 else count + k


def split_obj(obj: Path) -> dict[tuple[float, ...], str]:
    """One OBJ's triangles grouped by their material's colour: RGBA -> the text of a
    single-object OBJ holding them (positions and normals renumbered; polygons fanned)."""
    lines = obj.read_text().splitlines()
    colours = _materials(obj, lines)
    verts: list[str] = []
    normals: list[str] = []
    faces: dict[tuple[float, ...], list[list[tuple[int, int | None]]]] = {}
    current = DEFAULT_RGBA
    for line in lines:
        if line.startswith("v "):
            verts.append(line[2:].strip())
        elif line.startswith("vn "):
            normals.append(line[3:].strip())
        elif line.startswith("usemtl "):
            current = colours.get(line.split(maxsplit=1)[1].strip(), DEFAULT_RGBA)
        elif line.startswith("f "):
            corners = []
            for word in line.split()[1:]:
                refs = word.split("/")
                n = _index(refs[2], len(normals)) if len(refs) > 2 and refs[2] else None
                corners.append((_index(refs[0], len(verts)), n))
            for k in range(1, len(corners) - 1):
                faces.setdefault(current, []).append([corners[0], corners[k], corners[k + 1]])
    texts = {}
    for rgba, tris in faces.items():
        with_normals = all(n is not None for tri in tris for _, n in tri)
        vmap: dict[int, int] = {}
        nmap: dict[int, int] = {}
        out = []
        for tri in tris:
            refs = []
            for v, n in tri:
                vi = vmap.setdefault(v, len(vmap) + 1)
                if with_normals:
                    refs.append(f"{vi}//{nmap.setdefault(n, len(nmap) + 1)}")
                else:
                    refs.append(str(vi))
            out.append("f " + " ".join(refs))
        body = [f"v {verts[v]}" for v in vmap]
        body += [f"vn {normals[n]}" for n in nmap] if with_normals else []
        texts[rgba] = "\n".join([f"# {obj.name}, the faces of colour {rgba}", *body, *out]) + "\n"
    return texts


def _cache_key(root: Path) -> str:
    digest = hashlib.sha256(CONVERTER_VERSION.encode())
    for body, source in sorted(SOURCES.items()):
        obj = root / "meshes" / source
        digest.update(body.encode() + obj.read_bytes())
        for mtl in sorted(obj.parent.glob(obj.name + "*.mtl")) + [obj.with_suffix(".mtl")]:
            if mtl.is_file():
                digest.update(mtl.read_bytes())
    return digest.hexdigest()[:16]


def _cache_root() -> Path:
    return repo_path(os.environ.get("REALIKEA_CACHE", ".cache/realikea")) / "panda_visual"


@lru_cache(maxsize=1)
def panda_pieces() -> dict[str, tuple[Piece, ...]]:
    """robot.py's body name (link0 .. link7, hand, finger) -> its mesh's single-colour pieces,
    split once into the cache (written by whichever process gets there first)."""
    root = panda_dir()
    folder = _cache_root() / _cache_key(root)
    manifest = folder / "pieces.json"
    if not manifest.is_file():
        folder.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}."))
        try:
            listing = {}
            for body, source in SOURCES.items():
                pieces = split_obj(root / "meshes" / source)
                listing[body] = []
                for k, (rgba, text) in enumerate(sorted(pieces.items())):
                    name = f"{body}_{k}"
                    (tmp / f"{name}.obj").write_text(text)
                    listing[body].append({"name": name, "rgba": list(rgba)})
            (tmp / "pieces.json").write_text(json.dumps(listing, indent=1) + "\n")
            os.chmod(tmp, 0o755)
            try:
                tmp.rename(folder)
            except OSError:  # another process wrote it first
                if not manifest.is_file():
                    raise
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    listing = json.loads(manifest.read_text())
    return {
        body: tuple(Piece(p["name"], folder / f"{p['name']}.obj", tuple(p["rgba"])) for p in ps)
        for body, ps in listing.items()
    }
