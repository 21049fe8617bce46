"""Antipodal grasps sampled on the part's visual mesh (the role GraspGen plays in the paper).

Per part, once: sample surface points of the visual mesh (part frame), and for each point the
jaw-closing axis the hand can reach that is closest to the inward normal (the hand's roll and yaw
are fixed per configuration, so a reachable jaw axis is the TCP y axis of
`tcp_rotation(pitch, nominal)` for a pitch in [-max_pitch, max_pitch]); cast a ray along that
axis to the opposite surface. A pair is an antipodal grasp when the width fits the open jaws
(with `clearance` on each side) and both outward normals lie within the friction cone
(half-angle atan(mu), mu = the pads' friction) of the closing axis. Each grasp is placed with the
contacts on the pads (at the pad centre or `depth_offsets` towards the fingertips) and checked
against the part mesh and the front plane (z = 0 of the part frame) with the hand's boxes (pads,
finger bodies, housing; `realikea/sim/robot.py`): open jaws swept along the approach from the
pregrasp to the grasp, finger bodies at the grasp width, and the closing pads (nothing of the
part may lie inside a pad box `contact_tolerance` outside the contact width, i.e. the pads first
touch the part at the contacts). Survivors are scored

    score = margin / cone + 0.5 * min(clearance, clearance_cap) / clearance_cap
            + 0.25 * (1 - depth_offset / pad half-length)
            + 0.1 * (1 - |pitch| / max_pitch) + 0.1 * (1 - |offset along the jaws' x| / half span)

(margin = cone half-angle minus the larger normal-to-axis angle; clearance = the smallest
distance of the hand's boxes to the mesh or the front plane; level grasps near the middle of the
part's span across the jaws break ties). Sampling is seeded and
deterministic; `realikea/policies/grasp_sampler.py` executes the best grasp.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import trimesh

from realikea.sim.ik import tcp_pitch, tcp_rotation
from realikea.sim.robot import (
    FINGER_BODY_CENTRE,
    FINGER_BODY_HALF,
    FINGER_MOUNT_Z,
    HAND_BOX,
    PAD_CENTRE,
    PAD_HALF,
    TCP_Z,
)
from realikea.tasks.facts import SceneFacts

_CHUNK = 128  # candidates checked for clearance at once
_KEEP = 64  # stop checking once this many grasps passed


@dataclass(frozen=True)
class SamplerParams:
    """The sampler's settings (realikea/conf/policy/grasp_sampler.yaml)."""

    samples: int = 4000  # surface points tried as the first contact
    clearance_points: int = 12000  # surface points the hand's boxes are checked against
    seed: int = 0
    friction: float | None = None  # mu of the friction cone; None: the pads' (SceneFacts)
    clearance: float = 0.002  # m: hand boxes to mesh / front plane, and per jaw at the width
    clearance_cap: float = 0.01  # m: more clearance than this scores no higher
    contact_tolerance: float = 0.001  # m: closing pads may not meet the part before this
    min_width: float = 0.003  # m: thinner features are not grasped
    depth_offsets: tuple[float, ...] = (0.0, 0.003, 0.006)  # m: contacts towards the tips
    max_pitch: float = 0.6  # rad (task.workspace.pitch)
    reach_tolerance: float = 0.05  # rad: a file's rotation off the reachable ones
    pregrasp: float = 0.08  # m back along the approach axis
    pull_distance: float = 0.4  # m along a drawer's opening direction
    pull_angle: float = 1.2  # rad a door or flap is turned
    pull_wrist: float = 0.3  # share of a hinged front's turn the wrist follows


@dataclass(frozen=True)
class Grasp:
    """A part-frame TCP pose and how good it is."""

    pose: np.ndarray  # (4, 4) part frame
    contacts: np.ndarray | None = None  # (2, 3) part frame: the sampled point, the ray's hit
    width: float = math.nan  # m between the contacts
    margin: float = math.nan  # rad inside the friction cone
    clearance: float = math.nan  # m
    score: float = math.nan


