"""Reload every exported model in its own tool: MJCF in MuJoCo, URDF in PyBullet, USD in usd-core.

`verify_folder` checks one configuration folder (`OUT/<format>_<collision>/<config id>/`) against
its metadata.json: the model loads, with the front's one joint (type, limits) and one collision
shape per convex piece the export lists (`meshes/<collision>_NNN.stl`; a USD folder, whose meshes
live in the file, is counted against its URDF or MJCF sibling of the same configuration, source
and build, when there is one). `verify_release` checks every folder a release's manifest.json
lists (or, without a manifest, every folder under an export root) and counts the results per
`<format>_<collision>`; `write_verification` records them in `verification.json` beside the
manifest, with the manifest's SHA-256, so a stale record can be told apart.
"""

from __future__ import annotations

import ctypes
import json
import math
import os
import re
import sys
import tempfile
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import pybullet
from pxr import Usd, UsdPhysics
from tqdm import tqdm

from realikea.errors import RealIkeaError
from realikea.export import FORMATS
from realikea.export.metadata import PART_LINK
from realikea.export.model import JOINT_TYPES
from realikea.export.release import MANIFEST, VERIFICATION, sha256_file
from realikea.files import atomic_write_text
from realikea.provenance import package_versions
from realikea.sources import SOURCES

VERIFICATION_VERSION = "1"  # bump when verification.json's layout changes
TOOLS = ("mujoco", "pybullet", "usd-core")  # the packages whose versions a verification records
LISTED = 5  # failures named on the command line before "and n more"
MESSAGE = 600  # characters of a tool's diagnostics kept in a failure's message
PYBULLET_JOINT = {"slide": pybullet.JOINT_PRISMATIC, "hinge": pybullet.JOINT_REVOLUTE}
LIMIT_TOLERANCE = 1e-5  # relative: URDF writes 9 significant digits, USD single precision


class VerifyError(Exception):
    """A model that loaded, or not, differently from what its metadata.json describes."""


@dataclass(frozen=True)
class Verification:
    """One folder's result: whether its model reloaded as described, what was checked, and the
    error if not (`file`: the model file, or what failed before it could be read)."""

    folder: Path
    format: str
    collision: str
    file: Path
    ok: bool
    checked: list[str]
    error: str | None = None
    seconds: float = 0.0


@dataclass
class VerifyReport:
    """What a walk over a release or export folder found: results per `<format>_<collision>`
    (`configurations`, `ok`, `failed`, `seconds`), the failures and the wall time."""

    root: Path
    folders: dict[str, dict] = field(default_factory=dict)
    failures: list[Verification] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def checked(self) -> int:
        """Configuration folders verified."""
        return sum(f["configurations"] for f in self.folders.values())

    @property
    def ok(self) -> bool:
        """Whether every folder verified."""
        return not self.failures


def _require(condition: bool, message: str) -> None:
    """Raise a VerifyError with `message` unless `condition` holds."""
    if not condition:
        raise VerifyError(message)


def _pieces_listed(metadata: dict) -> list[str]:
    """The convex pieces an export's metadata.json lists as its files (`meshes/<source>_NNN.*`)."""
    export = metadata["export"]
    piece = re.compile(rf"meshes/{re.escape(export['collision'])}_\d+\.\w+")
    return [f for f in export["files"] if piece.fullmatch(f)]


def expected_pieces(folder: Path, metadata: dict) -> tuple[int, Path] | None:
    """How many convex pieces the configuration's collision source has and which metadata.json
    says so: the folder's own, or for USD (meshes stored in the file) a URDF or MJCF sibling's;
    None if no listing is found."""
    export = metadata["export"]
    if export["format"] != "usd":
        return len(_pieces_listed(metadata)), folder / "metadata.json"
    root, source = folder.parent.parent, export["collision"]
    for fmt in (f for f in FORMATS if f != "usd"):
        path = root / f"{fmt}_{source}" / folder.name / "metadata.json"
        if not path.is_file():
            continue
        sibling = json.loads(path.read_text())["export"]
        if sibling["build_key"] == export["build_key"]:  # exported from the same build
            return len(_pieces_listed({"export": sibling})), path
    return None


