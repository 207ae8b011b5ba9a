"""Furniture turned by a yaw, shelf ledges against any side, and part meshes from OBJ and ASCII STL files
(docs/workcell_format.md): the built geoms, the surfaces, what stands on them and the checks that follow."""

from __future__ import annotations

import math
import tomllib

import mujoco
import numpy as np
import pytest
from own_product import CELL, write_block_stl

from ergosim.errors import ConfigError
from ergosim.quat import from_yaw_deg
from ergosim.scenes import build_cell
from ergosim.scenes.cellfile import parse_cell
from ergosim.scenes.cellspec import Shelf, Table
from ergosim.scenes.export import export_cell
from ergosim.worker import Worker, make_subjects
from ergosim.worker.stance import area_of_cell

BENCH = '[furniture.bench]\ntype = "table"\ncenter = [0.62, 0.0]\nsize = [0.64, 1.0]\nheight = 0.9\n'


def _cell(tmp_path, old: str = "", new: str = "", name: str = "cell.toml"):
    """The bracket's workcell with ``old`` replaced by ``new``, parsed from a file in ``tmp_path``."""
    assert old in CELL, old
    path = tmp_path / name
    path.write_text(CELL.replace(old, new, 1))
    return parse_cell(tomllib.loads(path.read_text()), source=str(path))


def parse_cell_text(text: str):
    return parse_cell(tomllib.loads(text), source="cell.toml")


def _turn(yaw: float, x: float, y: float) -> tuple[float, float]:
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    return c * x - s * y, s * x + c * y


# -- a turned table --------------------------------------------------------------------------------------
def test_a_turned_table_turns_its_slab_legs_and_surface(tmp_path):
    spec = _cell(tmp_path, BENCH, BENCH + "yaw = 30.0\n")
    bench = spec.furniture[0]
    assert isinstance(bench, Table) and bench.yaw == 30.0
    surface = spec.surfaces()["bench"]
    assert surface.yaw == 30.0
    cell = build_cell(spec)
    m, d = cell.model, cell.data
    np.testing.assert_allclose(m.geom("bench").quat, from_yaw_deg(30.0), atol=1e-12)
    np.testing.assert_allclose(d.geom("bench").xpos[:2], (0.62, 0.0), atol=1e-12)
    # leg 0 stands 30 mm in from the slab's (+x, +y) corner of its own frame
    dx, dy = _turn(30.0, 0.32 - 0.03, 0.5 - 0.03)
    np.testing.assert_allclose(d.geom("bench_leg0").xpos[:2], (0.62 + dx, dy), atol=1e-12)
    np.testing.assert_allclose(m.geom("bench_leg0").quat, from_yaw_deg(30.0), atol=1e-12)
    # the surface's own frame: its long side runs at 30 deg
    ex, ey = _turn(30.0, 0.0, 0.48)
    assert surface.contains((0.62 + ex, ey))
    assert not surface.contains((0.62 + 0.30, 0.48))  # inside the unturned footprint, outside the turned one


def test_an_unturned_table_builds_without_a_geom_quaternion(tmp_path):
    """yaw = 0 (the default) leaves the geoms as they always were."""
    cell = build_cell(_cell(tmp_path))
    np.testing.assert_array_equal(cell.model.geom("bench").quat, [1.0, 0.0, 0.0, 0.0])


def test_a_part_on_a_turned_table_keeps_its_world_xy(tmp_path):
    """A part's xy is in the world frame; whether it is on the surface is asked in the surface's frame."""
    ex, ey = _turn(60.0, 0.0, 0.40)  # 0.40 m along the turned bench's long side
    xy = (round(0.62 + ex, 4), round(ey, 4))
    placed = f'xy = [{xy[0]}, {xy[1]}]\ninsert_axis = "z"'
    old = 'xy = [0.55, 0.20]\ninsert_axis = "z"'
    with pytest.raises(ConfigError, match=r"parts\.base\.xy: no surface under xy"):
        _cell(tmp_path, old, placed)  # off the unturned bench's 0.64 m width
    spec = parse_cell_text(CELL.replace(BENCH, BENCH + "yaw = 60.0\n").replace(old, placed))
    cell = build_cell(spec)
    np.testing.assert_allclose(cell.data.body("base").xpos, (xy[0], xy[1], 0.9 + 0.02), atol=1e-9)
    for _ in range(250):  # half a second: the block rests on the turned slab and stays where it was put
        mujoco.mj_step(cell.model, cell.data)
    np.testing.assert_allclose(cell.data.body("base").xpos, (xy[0], xy[1], 0.92), atol=2e-3)


