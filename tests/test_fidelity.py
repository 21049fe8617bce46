"""The surface-deviation metric against shapes whose distance distributions are known exactly.

Tolerances: the metric samples N points per shell, so a mean may differ from the true one by a few
standard errors (we allow 5 sigma/sqrt(N)) and a sample p-quantile lies between the true
(p -/+ 5 sqrt(p(1-p)/N))-quantiles. Curved shapes are tessellated: every vertex lies on the true
surface and every flat triangle lies within its sagitta ``sag`` (largest gap between a triangle
and the true surface) inside it, so each distance moves by at most the sum of both shells'
sagittas, and the flat-vs-curved area weighting changes a mean by about as much again; we allow
4 x the sagitta sum. The reference distributions are computed on fine quadrature grids of the
exact formulas, whose own error is far below these tolerances.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

from realikea.cli import main
from realikea.errors import RealIkeaError
from realikea.fidelity.meshes import load_collision, load_pair, load_visual
from realikea.fidelity.metric import collision_shell, surface_deviation

N = 100_000
Z = 5.0  # standard errors allowed


# --- reference distributions -------------------------------------------------------------------


class Reference:
    """An exact distance distribution given as values with area weights on a quadrature grid."""

    def __init__(self, values: np.ndarray, weights: np.ndarray):
        order = np.argsort(values)
        self.values = values[order]
        self.cdf = np.cumsum(weights[order]) / weights.sum()
        self.mean = float(np.dot(values, weights) / weights.sum())
        self.std = float(np.sqrt(np.dot((values - self.mean) ** 2, weights) / weights.sum()))

    def quantile(self, p: float) -> float:
        p = min(max(p, 0.0), 1.0)
        return float(self.values[min(np.searchsorted(self.cdf, p), len(self.values) - 1)])

    def check(self, dist: np.ndarray, tess: float, true_max: float, max_deficit: float) -> None:
        """Mean, median, p90 and max of a sampled distance array against this distribution."""
        n = len(dist)
        assert abs(dist.mean() - self.mean) <= Z * self.std / np.sqrt(n) + tess
        for p in (0.5, 0.9):
            dp = Z * np.sqrt(p * (1 - p) / n)
            got = np.percentile(dist, 100 * p)
            assert self.quantile(p - dp) - tess <= got <= self.quantile(p + dp) + tess, p
        assert true_max - max_deficit - tess <= dist.max() <= true_max + tess


def sagitta(mesh: trimesh.Trimesh, radius: float) -> float:
    """Deepest point of a sphere's flat triangles below the sphere (centred at the origin)."""
    plane_dist = np.abs(np.einsum("ij,ij->i", mesh.face_normals, mesh.triangles[:, 0]))
    return float(radius - plane_dist.min())


def midpoints(lo: float, hi: float, n: int) -> np.ndarray:
    return lo + (np.arange(n) + 0.5) * (hi - lo) / n


# --- analytic cases -----------------------------------------------------------------------------


def test_cube_against_hull_of_circumscribed_sphere():
    a = 0.05  # half side of the cube P
    R = a * np.sqrt(3.0)  # circumscribed sphere, its hull is Q
    cube = trimesh.creation.box(extents=(2 * a, 2 * a, 2 * a))
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=R)
    sag = sagitta(sphere, R)
    assert sag < 3e-5  # 20,480 faces: about 0.02 mm
    tess = 4 * sag
    result = surface_deviation(cube, [sphere], samples=N, seed=1)

    # Q -> P: sphere points, distance to the cube = |max(|x|-a, 0)|. Area is uniform in
    # (cos(theta), phi); one octant by symmetry.
    u, phi = np.meshgrid(midpoints(0, 1, 1200), midpoints(0, np.pi / 2, 1200))
    s = np.sqrt(1 - u**2)
    x = R * np.stack([s * np.cos(phi), s * np.sin(phi), u])
    d_qp = np.sqrt((np.maximum(x - a, 0.0) ** 2).sum(axis=0)).ravel()
    # the max, R - a, is on the 6 axes: the samples come within angle rho of one with
    # probability 1 - exp(-20) (6 caps of area fraction rho^2/4), where d >= R cos(rho) - a.
    rho2 = 20 / (1.5 * N)
    Reference(d_qp, np.ones_like(d_qp)).check(
        result.q_dist, tess, true_max=R - a, max_deficit=R * rho2 / 2
    )

    # P -> Q: cube points, distance R - |p| to the sphere; one quarter face by symmetry.
    fx, fy = np.meshgrid(midpoints(0, a, 1200), midpoints(0, a, 1200))
    d_pq = (R - np.sqrt(fx**2 + fy**2 + a**2)).ravel()
    # max R - a at the 6 face centres; samples within r of one with probability 1 - exp(-20)
    r2 = 80 * a**2 / (np.pi * N)
    Reference(d_pq, np.ones_like(d_pq)).check(
        result.p_dist, tess, true_max=R - a, max_deficit=r2 / (2 * a)
    )