def _joint_limits(metadata: dict, degrees: bool = False) -> tuple[float, float]:
    """The front joint's range as metadata.json gives it (radians or metres), or in degrees."""
    lower, upper = metadata["joint"]["range"]
    scale = 180.0 / math.pi if degrees and metadata["joint"]["type"] == "hinge" else 1.0
    return lower * scale, upper * scale


def _same_limits(found: tuple[float, float], expected: tuple[float, float]) -> bool:
    """Whether two joint ranges agree to the precision the formats store."""
    return all(
        math.isclose(a, b, rel_tol=LIMIT_TOLERANCE, abs_tol=1e-9)
        for a, b in zip(found, expected, strict=True)
    )


def _count(found: int, pieces: tuple[int, Path] | None, what: str, checked: list[str]) -> None:
    """Check `found` collision shapes on the part against the listed pieces; record the check."""
    if pieces is None:
        _require(found > 0, f"no {what} on the {PART_LINK!r} link")
        checked.append(f"{found} {what} on {PART_LINK!r} (no URDF/MJCF listing to count against)")
        return
    expected, listing = pieces
    _require(
        found == expected,
        f"{found} {what} on the {PART_LINK!r} link; "
        f"{listing.parent.parent.name}/{listing.parent.name}/{listing.name} lists {expected} "
        "convex pieces",
    )
    checked.append(f"{found} {what} on {PART_LINK!r}, one per listed convex piece")


def _check_mjcf(model_file: Path, metadata: dict, pieces, checked: list[str]) -> None:
    """MuJoCo compiles the MJCF with one joint of the listed type and range and one colliding
    mesh geom per convex piece on the part."""
    model = mujoco.MjModel.from_xml_path(str(model_file))
    checked.append(f"MuJoCo {mujoco.__version__} compiles {model_file.name}")
    joint = metadata["joint"]
    _require(model.njnt == 1, f"{model.njnt} joints; expected one, {joint['name']!r}")
    found = (model.joint(0).name, int(model.jnt_type[0]))
    _require(
        (found[0], JOINT_TYPES.get(found[1])) == (joint["name"], joint["type"]),
        f"joint {found[0]!r} of MuJoCo type {found[1]}; "
        f"expected {joint['name']!r} ({joint['type']})",
    )
    _require(
        _same_limits(tuple(model.jnt_range[0]), _joint_limits(metadata)),
        f"joint range {list(model.jnt_range[0])}; metadata.json: {joint['range']}",
    )
    checked.append(f"one joint, {joint['name']} ({joint['type']}), range as listed")
    part = model.body(PART_LINK).id
    colliding = [
        g
        for g in range(model.ngeom)
        if model.geom_bodyid[g] == part
        and model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH
        and (model.geom_contype[g] or model.geom_conaffinity[g])
    ]
    _count(len(colliding), pieces, "colliding mesh geoms", checked)


def _flush_c_stdio() -> None:
    """Flush the C library's stdio buffers (what PyBullet printed but has not yet written)."""
    ctypes.CDLL(None).fflush(None)


@contextmanager
def _c_output(lines: list[str]):
    """Collect what C code writes to stdout and stderr inside the block (PyBullet's diagnostics)
    into `lines` instead of the terminal."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    with tempfile.TemporaryFile() as sink:
        try:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            yield
        finally:
            _flush_c_stdio()
            for fd, copy in ((1, saved[0]), (2, saved[1])):
                os.dup2(copy, fd)
                os.close(copy)
            sink.seek(0)
            lines += sink.read().decode(errors="replace").splitlines()


def _diagnostics(lines: list[str]) -> str:
    """PyBullet's printed errors and warnings as one line, without their source locations."""
    text = " ".join(re.sub(r"b3(Error|Warning)\[[^\]]*\]:", " ", line) for line in lines)
    text = re.sub(r"pybullet build time:.*?\d{2}:\d{2}:\d{2}", " ", text)
    return re.sub(r"\s+", " ", text).strip()[:MESSAGE]


