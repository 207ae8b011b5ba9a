"""Scene geometry read from an MjModel: what is drawn, where, in which colour, under which entity."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from ergosim.errors import ModelError
from ergosim.robot.assets import erd_file
from ergosim.robot.model import load_mjcf, model_dir
from ergosim.robot.panda import PANDA
from ergosim.viz import default_body_groups, scene_bodies, wxyz_to_xyzw

FINGER = erd_file("robots/panda_description/meshes/collision/finger.stl")
LINK3 = erd_file("robots/panda_description/meshes/collision/link3.stl")

MJCF = f"""
<mujoco model="viz test">
  <compiler angle="radian"/>
  <asset>
    <material name="red" rgba="1 0 0 1"/>
    <mesh name="finger" file="{FINGER}" scale="2 1 0.5"/>
    <mesh name="link3" file="{LINK3}"/>
    <mesh name="tet" vertex="0 0 0  0.1 0 0  0 0.1 0  0 0 0.1"/>
  </asset>
  <worldbody>
    <geom name="floor" type="plane" size="0 0 0.05"/>
    <geom name="bench" type="box" size="0.5 0.3 0.02" pos="0.4 0 0.7" material="red"/>
    <body name="shelf" pos="1 0 1" euler="0 0 0.5">
      <geom name="board" type="box" size="0.2 0.2 0.01" rgba="0.6 0.5 0.4 1"/>
    </body>
    <body name="human_upper_arm" pos="0 0.5 1.2" euler="0.2 0 0">
      <joint name="shoulder" type="hinge" axis="0 1 0"/>
      <geom name="arm" type="capsule" size="0.04 0.15" pos="0 0 -0.15" rgba="0.2 0.6 0.9 1"/>
      <geom name="arm_collision" type="sphere" size="0.05" group="3"/>
      <geom name="invisible" type="sphere" size="0.05" rgba="1 1 1 0"/>
    </body>
    <body name="part" pos="0.3 0.1 0.8">
      <freejoint/>
      <geom name="ball" type="sphere" size="0.03"/>
      <geom name="egg" type="ellipsoid" size="0.01 0.02 0.03"/>
      <geom name="rod" type="cylinder" size="0.01 0.05" euler="0 1.2 0"/>
      <geom name="tetra" type="mesh" mesh="tet"/>
    </body>
    <body name="panda_finger" pos="0 0 1" euler="0.3 0.2 0.1">
      <joint name="slide" type="slide"/>
      <geom name="finger" type="mesh" mesh="finger" pos="0.01 0.02 0.03" euler="0.1 0.2 0.3"/>
      <geom name="link3" type="mesh" mesh="link3" pos="-0.02 0.01 0.05" euler="-0.4 0.1 0.7"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture(scope="module")
def model() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(MJCF)


@pytest.fixture(scope="module")
def bodies(model):
    return {b.name: b for b in scene_bodies(model, default_body_groups(model, parts=("part",)))}


@pytest.fixture(scope="module")
def panda() -> mujoco.MjModel:
    return load_mjcf("models/panda/scene.xml")


def read_mesh(path) -> np.ndarray:
    """Vertices of a binary STL (3 per triangle) or an OBJ file [m]."""
    if path.suffix == ".obj":
        return np.array([line.split()[1:] for line in path.read_text().splitlines() if line.startswith("v ")],
                        dtype=float)
    raw = path.read_bytes()
    n = int(np.frombuffer(raw[80:84], "<u4")[0])
    record = np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    return np.frombuffer(raw[84:84 + 50 * n], dtype=record)["v"].reshape(-1, 3).astype(float)


def rotate(quat_wxyz, points) -> np.ndarray:
    return Rotation.from_quat(wxyz_to_xyzw(quat_wxyz).astype(float)).apply(points)


def test_groups_entities_and_static_bodies(bodies):
    assert {n: b.entity for n, b in bodies.items()} == {
        "world": "world/scene/world",
        "shelf": "world/scene/shelf",
        "human_upper_arm": "world/human/upper_arm",
        "part": "world/parts/part",
        "panda_finger": "world/robot/panda_finger",
    }
    assert bodies["world"].static_pose is not None and bodies["shelf"].static_pose is not None
    for moving in ("human_upper_arm", "part", "panda_finger"):
        assert bodies[moving].static_pose is None
    pos, quat = bodies["shelf"].static_pose
    np.testing.assert_allclose(pos, [1, 0, 1])
    np.testing.assert_allclose(quat, [np.cos(0.25), 0, 0, np.sin(0.25)], atol=1e-12)


