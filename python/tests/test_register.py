"""laserfit.register on numpy arrays: the same pose as the CLI on the same data, clouds in other
units and from Open3D, bad input as laserfit.Error / ValueError. Tolerances are stated per test."""
import json
import os
import subprocess

import numpy as np
import open3d as o3d
import pytest

import laserfit
from conftest import pose_error


def quaternion(T):
    """(w, x, y, z) of a 4 x 4 pose's rotation (its angle is below 180 deg here)."""
    R = T[:3, :3]
    w = np.sqrt(max(1 + np.trace(R), 0)) / 2
    return [w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)]


def test_without_a_prior_a_twin_pose_is_not_ok(plug):
    # The plug is nearly symmetric under a half turn: with no q0 RANSAC may land on the twin;
    # laserfit must then not say ok (measured: ambiguous, 32 mm / 169 deg off).
    r = laserfit.register(plug["scan"], plug["ref"], ref_normals=plug["ref_normals"],
                          sensor_origin=plug["origin"])
    t_um, r_deg = pose_error(plug["T"], r.T_scan_ref)
    assert r.status != "ok" or (t_um < 50 and r_deg < 0.5), (r, t_um, r_deg)


def test_the_same_result_as_the_cli_on_the_same_data(plug):
    q0 = quaternion(plug["T"])  # the arm's belief of the orientation (the paper's q0)
    r = laserfit.register(plug["scan"], plug["ref"], ref_normals=plug["ref_normals"],
                          sensor_origin=plug["origin"], q0=q0)
    out = subprocess.run([os.environ["LASERFIT_BIN"], "register", "--json",
                          "--scan", str(plug["dir"] / "scan.pcd"),
                          "--ref", str(plug["dir"] / "ref.pcd"),
                          "--q0", " ".join(repr(float(x)) for x in q0)],
                         check=True, capture_output=True, text=True).stdout
    cli = json.loads(out)["results"][0]
    assert (cli["status"], cli["reason"]) == (r.status, r.reason)
    # Same floats in, same code: the same pose to the digits the JSON keeps (1e-12 mm).
    assert np.abs(np.array(cli["T_scan_ref"]["matrix"]) - r.T_scan_ref).max() < 1e-12
    assert abs(cli["inlier_rmse_um"] - r.inlier_rmse_mm * 1e3) < 1e-9


def test_a_box_corner_within_1_um_from_a_prior_in_metres(corner):
    prior = corner["T"].copy()
    prior[:3, 3] += [0.3, -0.2, 0.1]  # 0.37 mm off, refined without RANSAC
    kw = dict(refine_only=True, segment=False)
    mm = laserfit.register(corner["scan"], corner["ref"], ref_normals=corner["normals"],
                           sensor_origin=corner["origin"], prior=prior, **kw)
    t_um, r_deg = pose_error(corner["T"], mm.T_scan_ref)
    assert mm.status == "ok" and t_um < 1 and r_deg < 1e-3, (mm, t_um, r_deg)
    prior_m = prior.copy()
    prior_m[:3, 3] *= 1e-3  # the arm speaks metres; so do the clouds (float64: exact after x1000)
    m = laserfit.register(corner["scan"] * 1e-3, corner["ref"].astype(float) * 1e-3,
                          ref_normals=corner["normals"], sensor_origin=corner["origin"] * 1e-3,
                          prior=prior_m, unit="m", **kw)
    assert np.abs(m.T_scan_ref - mm.T_scan_ref).max() < 1e-9  # the pose in mm, as from mm


def test_open3d_ply_in_metres_reads_back_as_the_same_floats_and_pose(plug, tmp_path):
    pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(plug["scan"].astype(float) * 1e-3))
    path = str(tmp_path / "open3d.ply")
    assert o3d.io.write_point_cloud(path, pc)
    c = laserfit.read_cloud(path, unit="m")
    assert c["metadata"]["unit_converted_from"] == "m"
    assert np.array_equal(c["points"], plug["scan"])  # scaled in double, rounded once: exact
    a = laserfit.register(path, str(plug["dir"] / "ref.pcd"), unit="m",  # the ref file says mm
                          sensor_origin=plug["origin"] * 1e-3)
    b = laserfit.register(plug["scan"], plug["ref"], ref_normals=plug["ref_normals"],
                          sensor_origin=plug["origin"])
    assert np.abs(a.T_scan_ref - b.T_scan_ref).max() < 1e-12


def test_organized_arrays_keep_their_grid(plug, tmp_path):
    grid = np.full((4, 5, 3), np.nan, np.float32)
    grid[1, 2] = [1, 2, 3]
    laserfit.write_cloud(str(tmp_path / "g.ply"), grid)
    back = laserfit.read_cloud(str(tmp_path / "g.ply"))["points"]
    assert back.shape == (4, 5, 3) and np.array_equal(back[1, 2], grid[1, 2])


def test_bad_input_is_one_clear_error(plug, tmp_path):
    with pytest.raises(laserfit.Error, match="missing.pcd: no such file"):
        laserfit.register(str(tmp_path / "missing.pcd"), plug["ref"], ref_normals=plug["ref_normals"])
    with pytest.raises(ValueError, match="N x 3"):
        laserfit.register(plug["scan"][:, :2], plug["ref"], ref_normals=plug["ref_normals"])
    with pytest.raises(ValueError, match="needs normals"):
        laserfit.register(plug["scan"], plug["ref"])
    with pytest.raises(laserfit.Error, match="not the same unit"):  # metres taken as mm
        laserfit.register(plug["scan"] * 1e-3, plug["ref"], ref_normals=plug["ref_normals"])
    with pytest.raises(ValueError, match="rigid"):
        laserfit.register(plug["scan"], plug["ref"], ref_normals=plug["ref_normals"],
                          prior=np.ones((4, 4)))
