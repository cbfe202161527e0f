#!/usr/bin/env python3
"""Solve the IK bench's targets with pink (Python Pinocchio + QP differential IK).

Run by `cargo bench --bench ik` with the bench venv's python (.deps/bench-venv, created by
setup.sh from scripts/bench-requirements.txt):

    ik_pink.py INPUT.json OUTPUT.json

INPUT holds the robot URDF path, the tool frame, the arm joints (root to tip), the seed
configuration (one angle per arm joint) and the Rust model's tool pose there (checked, so both
sides use the same frames), the targets (root_from_tool as x y z qx qy qz qw, in
the URDF root link's frame) and the solver settings of the Rust solver. OUTPUT gets, per
target, whether it converged and the wall-clock time of the solve (microseconds); the total
number of QP steps, the thread's CPU time over all solves (seconds) and the package versions.

The algorithm mirrors kinscene's IkSolver so that the comparison is about the implementation
(Python + pink + qpsolvers + Clarabel's Python binding versus Rust + Pinocchio through the shim
+ Clarabel.rs): each step is pink's QP for one FrameTask (position and orientation cost 1,
Levenberg-Marquardt damping `lm_damping * |e|^2` plus a Tikhonov floor `damping`, dt = 1 so
the velocity is the step) with pink's ConfigurationLimit (gain 1: q + dq within the limits)
and VelocityLimit set to `max_step` (|dq_i| <= max_step); solved by Clarabel through qpsolvers.
Converged when |p* - p| <= position_tolerance and |log(R* R^T)| <= rotation_tolerance. Restarts
from uniformly random configurations within the limits (continuous joints uniform in
[-pi, pi)) when an attempt stalls (less than 10 % error reduction over 10 steps) or runs out of
steps, up to `restarts`, all within `budget_s` of wall-clock time.
"""

import json
import os
import sys
import time
import warnings
from importlib.metadata import version

import numpy as np
import pinocchio as pin
import pink
from pink.limits import ConfigurationLimit, VelocityLimit
from pink.tasks import FrameTask

STALL_FACTOR = 0.9
STALL_WINDOW = 10


