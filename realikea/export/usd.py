"""USD (usd-core's `pxr`): the configuration as a UsdPhysics articulation, meshes inside the file.

The root prim carries `UsdPhysics.ArticulationRootAPI`; the carcass is a static collider (no
rigid body: it is welded to the world, so the articulation has a fixed base); the front and the
part are rigid bodies with their MuJoCo masses and inertias (`MassAPI`), joined by the front's
`PhysicsPrismaticJoint` or `PhysicsRevoluteJoint` (limits in metres or degrees) and a
`PhysicsFixedJoint`. Each convex piece is its own mesh with `CollisionAPI` and `MeshCollisionAPI`
approximation "convexHull" (purpose "guide": not rendered); the visual mesh is a separate,
non-colliding mesh. The part's friction class is a `UsdPhysics.MaterialAPI` material bound for
physics.

Joint resistance. usd-core 26.11 ships `UsdPhysics` (joints, limits, `DriveAPI`, materials)
but neither NVIDIA's `PhysxSchema` nor any joint-friction attribute in `UsdPhysics`. So:

* damping is a `UsdPhysics.DriveAPI` (instance "linear" or "angular") of type "force" with
  stiffness 0 and target velocity 0, i.e. a pure damper: `drive:<i>:physics:damping` = MuJoCo's
  damping, in N s/m, or for a revolute joint in N m s/degree (UsdPhysics' angular drive unit,
  MuJoCo's N m s/rad x pi/180);
* friction is PhysX's `PhysxJointAxisAPI` (PhysX 5.6 / Omniverse), applied by name in the prim's
  `apiSchemas` and written as plain attributes `physxJointAxis:<i>:staticFrictionEffort` and
  `dynamicFrictionEffort`, both MuJoCo's frictionloss (N, or N m): a Coulomb friction force or
  torque, as MuJoCo's. (`PhysxJointAPI`'s older `physxJoint:jointFriction` is a unitless
  coefficient on the force a joint transmits, not a friction force, so it is not written.)
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import trimesh
from pxr import Gf, Sdf, Tf, Usd, UsdGeom, UsdPhysics, UsdShade, Vt

from realikea.export.model import Articulation, Joint, Link, Shape, quat_wxyz

RESISTANCE_SCHEMA = (
    "UsdPhysics DriveAPI:<linear|angular> (type force, stiffness 0, targetVelocity 0) "
    "physics:damping = damping (N s/m, or N m s/degree); PhysxJointAxisAPI:<linear|angular> "
    "staticFrictionEffort = dynamicFrictionEffort = frictionloss (N, or N m), authored as plain "
    "attributes because usd-core 26.11 has no PhysxSchema"
)
JOINT_SCHEMA = {"slide": UsdPhysics.PrismaticJoint, "hinge": UsdPhysics.RevoluteJoint}
DRIVE_INSTANCE = {"slide": "linear", "hinge": "angular"}


def _place(xformable: UsdGeom.Xformable, pose: np.ndarray, scale=None) -> None:
    """Author translate, orient (and scale) ops for a 4x4 pose."""
    xformable.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble).Set(Gf.Vec3d(*pose[:3, 3]))
    w, x, y, z = quat_wxyz(pose)
    xformable.AddOrientOp(UsdGeom.XformOp.PrecisionDouble).Set(Gf.Quatd(w, x, y, z))
    if scale is not None:
        xformable.AddScaleOp(UsdGeom.XformOp.PrecisionDouble).Set(Gf.Vec3d(*scale))


def _mesh(stage: Usd.Stage, path: Sdf.Path, file: Path) -> UsdGeom.Mesh:
    """A polygon mesh prim holding a mesh file's triangles."""
    data = trimesh.load(file, force="mesh")
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(np.asarray(data.vertices, np.float32)))
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray([3] * len(data.faces)))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(data.faces.astype(np.int32).ravel()))
    mesh.CreateExtentAttr([Gf.Vec3f(*data.bounds[0]), Gf.Vec3f(*data.bounds[1])])
    mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    return mesh


def _shape(stage: Usd.Stage, parent: Sdf.Path, shape: Shape, materials: dict) -> None:
    path = parent.AppendChild(Tf.MakeValidIdentifier(shape.name))
    if shape.mesh is None:
        geom = UsdGeom.Cube.Define(stage, path)
        geom.CreateSizeAttr(2.0)
        _place(geom, shape.pose, scale=shape.half_extents)
    else:
        geom = _mesh(stage, path, shape.mesh)
        _place(geom, shape.pose)
    geom.CreateDisplayColorAttr([Gf.Vec3f(*shape.rgba[:3])])
    geom.CreateDisplayOpacityAttr([shape.rgba[3]])
    if not shape.collides:
        return
    prim = geom.GetPrim()
    UsdPhysics.CollisionAPI.Apply(prim)
    if shape.mesh is not None:
        UsdPhysics.MeshCollisionAPI.Apply(prim).CreateApproximationAttr(
            UsdPhysics.Tokens.convexHull
        )
    if not shape.visual:
        geom.CreatePurposeAttr(UsdGeom.Tokens.guide)
    UsdShade.MaterialBindingAPI.Apply(prim).Bind(
        materials[shape.friction], UsdShade.Tokens.weakerThanDescendants, "physics"
    )