def test_torus_against_its_convex_hull():
    R, r = 0.04, 0.01  # major and minor radius
    n_major, n_minor = 128, 64
    torus = trimesh.creation.torus(R, r, major_sections=n_major, minor_sections=n_minor)
    sag = (R + r) * (1 - np.cos(np.pi / n_major)) + r * (1 - np.cos(np.pi / n_minor))
    tess = 4 * 2 * sag  # both shells are tessellated
    result = surface_deviation(torus, [torus], samples=N, seed=2)  # a piece is hulled

    # The hull is the outer half of the tube (distance 0) plus two discs of radius R at z = +-r,
    # which fill the hole: a disc point at radius rho is sqrt((R - rho)^2 + r^2) - r from the torus.
    outer_area = 2 * np.pi * r * (np.pi * R + 2 * r)
    rho = midpoints(0, R, 200_000)
    disc = np.sqrt((R - rho) ** 2 + r**2) - r
    d_qp = np.concatenate([[0.0], disc])
    w_qp = np.concatenate([[outer_area], 2 * 2 * np.pi * rho * (R / len(rho))])
    true_max = np.sqrt(R**2 + r**2) - r  # the middle of the hole
    # d is 1-Lipschitz; discs of radius rho0 around both hole centres hold a sample with
    # probability 1 - exp(-20)
    rho0 = np.sqrt(10 * w_qp.sum() / (np.pi * N))
    Reference(d_qp, w_qp).check(result.q_dist, tess, true_max=true_max, max_deficit=rho0)
    assert result.q_to_p.max == pytest.approx(true_max, abs=rho0 + tess)

    # P -> Q: the outer half of the torus is on the hull; an inner-half point at tube angle phi is
    # r (1 - |sin phi|) below the disc over it. Area weight (R + r cos phi).
    phi = midpoints(0, 2 * np.pi, 400_000)
    d_pq = np.where(np.cos(phi) >= 0, 0.0, r * (1 - np.abs(np.sin(phi))))
    # max r on the innermost equator; a band of half-angle delta there holds a sample w.p.
    # 1 - exp(-20) and d >= r (1 - delta) in it
    delta = 20 * np.pi * R / (N * (R - r))
    Reference(d_pq, R + r * np.cos(phi)).check(
        result.p_dist, tess, true_max=r, max_deficit=r * delta
    )


def test_identical_meshes_give_zero():
    for mesh in (
        trimesh.creation.icosphere(3, radius=0.03),
        trimesh.creation.box((0.1, 0.02, 0.03)),
    ):
        result = surface_deviation(mesh, [mesh], samples=20_000)
        assert result.q_to_p.max < 1e-9
        assert result.p_to_q.max < 1e-9


def test_shifted_copy():
    a, delta = 0.05, 0.002  # half side, shift along x
    box = trimesh.creation.box(extents=(2 * a, 2 * a, 2 * a))
    moved = box.copy()
    moved.apply_translation((delta, 0, 0))
    result = surface_deviation(box, [moved], samples=N, seed=3)
    # Q's +x face is delta out; its -x face is min(delta, a-|y|, a-|z|) inside (mean over the face
    # (a/3)(1 - (1 - delta/a)^3)); a strip of width delta of each side face sticks out by 0..delta.
    mean = (4 * a**2 * delta + 4 * a**2 * a / 3 * (1 - (1 - delta / a) ** 3) + 4 * a * delta**2) / (
        24 * a**2
    )
    for dist, dev in ((result.q_dist, result.q_to_p), (result.p_dist, result.p_to_q)):
        assert abs(dev.mean - mean) <= Z * dist.std() / np.sqrt(N)
        assert dev.median == pytest.approx(0.0, abs=1e-12)  # 65 % of the area is shared
        assert dev.p90 == pytest.approx(delta, abs=1e-12)  # the +-x faces are a sixth each
        assert dev.max == pytest.approx(delta, abs=1e-12)