def test_only_visible_geoms_are_drawn(bodies):
    kinds = {n: [(v.name, v.kind) for v in b.visuals] for n, b in bodies.items()}
    assert kinds["world"] == [("bench", "box")]  # the infinite floor plane is the viewer's grid
    assert kinds["human_upper_arm"] == [("arm", "capsule")]  # collision group 3 and alpha 0 are not drawn
    assert kinds["part"] == [("ball", "sphere"), ("egg", "ellipsoid"), ("rod", "cylinder"), ("tetra", "mesh")]


def test_colours_follow_material_or_geom(bodies):
    np.testing.assert_allclose(bodies["world"].visuals[0].rgba, [1, 0, 0, 1])
    np.testing.assert_allclose(bodies["shelf"].visuals[0].rgba, [0.6, 0.5, 0.4, 1], rtol=1e-6)


def test_primitive_poses_and_sizes(model, bodies):
    arm = bodies["human_upper_arm"].visuals[0]
    g = model.geom("arm").id
    np.testing.assert_allclose(arm.pos, [0, 0, -0.15])
    np.testing.assert_allclose(arm.quat, model.geom_quat[g])
    np.testing.assert_allclose(arm.size[:2], [0.04, 0.15])


def _check_file_meshes(model, bodies):
    """The mesh file's vertices, placed by the visual's pose and scale, land on MuJoCo's compiled vertices."""
    checked = 0
    for body in bodies:
        for v in body.visuals:
            if v.mesh_file is None:
                continue
            g = v.geom
            m = model.geom_dataid[g]
            compiled = model.mesh_vert[model.mesh_vertadr[m]:model.mesh_vertadr[m] + model.mesh_vertnum[m]]
            expected = rotate(model.geom_quat[g], compiled) + model.geom_pos[g]  # body frame
            placed = rotate(v.quat, read_mesh(v.mesh_file) * v.scale) + v.pos
            assert cKDTree(placed).query(expected)[0].max() < 1e-6
            assert cKDTree(expected).query(placed)[0].max() < 1e-6
            checked += 1
    return checked


def test_file_meshes_keep_their_file_and_land_where_mujoco_puts_them(model, bodies):
    finger = {v.name: v for v in bodies["panda_finger"].visuals}
    assert finger["finger"].mesh_file == FINGER and finger["link3"].mesh_file == LINK3
    np.testing.assert_allclose(finger["finger"].scale, [2, 1, 0.5])
    assert _check_file_meshes(model, bodies.values()) == 2


def test_panda_visual_meshes_are_the_model_files(panda):
    bodies = scene_bodies(panda, default_body_groups(panda))
    meshes = [v for b in bodies for v in b.visuals if v.kind == "mesh"]
    # link0..7, hand, two fingers in 26 OBJs, one per colour (the finger's two drawn twice): the visual class
    assert len(meshes) == 28
    assert {v.mesh_file.resolve().parent for v in meshes} == {(model_dir(PANDA) / "assets").resolve()}
    assert {v.mesh_file.suffix for v in meshes} == {".obj"}
    assert _check_file_meshes(panda, bodies) == 28


def test_meshes_without_a_file_use_compiled_vertices(model, bodies):
    tetra = bodies["part"].visuals[3]
    m = model.mesh("tet").id
    assert tetra.mesh_file is None
    np.testing.assert_array_equal(tetra.vertices, model.mesh_vert[model.mesh_vertadr[m]:][:4])
    assert tetra.faces.shape == (4, 3) and tetra.faces.max() == 3


def test_bad_body_groups_are_model_errors(model):
    with pytest.raises(ModelError, match="does not have"):
        scene_bodies(model, {"elbow": "human"})
    with pytest.raises(ModelError, match="expected one of robot, human, parts, scene"):
        scene_bodies(model, {"part": "tools"})
    clash = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><body name='human_arm'/><body name='arm'/></worldbody></mujoco>")
    with pytest.raises(ModelError, match="would both be drawn at world/human/arm"):
        scene_bodies(clash, {"human_arm": "human", "arm": "human"})


def test_quaternion_conversion_is_the_same_rotation():
    rng = np.random.default_rng(3)
    q = rng.normal(size=(20, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    for wxyz, xyzw in zip(q, wxyz_to_xyzw(q), strict=True):
        mat = np.empty(9)
        mujoco.mju_quat2Mat(mat, wxyz)
        np.testing.assert_allclose(Rotation.from_quat(xyzw.astype(float)).as_matrix(), mat.reshape(3, 3),
                                   atol=1e-6)
    with pytest.raises(ValueError, match=r"\(\.\.\., 4\)"):
        wxyz_to_xyzw(np.zeros(3))
