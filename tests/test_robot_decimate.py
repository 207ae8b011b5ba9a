"""Decimated visual meshes (issue 38): fewer triangles near the original surface, deterministic, and a
Panda whose bodies, joints, actuators and collision geoms are those of the full-resolution model."""

import dataclasses

import mujoco
import numpy as np
import pytest

from ergosim.robot import get_robot
from ergosim.robot.assets import erd_file, resolve_url
from ergosim.robot.collada import read_collada
from ergosim.robot.decimate import decimate, target_faces
from ergosim.robot.mjcf import robot_mjcf
from ergosim.robot.model import robot_files
from ergosim.robot.urdf import read_urdf

PANDA = get_robot("panda")


def _compile(files) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(files.xml.replace('meshdir="assets"', 'meshdir="m"'),
                                          assets={f"m/{k}": v for k, v in files.assets.items()})


def _area(mesh) -> tuple[float, np.ndarray]:
    """Surface area [m^2] and area-weighted centre (3,) [m] of a triangle mesh."""
    tri = mesh.vertices[mesh.faces]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    return float(area.sum()), (tri.mean(axis=1) * area[:, None]).sum(0) / area.sum()


@pytest.fixture(scope="module")
def link_mesh():
    """The largest coloured part of the Panda's link-5 visual (15,074 triangles)."""
    urdf = read_urdf(erd_file(PANDA.urdf))
    shape = urdf.links["panda_link5"].visuals[0]
    return max(read_collada(resolve_url(shape.file)), key=lambda m: len(m.faces))


@pytest.fixture(scope="module")
def models():
    """(decimated as committed, full resolution): the Panda compiled from both recipes."""
    urdf = read_urdf(erd_file(PANDA.urdf))
    full = robot_mjcf(urdf, dataclasses.replace(PANDA.recipe, visual_keep=1.0))
    return _compile(robot_files(PANDA)), _compile(full)


def test_target_faces_keeps_a_fraction_but_small_parts_whole():
    assert target_faces(15074, 0.15, 200) == 2261
    assert target_faces(1000, 0.1, 200) == 200
    assert target_faces(150, 0.1, 200) == 150
    assert target_faces(500, 1.0, 200) == 500
    for bad in (0.0, -0.1, 1.5):
        with pytest.raises(ValueError, match="keep"):
            target_faces(100, bad, 10)


def test_decimation_keeps_the_surface_and_the_colour(link_mesh):
    out = decimate(link_mesh, 0.15)
    assert len(out.faces) == pytest.approx(target_faces(len(link_mesh.faces), 0.15, 200), rel=0.02)
    assert out.rgba == link_mesh.rgba
    assert out.faces.min() >= 0 and out.faces.max() < len(out.vertices)
    lo, hi = link_mesh.vertices.min(0), link_mesh.vertices.max(0)
    np.testing.assert_allclose(out.vertices.min(0), lo, atol=2e-3)  # the same extent, to 2 mm
    np.testing.assert_allclose(out.vertices.max(0), hi, atol=2e-3)
    # the same surface: its area to 1 %, its area-weighted centre to 1 mm
    (a0, c0), (a1, c1) = _area(link_mesh), _area(out)
    assert a1 == pytest.approx(a0, rel=0.01)
    assert np.linalg.norm(c1 - c0) < 1e-3
    again = decimate(link_mesh, 0.15)
    assert np.array_equal(again.vertices, out.vertices) and np.array_equal(again.faces, out.faces)
    assert decimate(link_mesh, 1.0) is link_mesh


def _visual(m):
    return [g for g in range(m.ngeom) if m.geom_group[g] == 2]


def _collision(m):
    return [g for g in range(m.ngeom) if m.geom_group[g] != 2]


def test_the_decimated_panda_simulates_as_the_full_one(models):
    dec, full = models
    assert (dec.nbody, dec.njnt, dec.nu, dec.neq, dec.ntendon, dec.nsite) == \
        (full.nbody, full.njnt, full.nu, full.neq, full.ntendon, full.nsite)
    for attr in ("body_pos", "body_quat", "body_mass", "body_inertia", "body_ipos", "body_iquat", "jnt_range",
                 "jnt_axis", "dof_armature", "dof_damping", "actuator_gainprm", "actuator_biasprm"):
        a, b = getattr(dec, attr), getattr(full, attr)
        assert np.array_equal(a, b)
    assert [dec.body(i).name for i in range(dec.nbody)] == [full.body(i).name for i in range(full.nbody)]
    cd, cf = _collision(dec), _collision(full)
    assert len(cd) == len(cf) >= 8
    for attr in ("geom_type", "geom_size", "geom_pos", "geom_quat", "geom_contype", "geom_conaffinity",
                 "geom_friction", "geom_bodyid", "geom_rbound"):
        assert np.array_equal(getattr(dec, attr)[cd], getattr(full, attr)[cf]), attr
    for gd, gf in zip(cd, cf, strict=True):  # the collision meshes themselves, vertex for vertex
        if dec.geom_type[gd] == mujoco.mjtGeom.mjGEOM_MESH:
            md, mf = dec.geom_dataid[gd], full.geom_dataid[gf]
            sd = slice(dec.mesh_vertadr[md], dec.mesh_vertadr[md] + dec.mesh_vertnum[md])
            sf = slice(full.mesh_vertadr[mf], full.mesh_vertadr[mf] + full.mesh_vertnum[mf])
            assert np.array_equal(dec.mesh_vert[sd], full.mesh_vert[sf])
    vd, vf = _visual(dec), _visual(full)
    assert len(vd) == len(vf)
    assert np.array_equal(dec.geom_matid[vd], full.geom_matid[vf])
    assert not dec.geom_contype[vd].any() and not dec.geom_conaffinity[vd].any()
    faces = [sum(int(m.mesh_facenum[i]) for i in set(m.geom_dataid[v])) for m, v in ((dec, vd), (full, vf))]
    assert faces[1] == 134300 and faces[0] < 0.2 * faces[1]


def test_the_decimated_panda_steps_as_the_full_one(models):
    """Same physics, bit for bit: 500 steps from home with the same controls."""
    out = []
    for m in models:
        d = mujoco.MjData(m)
        mujoco.mj_resetDataKeyframe(m, d, m.keyframe("home").id)
        d.ctrl[:] = m.key_ctrl[0] + 0.05
        mujoco.mj_step(m, d, 500)
        out.append((d.qpos.copy(), d.qvel.copy(), d.qfrc_actuator.copy()))
    for a, b in zip(*out, strict=True):
        assert np.array_equal(a, b)