def _check_urdf(model_file: Path, metadata: dict, pieces, checked: list[str]) -> None:
    """PyBullet (DIRECT, its own client, disconnected afterwards) loads the URDF with one joint
    per non-root link, the front's joint of the listed type and limits, and one collision shape
    per convex piece on the part."""
    lines: list[str] = []
    with _c_output(lines):
        client = pybullet.connect(pybullet.DIRECT)
    try:
        try:
            with _c_output(lines):
                body = pybullet.loadURDF(str(model_file), useFixedBase=True, physicsClientId=client)
        except pybullet.error as err:
            printed = _diagnostics(lines)
            raise VerifyError(f"PyBullet: {err}" + (f" {printed}" if printed else "")) from None
        checked.append(f"PyBullet loads {model_file.name}")
        joints = [
            pybullet.getJointInfo(body, i, physicsClientId=client)
            for i in range(pybullet.getNumJoints(body, physicsClientId=client))
        ]
        expected = len(metadata["mass_model"]["links"]) - 1  # every link but the static root
        _require(len(joints) == expected, f"{len(joints)} joints; expected {expected}")
        by_name = {info[1].decode(): info for info in joints}
        joint = metadata["joint"]
        _require(joint["name"] in by_name, f"no joint {joint['name']!r}")
        info = by_name[joint["name"]]
        _require(
            info[2] == PYBULLET_JOINT[joint["type"]],
            f"joint {joint['name']!r} of PyBullet type {info[2]}; expected a {joint['type']}",
        )
        _require(
            _same_limits((info[8], info[9]), _joint_limits(metadata)),
            f"joint limits {[info[8], info[9]]}; metadata.json: {joint['range']}",
        )
        checked.append(f"{len(joints)} joints, {joint['name']} ({joint['type']}) limits as listed")
        links = {info[12].decode(): info[0] for info in joints}
        _require(PART_LINK in links, f"no link {PART_LINK!r}")
        shapes = pybullet.getCollisionShapeData(body, links[PART_LINK], physicsClientId=client)
        _count(len(shapes), pieces, "collision shapes", checked)
    finally:
        pybullet.disconnect(client)


def _check_usd(model_file: Path, metadata: dict, pieces, checked: list[str]) -> None:
    """usd-core opens the stage; its default prim is an articulation root; UsdPhysics' parse
    finds one prismatic or revolute joint with the listed limits and one convexHull collision
    mesh per convex piece on the part."""
    stage = Usd.Stage.Open(str(model_file))
    checked.append(f"usd-core opens {model_file.name}")
    root = stage.GetDefaultPrim()
    _require(root.IsValid(), "no default prim")
    _require(
        root.HasAPI(UsdPhysics.ArticulationRootAPI),
        f"the default prim {root.GetPath()} has no ArticulationRootAPI",
    )
    parsed = UsdPhysics.UsdPhysicsLoadStageFromPrimRange(stage, ["/"])
    kinds = UsdPhysics.ObjectType
    _require(
        len(parsed.get(kinds.Articulation, ([], []))[0]) == 1, "UsdPhysics parses no articulation"
    )
    joints = [
        (path, desc, name)
        for name, kind in (("slide", kinds.PrismaticJoint), ("hinge", kinds.RevoluteJoint))
        for path, desc in zip(*parsed.get(kind, ([], [])), strict=True)
    ]
    joint = metadata["joint"]
    _require(len(joints) == 1, f"{len(joints)} prismatic/revolute joints; expected one")
    ((path, desc, kind),) = joints
    _require(
        (path.name, kind) == (joint["name"], joint["type"]),
        f"joint {path} ({kind}); expected {joint['name']!r} ({joint['type']})",
    )
    limits = (desc.limit.lower, desc.limit.upper)
    _require(desc.limit.enabled, f"joint {path} has no limits")
    _require(
        _same_limits(limits, _joint_limits(metadata, degrees=True)),
        f"joint limits {list(limits)}; metadata.json: {joint['range']} {joint['range_unit']}",
    )
    checked.append(f"ArticulationRootAPI; one joint, {joint['name']} ({joint['type']}) limits")
    part = root.GetPath().AppendChild(PART_LINK)
    meshes = [
        (p, d)
        for p, d in zip(*parsed.get(kinds.MeshShape, ([], [])), strict=True)
        if p.GetParentPath() == part
    ]
    other = [str(p.name) for p, d in meshes if d.approximation != UsdPhysics.Tokens.convexHull]
    _require(not other, f"collision meshes not approximated as convexHull: {', '.join(other)}")
    _count(len(meshes), pieces, "convexHull collision meshes", checked)


