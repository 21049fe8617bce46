"""The fingertip probe behind a two-point bar, in MuJoCo on the part's collision pieces and in
PyBullet on the exported URDF: a Franka Hand pad pushed down through the gap between the bar and
the front (tests/test_physics.py's check, with the pad's 9 mm across the gap)."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
import pybullet

from realikea.export.metadata import PART_LINK
from realikea.interop import pybullet_sim
from realikea.sim.robot import PAD_HALF

# half extents in the part frame: 18 mm along the bar (x), 18 mm along the push (y), the pad's
# 9 mm thickness across the gap (z, away from the front)
PROBE_HALF = (PAD_HALF[0], PAD_HALF[2], PAD_HALF[1])
PROBE_FORCE = 5.0  # N pushing the probe down (-y of the part frame) through the gap
PROBE_DAMPING = 5.0  # N s/m on its slide
PROBE_MASS = 0.1  # kg
TIMESTEP = 0.001  # s
SECONDS = 1.0
BLOCKED = 0.004  # m: a probe that travelled less than this was stopped at the bar's top
CLEARANCE_MARGIN = 0.002  # m between the probe and the part's top at the start


@dataclass(frozen=True)
class ProbePath:
    """Where the probe starts and how far it must travel, in the part frame (metres)."""

    gap: float  # the bar's underside above the mounting plane
    start: float  # y of the probe's centre at the start (above the part's top)
    through: float  # travel that clears the whole part

    @classmethod
    def from_metadata(cls, metadata: dict) -> ProbePath:
        """From an exported configuration's metadata.json: the gap behind the bar
        (`fingertip_clearance`) and the part's extent along y (`part_bounds`)."""
        bounds = metadata["part_bounds"]["part_frame"]
        top, bottom = bounds["max"][1], bounds["min"][1]
        return cls(
            gap=metadata["fingertip_clearance"]["clearance"],
            start=top + PROBE_HALF[1] + CLEARANCE_MARGIN,
            through=top - bottom + 2 * PROBE_HALF[1] + 2 * CLEARANCE_MARGIN,
        )

    @property
    def centre(self) -> np.ndarray:
        """The probe's centre at the start: mid-gap, above the part."""
        return np.array([0.0, self.start, self.gap / 2])


def part_pieces(urdf: Path) -> list[Path]:
    """The mesh files of the part link's <collision> elements in an exported URDF."""
    root = ET.parse(urdf).getroot()
    link = next(node for node in root.iter("link") if node.get("name") == PART_LINK)
    return [
        Path(urdf).parent / mesh.get("filename")
        for collision in link.iter("collision")
        for mesh in collision.iter("mesh")
    ]


def _mujoco_model(pieces: list[Path], path: ProbePath) -> mujoco.MjModel:
    """Collision pieces fixed in the part frame and the probe on a slide along -y."""
    meshes = "".join(f'<mesh name="m{i}" file="{p}"/>' for i, p in enumerate(pieces))
    geoms = "".join(f'<geom name="piece{i}" type="mesh" mesh="m{i}"/>' for i in range(len(pieces)))
    size = " ".join(map(str, PROBE_HALF))
    x, y, z = path.centre
    return mujoco.MjModel.from_xml_string(f"""
<mujoco>
  <option gravity="0 0 0" timestep="{TIMESTEP}"/>
  <default><geom solref="0.004 1"/></default>
  <asset>{meshes}</asset>
  <worldbody>
    {geoms}
    <body name="probe" pos="{x} {y} {z}">
      <joint name="push" type="slide" axis="0 -1 0" damping="{PROBE_DAMPING}"/>
      <geom name="probe" type="box" size="{size}" mass="{PROBE_MASS}"/>
    </body>
  </worldbody>
</mujoco>""")


def mujoco_probe(pieces: list[Path], path: ProbePath) -> float:
    """Push the probe past the pieces in MuJoCo; how far it travelled (m)."""
    model = _mujoco_model(pieces, path)
    data = mujoco.MjData(model)
    for _ in range(int(round(SECONDS / TIMESTEP))):
        data.qfrc_applied[0] = PROBE_FORCE
        mujoco.mj_step(model, data)
    return float(data.qpos[0])