def test_a_target_off_a_turned_table_is_refused(tmp_path):
    """Turned by 90 deg, the 0.64 x 1.0 m bench is 0.64 m wide along y: 0.45 m off its centre is off it."""
    old = '[targets.fixture]\non = "bench"\nxy = [0.45, 0.0]'
    moved = CELL.replace(old, '[targets.fixture]\non = "bench"\nxy = [0.62, 0.45]')
    parse_cell_text(moved)  # on the unturned bench, 1.0 m along y
    with pytest.raises(ConfigError, match=r"targets\.fixture\.xy: \(0.62, 0.45\) is not on the bench"):
        parse_cell_text(moved.replace(BENCH, BENCH + "yaw = 90.0\n"))


# -- overlaps and the standing area follow the yaw -------------------------------------------------------
def _furniture(name: str, **keys) -> str:
    """A workcell of a worker at the origin and the furniture ``name`` with ``keys`` (TOML values)."""
    return f'name = "c"\n[worker]\nxy = [0.0, 0.0]\n{_entry(name, **keys)}'


def _entry(name: str, **keys) -> str:
    return f"[furniture.{name}]\n" + "".join(f"{k} = {v}\n" for k, v in keys.items())


def _two(yaw: float):
    long = _furniture("long", center=[0.6, 0.0], size=[1.0, 0.2], height=0.9, yaw=yaw)
    return parse_cell_text(long + _entry("small", center=[1.0, 0.0], size=[0.2, 0.2], height=0.9))


def test_overlap_checks_use_the_turned_footprint():
    with pytest.raises(ConfigError, match="furniture 'long' and 'small' overlap"):
        _two(0.0)  # the long table reaches x = 1.1, over the small one
    spec = _two(90.0)  # turned, it spans x 0.5..0.7 only
    assert [round(float(y), 6) for _, _, y in spec.furniture[0].boxes()] == [90.0]
    with pytest.raises(ConfigError, match="furniture 'long' and 'small' overlap"):
        _two(20.0)  # a corner still over the small table: its axis-aligned test alone would say no


def test_the_standing_area_follows_a_turned_table():
    """A table 1.0 m long along its own x and 0.2 m wide, centred 0.9 m ahead: unturned it reaches back to
    0.4 m ahead of the worker; turned by 90 deg it runs across, 0.8-1.0 m ahead, and lets the worker step
    further forward."""
    def table(size, yaw):
        return parse_cell_text(_furniture("t", center=[0.9, 0.0], size=size, height=0.9, yaw=yaw))

    across, along, unturned = table([1.0, 0.2], 90.0), table([0.2, 1.0], 0.0), table([1.0, 0.2], 0.0)
    assert area_of_cell(across, 1.75) == area_of_cell(along, 1.75)  # one rectangle, said two ways
    assert area_of_cell(unturned, 1.75).x[1] < area_of_cell(across, 1.75).x[1] - 0.3


# -- shelf ledges against any side -----------------------------------------------------------------------
_SHELF = """{shelf}{extra}
[parts.p]
shape = "box"
size = [0.04, 0.04, 0.04]
mass = 0.1
on = "shelf_top"
xy = [{px}, {py}]
"""


def _shelf(extra: str, px: float, py: float, depth: float = 0.2):
    shelf = _furniture("shelf", type='"shelf"', center=[0.9, 0.3], size=[0.5, 0.8], height=1.4,
                       low_height=0.9, top_depth=depth)
    return parse_cell_text(_SHELF.format(shelf=shelf, extra=extra, px=px, py=py))


def test_the_default_ledge_is_against_minus_y():
    top, low = _shelf("", 0.9, 0.0).furniture[0].ledges()
    assert (top.center, top.size) == ((0.9, 0.3 - 0.4 + 0.1), (0.5, 0.2))
    assert (low.center, low.size) == ((0.9, 0.3), (0.5, 0.8))