CHECKS = {"mjcf": _check_mjcf, "urdf": _check_urdf, "usd": _check_usd}


def verify_folder(folder: Path, fmt: str) -> Verification:
    """Reload one exported configuration folder's model in its format's tool, as its
    metadata.json describes it; never raises for a broken folder, reports it."""
    folder = Path(folder)
    start = time.perf_counter()
    checked: list[str] = []
    source = folder.parent.name.removeprefix(f"{fmt}_")
    model_file = folder / "metadata.json"
    try:
        if fmt not in CHECKS:
            raise VerifyError(f"unknown format {fmt!r}; choose one of {', '.join(CHECKS)}")
        try:
            metadata = json.loads(model_file.read_text())
            export = metadata["export"]
            source, model_file = export["collision"], folder / export["model"]
        except (OSError, ValueError, KeyError) as err:
            raise VerifyError(f"metadata.json unreadable: {type(err).__name__}: {err}") from None
        _require(export["format"] == fmt, f"metadata.json says format {export['format']!r}")
        _require(model_file.is_file(), f"the model file {export['model']} is missing")
        CHECKS[fmt](model_file, metadata, expected_pieces(folder, metadata), checked)
    except Exception as err:  # any tool's failure to load is this folder's result, not a crash
        message = str(err) if isinstance(err, VerifyError) else f"{type(err).__name__}: {err}"
        message = re.sub(r"\s+", " ", message).strip()[:MESSAGE]
        seconds = time.perf_counter() - start
        return Verification(folder, fmt, source, model_file, False, checked, message, seconds)
    return Verification(
        folder, fmt, source, model_file, True, checked, None, time.perf_counter() - start
    )


def _walked(root: Path) -> list[tuple[str, str, str, Path]]:
    """The configuration folders under `root` (a `<format>_<collision>` folder or a folder
    holding some), as (`<format>_<collision>`, format, collision, folder), sorted; staging
    folders a killed export left (named `.*`) are skipped."""
    names = {f"{fmt}_{source}": (fmt, source) for fmt in FORMATS for source in SOURCES}
    parents = [root] if root.name in names else sorted(root.iterdir())
    return [
        (parent.name, *names[parent.name], folder)
        for parent in parents
        if parent.name in names and parent.is_dir()
        for folder in sorted(parent.iterdir())
        if folder.is_dir() and not folder.name.startswith(".")
    ]


def _listed(root: Path) -> list[tuple[str, str, str, Path]] | None:
    """The export folders a release's manifest.json lists, as `_walked` gives them; None if
    `root` holds no manifest."""
    manifest = root / MANIFEST
    if not manifest.is_file():
        return None
    record = json.loads(manifest.read_text())
    return sorted(
        (name, e["format"], e["collision"], root / name / config_id)
        for config_id, c in record["configurations"].items()
        for name, e in c["exports"].items()
    )