def main(input_path, output_path):
    with open(input_path) as f:
        spec = json.load(f)
    # urdfdom prints an error for every <capsule> collision element (URDF 1.0 has none); only
    # the kinematics is needed here, so silence the C++ parser's stderr while it runs.
    saved_stderr = os.dup(2)
    with open(os.devnull, "w") as devnull:
        os.dup2(devnull.fileno(), 2)
        try:
            model = pin.buildModelFromUrdf(spec["urdf"])
        finally:
            os.dup2(saved_stderr, 2)
            os.close(saved_stderr)
    # qpsolvers converts pink's dense P and G to CSC for Clarabel on every step and warns.
    warnings.filterwarnings("ignore", message="Converted matrix")
    data = model.createData()
    frame = spec["frame"]
    frame_id = model.getFrameId(frame)
    if frame_id >= model.nframes:
        raise SystemExit(f"frame {frame!r} not in the URDF model")

    # Arm joints: q index, nq (1 or 2 for a continuous joint's (cos, sin)), limits.
    joints = []
    for name in spec["joints"]:
        jid = model.getJointId(name)
        if jid >= model.njoints:
            raise SystemExit(f"joint {name!r} not in the URDF model")
        joint = model.joints[jid]
        lo = model.lowerPositionLimit[joint.idx_q]
        hi = model.upperPositionLimit[joint.idx_q]
        joints.append((joint.idx_q, joint.nq, lo, hi))

    def configuration_from_angles(angles):
        q = pin.neutral(model)
        for (idx_q, nq, _, _), angle in zip(joints, angles):
            if nq == 2:
                q[idx_q], q[idx_q + 1] = np.cos(angle), np.sin(angle)
            else:
                q[idx_q] = angle
        return q

    settings = spec["settings"]
    tol_p = settings["position_tolerance"]
    tol_r = settings["rotation_tolerance"]
    max_iterations = settings["max_iterations"]
    restarts = settings["restarts"]
    budget = settings["budget_s"]
    damping = settings["damping"]
    model.velocityLimit[:] = settings["max_step"]
    limits = [ConfigurationLimit(model, config_limit_gain=1.0), VelocityLimit(model)]
    task = FrameTask(
        frame, position_cost=1.0, orientation_cost=1.0, lm_damping=settings["lm_damping"]
    )
    # Clarabel as in the Rust solver: absolute gap tolerances off (see src/kinematics/ik/qp.rs).
    qp_options = {"tol_gap_abs": 0.0, "reduced_tol_gap_abs": 0.0}
    lower, upper = model.lowerPositionLimit, model.upperPositionLimit
    bounded = np.array([hi < 1e20 and hi > lo for lo, hi in zip(lower, upper)])
    seed = configuration_from_angles(spec["seed"])
    # Same frames as the Rust model: the tool pose at the seed must agree.
    pin.framesForwardKinematics(model, data, seed)
    expected = pin.XYZQUATToSE3(np.array(spec["seed_pose"]))
    mismatch = np.linalg.norm(pin.log6(expected.actInv(data.oMf[frame_id])).vector)
    if mismatch > 1e-9:
        raise SystemExit(f"tool pose at the seed differs from the Rust model's by {mismatch}")

    def random_configuration(rng):
        angles = []
        for _, nq, lo, hi in joints:
            if nq == 2 or not (hi < 1e20):
                angles.append(rng.uniform(-np.pi, np.pi))
            else:
                angles.append(rng.uniform(lo, hi))
        return configuration_from_angles(angles)

    def errors(configuration, target):
        pose = configuration.get_transform_frame_to_world(frame)
        ep = target.translation - pose.translation
        er = pin.log3(target.rotation @ pose.rotation.T)
        return ep, er

    steps = 0

    def solve(target):
        nonlocal steps
        deadline = time.perf_counter() + budget
        rng = np.random.default_rng(settings["seed"])
        task.set_target(target)
        for attempt in range(restarts + 1):
            q = seed.copy() if attempt == 0 else random_configuration(rng)
            configuration = pink.Configuration(model, data, q)
            history = []
            for step in range(max_iterations + 1):
                ep, er = errors(configuration, target)
                if np.linalg.norm(ep) <= tol_p and np.linalg.norm(er) <= tol_r:
                    return True
                if step == max_iterations:
                    break
                if time.perf_counter() >= deadline:
                    return False
                score = ep @ ep + er @ er
                history.append(score)
                if step >= STALL_WINDOW and np.sqrt(score) > STALL_FACTOR * np.sqrt(
                    history[step - STALL_WINDOW]
                ):
                    break
                velocity = pink.solve_ik(
                    configuration,
                    [task],
                    dt=1.0,
                    solver="clarabel",
                    damping=damping,
                    limits=limits,
                    safety_break=False,
                    **qp_options,
                )
                steps += 1
                q = pin.integrate(model, configuration.q, velocity)
                q[bounded] = np.clip(q[bounded], lower[bounded], upper[bounded])
                configuration.update(q)
        return False

    solved, times_us = [], []
    cpu_start = time.thread_time()
    for x, y, z, qx, qy, qz, qw in spec["targets"]:
        target = pin.XYZQUATToSE3(np.array([x, y, z, qx, qy, qz, qw]))
        start = time.perf_counter()
        ok = solve(target)
        times_us.append((time.perf_counter() - start) * 1e6)
        solved.append(bool(ok))
    cpu_s = time.thread_time() - cpu_start

    with open(output_path, "w") as f:
        json.dump(
            {
                "pink": version("pin-pink"),
                "pinocchio": pin.__version__,
                "qpsolvers": version("qpsolvers"),
                "clarabel": version("clarabel"),
                "solved": solved,
                "times_us": times_us,
                "steps": steps,
                "cpu_s": cpu_s,
            },
            f,
        )


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    main(sys.argv[1], sys.argv[2])