def test_a_ledge_on_plus_x_builds_there(tmp_path):
    spec = _shelf('back = "+x"', 0.9 + 0.25 - 0.1, 0.3)
    shelf = spec.furniture[0]
    assert isinstance(shelf, Shelf) and shelf.back == "+x"
    top = spec.surfaces()["shelf_top"]
    np.testing.assert_allclose(top.center, (0.9 + 0.25 - 0.1, 0.3))
    assert top.size == (0.2, 0.8)
    cell = build_cell(spec)
    np.testing.assert_allclose(cell.data.geom("shelf_top").xpos, (1.05, 0.3, 1.4 - 0.015), atol=1e-12)
    np.testing.assert_allclose(cell.model.geom("shelf_top").size, (0.1, 0.4, 0.015), atol=1e-12)
    posts = sorted(tuple(np.round(cell.data.geom(f"shelf_post{i}").xpos[:2], 9)) for i in range(4))
    assert posts == sorted((round(x, 9), round(y, 9)) for x in (0.97, 1.13) for y in (-0.08, 0.68))
    np.testing.assert_allclose(cell.data.body("p").xpos, (1.05, 0.3, 1.42), atol=1e-9)
    with pytest.raises(ConfigError, match=r"parts\.p\.xy.*is not on the shelf_top"):
        _shelf('back = "+x"', 0.9, 0.0)  # on the -y ledge of the default, not on the +x one


def test_a_ledge_on_minus_x_of_a_turned_shelf(tmp_path):
    """back names a side of the shelf's own frame: -x turned by 90 deg is the world's -y side."""
    spec = _shelf('back = "-x"\nyaw = 90.0', 0.9, 0.15)
    top = spec.surfaces()["shelf_top"]
    np.testing.assert_allclose(top.center, (0.9, 0.3 - 0.15), atol=1e-12)
    assert top.yaw == 90.0 and top.size == (0.2, 0.8)
    build_cell(spec)


def test_top_depth_is_checked_across_the_side_it_covers():
    with pytest.raises(ConfigError, match="top_depth must leave >= 0.1 m"):
        _shelf('back = "+x"', 1.0, 0.3, depth=0.45)  # of 0.5 m along x (0.8 m along y would take it)


# -- meshes from OBJ and ASCII STL -----------------------------------------------------------------------
_CORNERS = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
_FACES = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6),
          (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]


def _block(half) -> np.ndarray:
    return np.array(_CORNERS, dtype=float) * np.asarray(half)


def write_obj(path, half=(0.02, 0.02, 0.015)) -> None:
    """A Wavefront OBJ of a box of ``half`` sizes [m] (8 vertices, 12 triangles; OBJ counts from 1)."""
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in _block(half)]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in _FACES]
    path.write_text("# a block\n" + "\n".join(lines) + "\n")


def write_ascii_stl(path, half=(0.02, 0.02, 0.015)) -> None:
    v = _block(half)
    out = ["solid block"]
    for f in _FACES:
        a, b, c = v[list(f)]
        n = np.cross(b - a, c - a)
        n /= np.linalg.norm(n)
        out += [f"  facet normal {n[0]:.6f} {n[1]:.6f} {n[2]:.6f}", "    outer loop"]
        out += [f"      vertex {p[0]:.6f} {p[1]:.6f} {p[2]:.6f}" for p in (a, b, c)]
        out += ["    endloop", "  endfacet"]
    path.write_text("\n".join(out + ["endsolid block"]) + "\n")


_BOX_PART = 'shape = "box"\nsize = [0.06, 0.06, 0.04]'


@pytest.mark.parametrize(("name", "writer"), [("block.obj", write_obj), ("block.stl", write_ascii_stl),
                                              ("binary.stl", write_block_stl)])
def test_a_mesh_part_builds_and_steps(tmp_path, name, writer):
    writer(tmp_path / name)
    mesh = f'shape = "mesh"\nfile = "{tmp_path / name}"\nsize = [0.08, 0.08, 0.06]\nscale = 2.0'
    spec = _cell(tmp_path, _BOX_PART, mesh)
    cell = build_cell(spec)
    m, d = cell.model, cell.data
    k = m.mesh("base_mesh").id
    verts = m.mesh_vert[m.mesh_vertadr[k]:m.mesh_vertadr[k] + m.mesh_vertnum[k]]
    # MuJoCo keeps a mesh in its principal axes of inertia, which may order the edges differently
    np.testing.assert_allclose(np.sort(verts.max(axis=0) - verts.min(axis=0)), (0.06, 0.08, 0.08), atol=1e-5)
    assert m.mesh_facenum[k] == 12
    for _ in range(500):
        mujoco.mj_step(m, d)
    assert np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel))
    np.testing.assert_allclose(d.body("base").xpos, (0.55, 0.20, 0.9 + 0.03), atol=2e-3)  # rests by its size