def verify_release(out: Path, *, progress: bool = True) -> VerifyReport:
    """Reload in its tool every configuration folder of a release `out` (those its
    manifest.json lists; one missing is a failure) or of an export folder (every one found):
    counts per `<format>_<collision>` and the failures."""
    root = Path(out)
    if not root.is_dir():
        raise RealIkeaError(f"{root} is not a folder; give a release or export folder")
    start = time.perf_counter()
    listed = _listed(root)
    jobs = listed if listed is not None else _walked(root)
    if not jobs:
        raise RealIkeaError(
            f"{root} holds no exported configuration: no {MANIFEST} and no folder "
            f"<{'|'.join(FORMATS)}>_<{'|'.join(SOURCES)}>/<config id>/"
        )
    report = VerifyReport(root)
    for name, fmt, source, _ in jobs:
        report.folders.setdefault(
            name,
            {
                "format": fmt,
                "collision": source,
                "configurations": 0,
                "ok": 0,
                "failed": 0,
                "seconds": 0.0,
            },
        )
    for name, fmt, source, folder in tqdm(
        jobs, desc="verify", disable=not progress or len(jobs) < 2
    ):
        if folder.is_dir():
            result = verify_folder(folder, fmt)
        else:
            message = f"listed in {MANIFEST} but missing"
            result = Verification(folder, fmt, source, folder, False, [], message)
        counts = report.folders[name]
        counts["configurations"] += 1
        counts["ok" if result.ok else "failed"] += 1
        counts["seconds"] += result.seconds
        if not result.ok:
            report.failures.append(result)
    report.seconds = time.perf_counter() - start
    return report


def _shown(path: Path, root: Path) -> str:
    """A path relative to the verified folder when inside it (POSIX)."""
    path = Path(path)
    return path.relative_to(root).as_posix() if path.is_relative_to(root) else str(path)


def verification_record(report: VerifyReport) -> dict:
    """What verification.json holds: the tools, counts per `<format>_<collision>`, the failures
    with their messages and the wall time."""
    root = report.root
    manifest = root / MANIFEST
    folders = {
        name: {**counts, "seconds": round(counts["seconds"], 3)}
        for name, counts in report.folders.items()
    }
    return {
        "verification_version": VERIFICATION_VERSION,
        "manifest_sha256": sha256_file(manifest) if manifest.is_file() else None,
        "tools": package_versions(TOOLS),
        "checks": {
            "mjcf": "compiles in MuJoCo; one joint of the listed type and range; one colliding "
            "mesh geom per convex piece on the part",
            "urdf": "loads in PyBullet (DIRECT); one joint per moving link; the front joint's "
            "type and limits as listed; one collision shape per convex piece on the part",
            "usd": "opens in usd-core; ArticulationRootAPI on the default prim; one prismatic "
            "or revolute joint with the listed limits; one convexHull collision mesh per "
            "convex piece on the part (counted against the URDF or MJCF folder's list)",
        },
        "totals": {
            "configurations": report.checked,
            "ok": sum(c["ok"] for c in report.folders.values()),
            "failed": len(report.failures),
        },
        "folders": folders,
        "failures": [
            {
                "folder": _shown(f.folder, root),
                "format": f.format,
                "collision": f.collision,
                "file": _shown(f.file, root),
                "error": f.error,
            }
            for f in report.failures
        ],
        "seconds": round(report.seconds, 3),
    }


def write_verification(report: VerifyReport) -> Path:
    """Write verification.json into the verified folder atomically; returns its path."""
    path = report.root / VERIFICATION
    atomic_write_text(path, json.dumps(verification_record(report), indent=1) + "\n")
    return path


def failure_lines(report: VerifyReport, limit: int = LISTED) -> list[str]:
    """The first failures as `file: error` lines, and how many more."""
    lines = [f"{_shown(f.file, report.root)}: {f.error}" for f in report.failures[:limit]]
    if len(report.failures) > limit:
        lines.append(f"... and {len(report.failures) - limit} more")
    return lines