def mujoco_clearance(pieces: list[Path], path: ProbePath) -> float:
    """MuJoCo's distance (m) from the probe, centred under the bar, to the nearest piece."""
    model = _mujoco_model(pieces, path)
    data = mujoco.MjData(model)
    data.qpos[0] = path.start  # the probe's centre at y = 0, under the bar
    mujoco.mj_forward(model, data)
    probe = model.geom("probe").id
    return min(
        mujoco.mj_geomDistance(model, data, probe, model.geom(f"piece{i}").id, 0.05, None)
        for i in range(len(pieces))
    )


def _pybullet_probe_body(front: pybullet_sim.LoadedFront, path: ProbePath) -> int:
    """The probe as a one-link body whose slide runs along the part frame's -y."""
    position, orientation = pybullet_sim.link_pose(front, front.part)
    start = pybullet_sim.to_world(front, front.part, path.centre)
    box = pybullet.createCollisionShape(
        pybullet.GEOM_BOX, halfExtents=PROBE_HALF, physicsClientId=front.client
    )
    body = pybullet.createMultiBody(
        baseMass=0,
        basePosition=start.tolist(),
        baseOrientation=orientation.tolist(),
        linkMasses=[PROBE_MASS],
        linkCollisionShapeIndices=[box],
        linkVisualShapeIndices=[-1],
        linkPositions=[[0, 0, 0]],
        linkOrientations=[[0, 0, 0, 1]],
        linkInertialFramePositions=[[0, 0, 0]],
        linkInertialFrameOrientations=[[0, 0, 0, 1]],
        linkParentIndices=[0],
        linkJointTypes=[pybullet.JOINT_PRISMATIC],
        linkJointAxis=[[0, -1, 0]],
        physicsClientId=front.client,
    )
    pybullet.setJointMotorControl2(
        body, 0, pybullet.VELOCITY_CONTROL, force=0, physicsClientId=front.client
    )
    pybullet.changeDynamics(  # undamped but for its slide's damping, as in MuJoCo
        body, -1, linearDamping=0.0, angularDamping=0.0, physicsClientId=front.client
    )
    return body


def _held_closed(client: int, urdf: Path) -> pybullet_sim.LoadedFront:
    """The exported configuration with its front held shut (the probe tests the part alone)."""
    front = pybullet_sim.load_front(client, urdf)
    pybullet.setJointMotorControl2(
        front.body, front.joint, pybullet.VELOCITY_CONTROL, targetVelocity=0, force=1e6,
        physicsClientId=client,
    )  # fmt: skip
    return front


def pybullet_probe(urdf: Path, path: ProbePath) -> float:
    """Push the probe past the exported part in PyBullet (no gravity, as in MuJoCo's check);
    how far it travelled (m)."""
    with pybullet_sim.session(TIMESTEP, gravity=(0.0, 0.0, 0.0)) as client:
        front = _held_closed(client, urdf)
        probe = _pybullet_probe_body(front, path)
        for _ in range(int(round(SECONDS / TIMESTEP))):
            velocity = pybullet.getJointState(probe, 0, physicsClientId=client)[1]
            pybullet.setJointMotorControl2(
                probe, 0, pybullet.TORQUE_CONTROL, force=PROBE_FORCE - PROBE_DAMPING * velocity,
                physicsClientId=client,
            )  # fmt: skip
            pybullet.stepSimulation(physicsClientId=client)
        return float(pybullet.getJointState(probe, 0, physicsClientId=client)[0])


def pybullet_clearance(urdf: Path, path: ProbePath) -> tuple[float, float]:
    """PyBullet's distances (m) from the probe, centred under the bar, to the part link and to the
    front link: the geometric ones less any collision margin it adds around their shapes."""
    with pybullet_sim.session(TIMESTEP, gravity=(0.0, 0.0, 0.0)) as client:
        front = _held_closed(client, urdf)
        probe = _pybullet_probe_body(front, path)
        pybullet.resetJointState(probe, 0, path.start, physicsClientId=client)

        def nearest(link: int) -> float:
            """Distance from the probe to one link of the configuration."""
            points = pybullet.getClosestPoints(
                probe, front.body, 0.05, linkIndexA=0, linkIndexB=link, physicsClientId=client
            )
            return min(p[8] for p in points)

        return nearest(front.part), nearest(front.joint)