def test_an_ascii_stl_and_an_obj_give_the_binary_stls_body(tmp_path):
    """The same block through trimesh (OBJ, ASCII STL) and through MuJoCo's own reader (binary STL): the same
    mass and inertia."""
    bodies = []
    for name, writer in (("b.stl", write_block_stl), ("a.obj", write_obj), ("a.stl", write_ascii_stl)):
        writer(tmp_path / name)
        mesh = f'shape = "mesh"\nfile = "{tmp_path / name}"\nsize = [0.04, 0.04, 0.03]\ndensity = 2700.0'
        m = build_cell(_cell(tmp_path, _BOX_PART + "\nmass = 0.2", mesh)).model
        bodies.append((float(m.body("base").mass[0]), m.body("base").inertia.copy()))
    (mass, inertia), *others = bodies
    assert mass == pytest.approx(2700.0 * 0.04 * 0.04 * 0.03, rel=1e-4)
    for m_other, i_other in others:
        assert m_other == pytest.approx(mass, rel=1e-6)
        np.testing.assert_allclose(i_other, inertia, rtol=1e-5)


def test_the_workers_obstacles_turn_with_the_furniture(tmp_path):
    """The worker's IK sees a turned bench as a box turned by the bench's yaw less the worker's, in the
    worker's frame (ergosim.worker.motion.Worker.ik_for)."""
    turned = CELL.replace(BENCH, BENCH + "yaw = 30.0\n")
    spec = parse_cell_text(turned.replace('xy = [0.0, 0.0]\nhand', 'xy = [0.0, 0.0]\nyaw = 20.0\nhand'))
    assert spec.worker.yaw == 20.0
    cell = build_cell(spec)
    _, built = Worker(make_subjects(1, 0)[0]).ik_for(cell)
    obstacle = built.model.geom("obstacle_0")
    np.testing.assert_allclose(obstacle.quat, from_yaw_deg(10.0), atol=1e-9)
    origin = cell.body_pose("human_base")[0]
    x, y = _turn(-20.0, 0.62 - origin[0], 0.0 - origin[1])
    np.testing.assert_allclose(obstacle.pos[:2], (x, y), atol=1e-9)
    np.testing.assert_allclose(obstacle.size, (0.32, 0.5, 0.02), atol=1e-12)


def test_a_point_is_clamped_onto_a_turned_surface_in_its_own_frame():
    """Surface.clamp (the sensitivity study's moved parts): onto the turned footprint, not its world box."""
    bench = Table("bench", (0.0, 0.0), (1.0, 0.2), 0.9, yaw=90.0).surfaces()[0]
    x, y = bench.clamp((0.4, 0.3), margin=0.05)
    np.testing.assert_allclose((x, y), (0.05, 0.3), atol=1e-12)
    assert bench.contains((x, y), margin=0.05 - 1e-9)
    flat = Table("flat", (0.0, 0.0), (1.0, 0.2), 0.9).surfaces()[0]
    assert flat.clamp((0.7, 0.3), margin=0.05) == (0.45, 0.05)


def test_an_obj_part_exports_inside_the_mjcf(tmp_path):
    """ergosim export: a mesh given by its vertices is written into the MJCF, which loads in plain MuJoCo."""
    write_obj(tmp_path / "block.obj")
    mesh = f'shape = "mesh"\nfile = "{tmp_path / "block.obj"}"\nsize = [0.04, 0.04, 0.03]'
    written = export_cell(_cell(tmp_path, _BOX_PART, mesh), tmp_path / "out")
    assert not any(name.startswith("base_mesh") for name in written.assets)  # not a file in assets/
    m = mujoco.MjModel.from_xml_path(str(written.path))
    assert m.mesh_facenum[m.mesh("base_mesh").id] == 12