# --- the hand as boxes in the TCP frame -----------------------------------------------------
def hand_boxes(opening: float) -> list[tuple[np.ndarray, np.ndarray, str]]:
    """(centre, half-extents, name) of the hand's collision boxes in the TCP frame with the
    pads' inner faces `opening` m apart."""
    o = opening / 2.0
    boxes = []
    for sign in (1.0, -1.0):
        pad = np.array(PAD_CENTRE, float) - [0.0, 0.0, TCP_Z - FINGER_MOUNT_Z]
        pad[1] = sign * (o + PAD_CENTRE[1])
        body = np.array(FINGER_BODY_CENTRE, float) + [0.0, 0.0, FINGER_MOUNT_Z - TCP_Z]
        body[1] = sign * (o + FINGER_BODY_CENTRE[1])
        boxes.append((pad, np.array(PAD_HALF, float), "pad"))
        boxes.append((body, np.array(FINGER_BODY_HALF, float), "body"))
    centre, half = HAND_BOX
    boxes.append((np.array(centre, float) - [0.0, 0.0, TCP_Z], np.array(half, float), "hand"))
    return boxes


def _swept(centre, half, back: float):
    """A box extended `back` m against the approach (TCP -z): its sweep from the pregrasp."""
    centre, half = centre.copy(), half.copy()
    centre[2] -= back / 2.0
    half[2] += back / 2.0
    return centre, half


def _box_distance(points: np.ndarray, centre, half) -> np.ndarray:
    """Distance (0 inside) of points (..., M, 3) in the TCP frame to an axis-aligned box."""
    excess = np.abs(points - centre)
    excess -= half
    np.maximum(excess, 0.0, out=excess)
    return np.sqrt(np.einsum("...i,...i->...", excess, excess))


_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)


# --- reachability ---------------------------------------------------------------------------
def reference_rotation(facts: SceneFacts) -> np.ndarray:
    """The nominal TCP orientation (pitch 0) in the part frame, the base's yaw perturbation
    taken out: the part frame turned about the world z until its z axis (out of the front) points
    against the approach in the horizontal plane. The same for every episode of a configuration."""
    z = facts.part_rot[:, 2]
    back = -facts.tcp_nominal[:, 2]
    yaw = math.atan2(z[1], z[0]) - math.atan2(back[1], back[0])
    c, s = math.cos(-yaw), math.sin(-yaw)
    unyaw = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return (unyaw @ facts.part_rot).T @ facts.tcp_nominal


def _pitched(reference: np.ndarray, pitch) -> np.ndarray:
    """`tcp_rotation(pitch, reference)` for an array of pitches: (N, 3, 3)."""
    pitch = np.atleast_1d(pitch)
    c, s = np.cos(pitch), np.sin(pitch)
    rx = np.zeros((len(pitch), 3, 3))
    rx[:, 0, 0] = 1.0
    rx[:, 1, 1], rx[:, 1, 2], rx[:, 2, 1], rx[:, 2, 2] = c, -s, s, c
    return reference @ rx


def reachable_pitch(rotation: np.ndarray, reference: np.ndarray, max_pitch: float, tol: float):
    """The pitch at which the fixed-roll/yaw hand has `rotation` (or its half turn about the
    approach), or None when no pitch in range comes within `tol` rad of it."""
    for flip in (np.eye(3), np.diag([-1.0, -1.0, 1.0])):
        r = rotation @ flip
        pitch = tcp_pitch(r, reference)
        if abs(pitch) > max_pitch + tol:
            continue
        near = tcp_rotation(float(np.clip(pitch, -max_pitch, max_pitch)), reference)
        cos = (np.trace(near.T @ r) - 1.0) / 2.0
        if math.acos(min(max(cos, -1.0), 1.0)) <= tol:
            return float(pitch)
    return None


def world_pitch(rotation: np.ndarray, nominal: np.ndarray) -> float:
    """The pitch whose jaw axis is nearest the rotation's (up to the jaws' half-turn symmetry)."""
    pitch = tcp_pitch(rotation, nominal)
    return (pitch + math.pi / 2.0) % math.pi - math.pi / 2.0


