"""Shared fixtures: a view of the USB plug (what a scanner sees of it) placed at a known pose, its
full-surface reference, and the files the CLI reads. Made by laserfit itself, seeded."""
import os
import pathlib

import numpy as np
import pytest

import laserfit

SOURCE = pathlib.Path(os.environ.get("LASERFIT_SOURCE_DIR", pathlib.Path(__file__).parents[2]))


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


@pytest.fixture(scope="session")
def plug(tmp_path_factory):
    v, f = laserfit.import_mesh(str(SOURCE / "cad" / "usb_a_plug.ply"))
    ref, ref_n = laserfit.refcloud(v, f, count=60000, seed=11)
    c = v.astype(float).mean(axis=0)
    eye = c + 95 * np.array([0.3, -0.5, 1.0]) / np.linalg.norm([0.3, -0.5, 1.0])
    z = (c - eye) / np.linalg.norm(c - eye)  # the sensor looks along its z at the plug
    x = np.cross([0, 1, 0], z)
    x /= np.linalg.norm(x)
    view = np.eye(4)
    view[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    view[:3, 3] = eye
    seen, _ = laserfit.refcloud(v, f, count=40000, seed=99, view=view)
    T = np.eye(4)
    T[:3, :3] = rotation([0, 0, 1], 0.35)
    T[:3, 3] = [512.3, -40.7, 101.9]
    scan = (seen.astype(float) @ T[:3, :3].T + T[:3, 3]).astype(np.float32)
    d = tmp_path_factory.mktemp("plug")
    origin = T[:3, :3] @ eye + T[:3, 3]
    laserfit.write_cloud(str(d / "scan.pcd"), scan, sensor_origin=origin)
    laserfit.write_cloud(str(d / "ref.pcd"), ref, normals=ref_n)
    return dict(scan=scan, ref=ref, ref_normals=ref_n, T=T, origin=origin, dir=d)


def pose_error(A, B):
    """(translation um, rotation deg) between two 4 x 4 poses."""
    D = np.linalg.inv(A) @ B
    c = np.clip((np.trace(D[:3, :3]) - 1) / 2, -1, 1)
    return np.linalg.norm(D[:3, 3]) * 1e3, np.degrees(np.arccos(c))


@pytest.fixture(scope="session")
def corner():
    """A box corner (three orthogonal faces: every DoF pinned) with normals, and the same points
    moved by a known pose as the scan (noise-free)."""
    u, v = np.meshgrid(np.arange(80) / 4.0, np.arange(40) / 4.0, indexing="ij")
    u, v, zero = u.ravel(), v.ravel(), np.zeros(u.size)
    faces = [(np.column_stack([u, v, zero]), [0, 0, 1]),   # floor, 20 x 10 mm
             (np.column_stack([zero, u / 2, v]), [1, 0, 0]),  # wall x = 0
             (np.column_stack([u, zero, v]), [0, 1, 0])]      # wall y = 0
    ref = np.vstack([p for p, _ in faces]).astype(np.float32)
    normals = np.vstack([np.tile(n, (len(p), 1)) for p, n in faces]).astype(np.float32)
    T = np.eye(4)
    T[:3, :3] = rotation([1, 2, 3], 0.087)
    T[:3, 3] = [1.0, -2.0, 0.5]
    scan = ref.astype(float) @ T[:3, :3].T + T[:3, 3]
    return dict(ref=ref, normals=normals, scan=scan, T=T, origin=T[:3, :3] @ [30, 30, 60] + T[:3, 3])