def _materials(stage: Usd.Stage, root: Sdf.Path, articulation: Articulation) -> dict:
    """One physics material per friction coefficient of the colliding shapes."""
    frictions = {s.friction for link in articulation.links for s in link.shapes if s.collides}
    scope = UsdGeom.Scope.Define(stage, root.AppendChild("materials")).GetPath()
    materials = {}
    for friction in sorted(frictions):
        path = scope.AppendChild(f"friction_{friction:g}".replace(".", "_"))
        material = UsdShade.Material.Define(stage, path)
        api = UsdPhysics.MaterialAPI.Apply(material.GetPrim())
        api.CreateStaticFrictionAttr(friction)
        api.CreateDynamicFrictionAttr(friction)
        materials[friction] = material
    return materials


def _body(stage: Usd.Stage, root: Sdf.Path, link: Link, materials: dict) -> None:
    xform = UsdGeom.Xform.Define(stage, root.AppendChild(link.name))
    _place(xform, link.pose)
    if link.parent is not None:  # the static root is a collider, not a rigid body
        prim = xform.GetPrim()
        UsdPhysics.RigidBodyAPI.Apply(prim)
        mass = UsdPhysics.MassAPI.Apply(prim)
        mass.CreateMassAttr(link.inertial.mass)
        mass.CreateCenterOfMassAttr(Gf.Vec3f(*link.inertial.pose[:3, 3]))
        mass.CreateDiagonalInertiaAttr(Gf.Vec3f(*link.inertial.moments))
        w, x, y, z = quat_wxyz(link.inertial.pose)
        mass.CreatePrincipalAxesAttr(Gf.Quatf(w, x, y, z))
    for shape in link.shapes:
        _shape(stage, xform.GetPath(), shape, materials)


def _x_to(axis: np.ndarray) -> np.ndarray:
    """A rotation matrix taking +x onto the unit vector `axis` (UsdPhysics joints move along x)."""
    x = np.array([1.0, 0.0, 0.0])
    v, c = np.cross(x, axis), float(x @ axis)
    if np.linalg.norm(v) < 1e-12:
        return np.eye(3) if c > 0 else np.diag([-1.0, -1.0, 1.0])
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + k + k @ k / (1 + c)


def _resistance(prim: Usd.Prim, joint: Joint) -> None:
    """The joint's damping as a force drive without stiffness, its friction as PhysX's axis API."""
    instance = DRIVE_INSTANCE[joint.type]
    per_unit = math.pi / 180.0 if joint.type == "hinge" else 1.0  # UsdPhysics: per degree
    drive = UsdPhysics.DriveAPI.Apply(prim, instance)
    drive.CreateTypeAttr(UsdPhysics.Tokens.force)
    drive.CreateStiffnessAttr(0.0)
    drive.CreateDampingAttr(joint.damping * per_unit)
    drive.CreateTargetVelocityAttr(0.0)
    prim.AddAppliedSchema(f"PhysxJointAxisAPI:{instance}")
    for effort in ("staticFrictionEffort", "dynamicFrictionEffort"):
        name = f"physxJointAxis:{instance}:{effort}"
        prim.CreateAttribute(name, Sdf.ValueTypeNames.Float, custom=False).Set(joint.frictionloss)


def _joint(stage: Usd.Stage, root: Sdf.Path, link: Link, parent: Link) -> None:
    j = link.joint
    path = root.AppendPath(f"joints/{link.name + '_weld' if j is None else j.name}")
    frame = np.eye(4)
    if j is None:
        joint = UsdPhysics.FixedJoint.Define(stage, path)
    else:
        joint = JOINT_SCHEMA[j.type].Define(stage, path)
        frame[:3, :3], frame[:3, 3] = _x_to(np.asarray(j.axis)), np.asarray(j.pos)
        joint.CreateAxisAttr(UsdPhysics.Tokens.x)
        to_unit = 1.0 if j.type == "slide" else 180.0 / math.pi  # revolute limits in degrees
        joint.CreateLowerLimitAttr(j.range[0] * to_unit)
        joint.CreateUpperLimitAttr(j.range[1] * to_unit)
        _resistance(joint.GetPrim(), j)
    in_parent = np.linalg.inv(parent.pose) @ link.pose @ frame
    joint.CreateBody0Rel().SetTargets([root.AppendChild(parent.name)])
    joint.CreateBody1Rel().SetTargets([root.AppendChild(link.name)])
    for pose, pos_attr, rot_attr in (
        (in_parent, joint.CreateLocalPos0Attr, joint.CreateLocalRot0Attr),
        (frame, joint.CreateLocalPos1Attr, joint.CreateLocalRot1Attr),
    ):
        pos_attr(Gf.Vec3f(*pose[:3, 3]))
        w, x, y, z = quat_wxyz(pose)
        rot_attr(Gf.Quatf(w, x, y, z))


def write_usd(articulation: Articulation, folder: Path, name: str) -> Path:
    """Write `folder/name`, self-contained (`.usd` and `.usdc`: binary crate; `.usda`: text)."""
    path = folder / name
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
    root = UsdGeom.Xform.Define(stage, "/" + Tf.MakeValidIdentifier(articulation.name))
    stage.SetDefaultPrim(root.GetPrim())
    UsdPhysics.ArticulationRootAPI.Apply(root.GetPrim())
    materials = _materials(stage, root.GetPath(), articulation)
    links = {link.name: link for link in articulation.links}
    for link in articulation.links:
        _body(stage, root.GetPath(), link, materials)
    UsdGeom.Scope.Define(stage, root.GetPath().AppendChild("joints"))
    for link in articulation.links[1:]:
        _joint(stage, root.GetPath(), link, links[link.parent])
    stage.GetRootLayer().Save()
    return path