def box_between(lo, hi) -> trimesh.Trimesh:
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    box = trimesh.creation.box(extents=hi - lo)
    box.apply_translation((lo + hi) / 2)
    return box


def l_prism() -> trimesh.Trimesh:
    """An L-shaped prism: [-5, 15] x [-5, 5] plus [-5, 5] x [5, 15] (cm), z in [-5, 5]."""
    pts = np.array([(-5, -5), (15, -5), (15, 5), (5, 5), (5, 15), (-5, 15), (-5, 5)]) * 0.01
    tris = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 6], [6, 3, 4], [6, 4, 5]])
    prism = trimesh.creation.extrude_triangulation(pts, tris, height=0.1)
    prism.apply_translation((0, 0, -0.05))
    return prism


@pytest.mark.parametrize(
    ("pieces", "union"),
    [
        pytest.param(  # overlapping, every outer face coplanar with the other box's
            [box_between((0, 0, 0), (0.15, 0.1, 0.1)), box_between((0.05, 0, 0), (0.2, 0.1, 0.1))],
            box_between((0, 0, 0), (0.2, 0.1, 0.1)),
            id="overlap-to-box",
        ),
        pytest.param(  # touching along a whole face
            [box_between((0, 0, 0), (0.1, 0.1, 0.1)), box_between((0.1, 0, 0), (0.2, 0.1, 0.1))],
            box_between((0, 0, 0), (0.2, 0.1, 0.1)),
            id="touching",
        ),
        pytest.param(
            [
                box_between((-0.05, -0.05, -0.05), (0.15, 0.05, 0.05)),
                box_between((-0.05, -0.05, -0.05), (0.05, 0.15, 0.05)),
            ],
            l_prism(),
            id="L-shape",
        ),
    ],
)
def test_union_boundary_has_no_internal_faces(pieces, union):
    shell = collision_shell(pieces)
    assert shell.area == pytest.approx(union.area, rel=1e-9)
    assert shell.area < sum(p.area for p in pieces) - 0.01  # the inner faces are gone
    result = surface_deviation(union, pieces, samples=20_000)
    assert result.q_to_p.max < 1e-9
    assert result.p_to_q.max < 1e-9


def test_micrometre_slit_between_pieces_is_closed_and_a_real_gap_is_not():
    def pair(gap):
        return [
            box_between((0, 0, 0), (0.1, 0.1, 0.1)),
            box_between((0.1 + gap, 0, 0), (0.2, 0.1, 0.1)),
        ]

    # CoACD pieces sharing a cut plane leave slits of a few micrometres: both walls go
    slit = collision_shell(pair(2e-6))
    assert slit.metadata["crack_area"] == pytest.approx(2 * 0.01, rel=1e-9)
    whole = box_between((0, 0, 0), (0.2, 0.1, 0.1))
    result = surface_deviation(whole, pair(2e-6), samples=20_000)
    assert result.q_to_p.max < 2e-6
    assert result.p_to_q.max < 2e-6
    # a 5 mm gap is geometry a finger could use: kept
    gap = collision_shell(pair(0.005))
    assert gap.metadata["crack_area"] == 0.0
    assert gap.area == pytest.approx(sum(p.area for p in pair(0.005)), rel=1e-9)
    # three pieces: a slab on two blocks, slits of 2 um above and 0.5 um between the blocks
    three = [
        box_between((0, 0, 0), (0.1, 0.1, 0.05)),
        box_between((0.1 + 5e-7, 0, 0), (0.2, 0.1, 0.05)),
        box_between((0, 0, 0.05 + 2e-6), (0.2, 0.1, 0.1)),
    ]
    result = surface_deviation(whole, three, samples=20_000)
    assert result.q_to_p.max < 2e-6
    assert result.p_to_q.max < 2e-6
    # and the exact union (no closing) keeps the slit walls
    exact = collision_shell(pair(2e-6), gap_tol=None)
    assert exact.area == pytest.approx(sum(p.area for p in pair(2e-6)), rel=1e-9)


