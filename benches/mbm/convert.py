"""Converts VAMP's MotionBenchMaker Panda problems (MoveIt scene/request YAML pairs, from the
`vamp-planner` sdist's resources/panda/problems.tar.bz2) into one JSON file for benches/mbm.rs.

Usage: python convert.py PROBLEMS_DIR OUT_JSON

Each problem: {"set", "index", "start": [7], "goal": [7], "obstacles": [...]}, an obstacle
{"kind": "box" | "cylinder" | "sphere", "dims", "position", "orientation" (x, y, z, w)}, with
MoveIt's dimensions: box sizes (x, y, z), cylinder (height, radius), sphere (radius).
"""

import json
import os
import sys

import yaml

ARM = [f"panda_joint{i}" for i in range(1, 8)]


def arm_values(names, positions):
    by_name = dict(zip(names, positions))
    return [float(by_name[j]) for j in ARM]


def main(problems_dir, out):
    problems = []
    for set_name in sorted(os.listdir(problems_dir)):
        folder = os.path.join(problems_dir, set_name)
        requests = sorted(f for f in os.listdir(folder) if f.startswith("request"))
        for request_file in requests:
            index = request_file[len("request"):-len(".yaml")]
            with open(os.path.join(folder, request_file)) as f:
                request = yaml.safe_load(f)
            with open(os.path.join(folder, f"scene{index}.yaml")) as f:
                scene = yaml.safe_load(f)
            js = request["start_state"]["joint_state"]
            start = arm_values(js["name"], js["position"])
            goal_by_name = {
                c["joint_name"]: c["position"]
                for c in request["goal_constraints"][0]["joint_constraints"]
            }
            goal = [float(goal_by_name[j]) for j in ARM]
            obstacles = []
            for obj in scene["world"]["collision_objects"]:
                for prim, pose in zip(obj["primitives"], obj["primitive_poses"]):
                    obstacles.append(
                        {
                            "kind": prim["type"],
                            "dims": [float(d) for d in prim["dimensions"]],
                            "position": [float(p) for p in pose["position"]],
                            "orientation": [float(q) for q in pose["orientation"]],
                        }
                    )
            problems.append(
                {
                    "set": set_name,
                    "index": int(index),
                    "start": start,
                    "goal": goal,
                    "obstacles": obstacles,
                }
            )
    with open(out, "w") as f:
        json.dump(problems, f)
    print(f"{len(problems)} problems written to {out}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