# --- sampling -------------------------------------------------------------------------------
class _Pairs(NamedTuple):
    """Antipodal contact pairs: the sampled point, the opposite hit, the closing pitch, the
    width between them and the margin inside the friction cone."""

    points: np.ndarray
    hits: np.ndarray
    pitch: np.ndarray
    width: np.ndarray
    margin: np.ndarray


def _antipodal_pairs(mesh, rng, reference, cone: float, max_aperture: float, params) -> _Pairs:
    """Surface points whose reachable closing axis lies inside the friction cone, paired with
    the opposite surface where the jaws fit and that contact is inside the cone too."""
    points, faces = trimesh.sample.sample_surface(mesh, params.samples, seed=rng)
    normals = mesh.face_normals[faces]
    ry, rz = reference[:, 1], reference[:, 2]
    # the reachable closing axis nearest the inward normal: a line angle in the (ry, rz) plane
    u, v = -normals @ ry, -normals @ rz
    sign = np.where(u < 0.0, -1.0, 1.0)
    pitch = np.clip(np.arctan2(sign * v, sign * u), -params.max_pitch, params.max_pitch)
    axis = sign[:, None] * (np.cos(pitch)[:, None] * ry + np.sin(pitch)[:, None] * rz)
    angle_in = np.arccos(np.clip(np.einsum("ij,ij->i", axis, -normals), -1.0, 1.0))
    ok = angle_in < cone
    points, normals, axis, pitch, angle_in = (
        a[ok] for a in (points, normals, axis, pitch, angle_in)
    )
    if not len(points):
        empty = np.zeros((0, 3))
        return _Pairs(empty, empty, np.zeros(0), np.zeros(0), np.zeros(0))
    # the opposite surface: first hit along the closing axis (the exact triangle intersector,
    # deterministic, not embree's float32 one)
    caster = trimesh.ray.ray_triangle.RayMeshIntersector(mesh)
    hits, rays, tris = caster.intersects_location(points + 1e-5 * axis, axis, multiple_hits=False)
    order = np.argsort(rays, kind="stable")
    hits, rays, tris = hits[order], rays[order], tris[order]
    width = np.linalg.norm(hits - points[rays], axis=1)
    normal_out = mesh.face_normals[tris]
    angle_out = np.arccos(np.clip(np.einsum("ij,ij->i", normal_out, axis[rays]), -1.0, 1.0))
    room = max_aperture - 2.0 * params.clearance
    good = (width >= params.min_width) & (width <= room) & (angle_out < cone)
    rays, hits, width, angle_out = rays[good], hits[good], width[good], angle_out[good]
    margin = cone - np.maximum(angle_in[rays], angle_out)
    return _Pairs(points[rays], hits, pitch[rays], width, margin)