def test_same_seed_same_result_other_seed_other_points():
    mesh = trimesh.creation.icosphere(2, radius=0.02)
    hull = [trimesh.creation.box((0.04, 0.04, 0.04))]
    one = surface_deviation(mesh, hull, samples=5_000, seed=7)
    two = surface_deviation(mesh, hull, samples=5_000, seed=7)
    assert np.array_equal(one.q_points, two.q_points)
    assert np.array_equal(one.p_dist, two.p_dist)
    assert one.to_dict() == two.to_dict()
    other = surface_deviation(mesh, hull, samples=5_000, seed=8)
    assert not np.array_equal(one.q_points, other.q_points)


def test_to_dict_keys():
    mesh = trimesh.creation.box((0.1, 0.1, 0.1))
    d = surface_deviation(mesh, [mesh], samples=100).to_dict()
    assert set(d) == {"q_to_p", "p_to_q"}
    assert all(set(v) == {"mean", "median", "p90", "max"} for v in d.values())


# --- files and errors ---------------------------------------------------------------------------


@pytest.fixture
def files(tmp_path):
    """A visual box, a two-piece collision file, the same in millimetres, and bad files."""
    visual = box_between((0, 0, 0), (0.1, 0.04, 0.02))
    pieces = [
        box_between((0, 0, 0), (0.06, 0.04, 0.021)),
        box_between((0.05, 0, 0), (0.1, 0.04, 0.02)),
    ]
    paths = {"visual": tmp_path / "visual.stl", "collision": tmp_path / "collision.obj"}
    visual.export(paths["visual"])
    trimesh.Scene({f"piece{k}": p for k, p in enumerate(pieces)}).export(paths["collision"])
    paths["collision_mm"] = tmp_path / "collision_mm.obj"
    mm = trimesh.Scene({f"piece{k}": p.copy().apply_scale(1000) for k, p in enumerate(pieces)})
    mm.export(paths["collision_mm"])
    paths["empty"] = tmp_path / "empty.obj"
    paths["empty"].write_text("# nothing here\n")
    paths["points"] = tmp_path / "points.obj"
    paths["points"].write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n")
    paths["text"] = tmp_path / "notes.txt"
    paths["text"].write_text("not a mesh\n")
    paths["concave"] = tmp_path / "concave.stl"
    l_prism().export(paths["concave"])
    return paths


def test_loading_pieces_from_one_file(files):
    pieces = load_collision([files["collision"]])
    assert len(pieces) == 2
    assert len(load_visual(files["visual"]).faces) == 12


@pytest.mark.parametrize(
    ("key", "words"),
    [
        ("missing", ["no such file"]),
        ("empty", ["empty mesh", "no faces"]),
        ("points", ["not a triangle mesh"]),
        ("text", ["not a readable mesh"]),
        ("collision_mm", ["1000 times", "millimetres", "rescale the collision mesh by 0.001"]),
        ("concave", ["not convex"]),
    ],
)
def test_bad_collision_input_is_named(files, tmp_path, key, words):
    path = files.get(key, tmp_path / "missing.obj")
    with pytest.raises(RealIkeaError) as err:
        load_pair(files["visual"], [path])
    message = str(err.value)
    assert path.name in message
    for word in words:
        assert word in message


def test_bad_visual_input_is_named(files, tmp_path):
    for path in (tmp_path / "nope.stl", files["empty"], files["text"]):
        with pytest.raises(RealIkeaError, match=path.name):
            load_pair(path, [files["collision"]])


# --- command line -------------------------------------------------------------------------------


def test_cli_measure_json(files, capsys):
    argv = ["fidelity", "measure", str(files["visual"]), str(files["collision"])]
    assert main([*argv, "--samples", "20000", "--seed", "4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)  # exactly one JSON object
    assert set(out) == {"q_to_p", "p_to_q"}
    # the first piece sticks out 1 mm above the visual box's top over 6 x 4 cm: max 1 mm
    assert out["q_to_p"]["max"] == pytest.approx(0.001, abs=1e-9)
    # and the visual top under it is 1 mm from the collision shell (the inner faces are gone)
    assert out["p_to_q"]["max"] == pytest.approx(0.001, abs=1e-9)
    assert 0 < out["q_to_p"]["mean"] < out["q_to_p"]["max"]
    assert main([*argv, "--samples", "2000"]) == 0
    table = capsys.readouterr().out
    assert "E(Q->P)" in table and "mm" in table and "2 convex pieces" in table


def test_cli_error_is_one_line_exit_2(files, capsys):
    code = main(["fidelity", "measure", str(files["visual"]), str(files["collision_mm"])])
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("realikea: error:") and "\n" not in err
    assert "collision_mm.obj" in err
