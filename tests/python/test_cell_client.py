"""A Python client of the cell protocol (grpcio + the generated stubs) driving cell-sim directly,
as a ROS 2 node or a lab script would: the contract is usable without laserfit's C++."""
import math
import os
import re
import subprocess

import grpc
import pytest

from laserfit.cell.v1 import cell_pb2 as pb
from laserfit.cell.v1 import cell_pb2_grpc as rpc

CTL = os.environ["LASERFIT_CONTROLLER_BIN"]
SRC = os.environ["LASERFIT_SOURCE_DIR"]
# The needle cell's sensing arm near its scan pose (cells/needle.yaml scan_near_deg), rad.
SCAN_NEAR = [math.radians(d) for d in (16, -15, -10, -138, 15, 124, -2)]


def quaternion(m):
    """w, x, y, z of the rotation in a row-major 4 x 4 (the largest component first, stable)."""
    r = [[m[4 * i + j] for j in range(3)] for i in range(3)]
    tr = r[0][0] + r[1][1] + r[2][2]
    if tr > 0:
        s = 2 * math.sqrt(1 + tr)
        q = [s / 4, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s]
    elif r[0][0] > r[1][1] and r[0][0] > r[2][2]:
        s = 2 * math.sqrt(1 + r[0][0] - r[1][1] - r[2][2])
        q = [(r[2][1] - r[1][2]) / s, s / 4, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s]
    elif r[1][1] > r[2][2]:
        s = 2 * math.sqrt(1 + r[1][1] - r[0][0] - r[2][2])
        q = [(r[0][2] - r[2][0]) / s, (r[0][1] + r[1][0]) / s, s / 4, (r[1][2] + r[2][1]) / s]
    else:
        s = 2 * math.sqrt(1 + r[2][2] - r[0][0] - r[1][1])
        q = [(r[1][0] - r[0][1]) / s, (r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, s / 4]
    n = math.sqrt(sum(v * v for v in q))
    return [v / n for v in q]


@pytest.fixture()
def cell():
    proc = subprocess.Popen([CTL, "cell-sim", "--listen", "127.0.0.1:0", "--cell",
                             f"{SRC}/cells/needle.yaml"], stdout=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    port = int(re.search(r"port (\d+)", line).group(1))
    channel = grpc.insecure_channel(f"127.0.0.1:{port}")
    yield rpc.CellStub(channel), rpc.SimulationStub(channel)
    channel.close()
    proc.terminate()
    proc.wait(timeout=10)


def test_hello_state_motion_sweep_judge(cell):
    c, sim = cell
    hello = c.Hello(pb.HelloRequest(protocol_version=1, client="pytest"), timeout=10)
    assert hello.protocol_version == 1 and hello.points_per_profile == 2048 and hello.simulated
    sim.BeginTrial(pb.TrialRequest(campaign_seed=1, trial=0), timeout=60)
    state = c.GetArmState(pb.ArmStateRequest(arm=pb.ARM_ASSEMBLING), timeout=10)
    assert len(state.q.q) == 7 and len(state.T_base_flange.m) == 16
    # Hold the flange where it is for 0.3 s at 1 kHz: the arm stays within 1 um.
    m = state.T_base_flange.m
    t = [m[3], m[7], m[11]]
    q = quaternion(m)
    done = c.Execute(pb.Trajectory(rate_hz=1000, samples=(t + q) * 300, q_ref=state.q),
                     timeout=30)
    assert done.ok, done.fault
    assert abs(done.duration_s - 0.3) < 1e-9
    after = c.GetArmState(pb.ArmStateRequest(arm=pb.ARM_ASSEMBLING), timeout=10).T_base_flange.m
    assert max(abs(after[k] - m[k]) for k in (3, 7, 11)) < 1e-3
    # A 6 mm sweep at 10 mm/s streams its profiles in order, each 2048 points, then its end.
    req = pb.SweepRequest(q_start=pb.Joints(q=SCAN_NEAR), direction=[0, 1, 0], length_mm=6,
                          speed_mm_s=10)
    profiles, end = 0, None
    for chunk in c.Sweep(req, timeout=60):
        if chunk.HasField("end"):
            end = chunk.end
            continue
        assert chunk.profile.index == profiles
        assert len(chunk.profile.x) == 2048 and len(chunk.profile.z) == 2048
        profiles += 1
    assert end is not None and end.fault == "" and end.profiles == profiles > 100
    assert abs(end.duration_s - 0.6) < 1e-9
    judged = sim.Judge(pb.JudgeRequest(), timeout=10)
    assert judged.moved


def test_a_request_out_of_the_arms_limits_is_refused(cell):
    c, sim = cell
    sim.BeginTrial(pb.TrialRequest(campaign_seed=1, trial=0), timeout=60)
    # Joint 4 of a Panda cannot be at 0 rad: the cell says why and sends no profile.
    req = pb.SweepRequest(q_start=pb.Joints(q=[0] * 7), direction=[0, 1, 0], length_mm=6,
                          speed_mm_s=10)
    chunks = list(c.Sweep(req, timeout=60))
    assert len(chunks) == 1 and "joint 4" in chunks[0].end.fault
    with pytest.raises(grpc.RpcError) as e:  # a malformed message: 6 joints
        c.Execute(pb.Trajectory(rate_hz=1000, samples=[0, 0, 0, 1, 0, 0, 0],
                                q_ref=pb.Joints(q=[0] * 6)), timeout=10)
    assert e.value.code() == grpc.StatusCode.INVALID_ARGUMENT