def sample_grasps(
    mesh_path: str,
    reference: np.ndarray,
    friction: float,
    max_aperture: float,
    params: SamplerParams = SamplerParams(),
) -> list[Grasp]:
    """Antipodal, reachable, collision-free grasps on the mesh (part frame), best first."""
    mesh = trimesh.load(mesh_path, force="mesh")
    rng = np.random.default_rng(params.seed)
    cone = math.atan(friction)
    pairs = _antipodal_pairs(mesh, rng, reference, cone, max_aperture, params)
    if not len(pairs.points):
        return []
    centre = (pairs.points + pairs.hits) / 2.0
    rotations = _pitched(reference, pairs.pitch)
    # candidates: each pair with the contacts at the pad centre or nearer the fingertips
    offsets = np.asarray(params.depth_offsets, float)
    n = len(pairs.points)
    cand_rot = np.repeat(rotations, len(offsets), axis=0)
    cand_offset = np.tile(offsets, n)
    cand_tcp = np.repeat(centre, len(offsets), axis=0) - cand_offset[:, None] * cand_rot[:, :, 2]
    cand_width = np.repeat(pairs.width, len(offsets))
    cand_margin = np.repeat(pairs.margin, len(offsets))
    cand_contacts = np.repeat(np.stack([pairs.points, pairs.hits], axis=1), len(offsets), axis=0)
    order = np.lexsort((cand_offset, -cand_margin))  # best margin first, then the deeper
    # one candidate per 1 mm cell of TCP position and 0.02 rad of pitch (the first in order)
    cand_pitch = np.repeat(pairs.pitch, len(offsets))
    cells = np.column_stack([np.round(cand_tcp / 0.001), np.round(cand_pitch / 0.02)])
    _, first = np.unique(cells[order], axis=0, return_index=True)
    order = order[np.sort(first)]
    cloud, _ = trimesh.sample.sample_surface(mesh, params.clearance_points, seed=rng)
    middle = mesh.bounds.mean(axis=0)
    spread = max(float(np.ptp(mesh.vertices @ reference[:, 0])) / 2.0, 1e-6)
    grasps: list[Grasp] = []
    for start in range(0, len(order), _CHUNK):
        idx = order[start : start + _CHUNK]
        clear = _clearance(
            cloud, cand_tcp[idx], cand_rot[idx], cand_width[idx], max_aperture, params
        )
        for k, c in zip(idx, clear, strict=True):
            if c < params.clearance:
                continue
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = cand_rot[k], cand_tcp[k]
            offcentre = abs((cand_tcp[k] - middle) @ reference[:, 0]) / spread
            score = (
                cand_margin[k] / cone
                + 0.5 * min(c, params.clearance_cap) / params.clearance_cap
                + 0.25 * (1.0 - cand_offset[k] / PAD_HALF[2])
                + 0.1 * (1.0 - abs(cand_pitch[k]) / max(params.max_pitch, 1e-9))
                + 0.1 * (1.0 - min(offcentre, 1.0))
            )
            width_k, margin_k = float(cand_width[k]), float(cand_margin[k])
            grasps.append(Grasp(pose, cand_contacts[k], width_k, margin_k, float(c), score))
        if len(grasps) >= _KEEP:
            break
    grasps.sort(key=lambda g: -g.score)  # stable: ties keep the candidate order
    return grasps


def _clearance(cloud, tcp, rot, width, max_aperture, params: SamplerParams) -> np.ndarray:
    """Per candidate: the hand's smallest distance to the mesh points and the front plane
    (-inf when the closing pads meet the part before the contacts)."""
    local = np.einsum("nmi,nij->nmj", cloud[None] - tcp[:, None], rot)  # (N, M, 3) TCP frame
    depth = rot[:, :, 2]  # (N, 3): each TCP axis's part-frame z component

    def plane(centre, half):  # smallest part-frame z of a box's corners, per candidate
        corners = centre[..., None, :] + _CORNERS * half  # (8, 3) or (N, 8, 3)
        return np.min(np.sum(corners * depth[:, None, :], axis=2), axis=1) + tcp[:, 2]

    best = np.full(len(tcp), np.inf)
    # closed on the contacts: the pads must first touch the part at the contacts
    closed = width + 2.0 * params.contact_tolerance
    boxes = []
    for centre, half, name in hand_boxes(0.0):
        if name != "hand":
            centre = np.tile(centre, (len(tcp), 1))
            centre[:, 1] += np.sign(centre[:, 1]) * closed / 2.0
            boxes.append((centre[:, None, :], half, name))
    for centre, half, name in sorted(boxes, key=lambda b: b[2] != "pad"):  # pads first
        alive = np.flatnonzero(best >= params.clearance)
        d = _box_distance(local[alive], centre[alive], half).min(axis=1)
        if name == "pad":  # touching the pads is the grasp; inside them is not
            best[alive[d <= 0.0]] = -np.inf
        else:
            best[alive] = np.minimum(best[alive], d)
        best = np.minimum(best, plane(centre[:, 0], half))
    # open jaws along the approach, from the pregrasp to the grasp
    for centre, half, _ in hand_boxes(max_aperture):
        centre, half = _swept(centre, half, params.pregrasp)
        best = np.minimum(best, plane(centre, half))
        alive = best >= params.clearance
        if not alive.any():
            break
        best[alive] = np.minimum(best[alive], _box_distance(local[alive], centre, half).min(1))
    return best
