"""Print the end angles (wrists, ankles, neck) and knee bends of every skeleton family, over all frames and at rest.

    python benchmarks/end_angles.py [--bvh DIR] [--library DIR] [--generated N]

Issue 18 item 2: the canonical angles must mean the same on every skeleton family. The ends (hand tips, toes,
head top) are where families differ, so this prints, per family (CMU, Bandai, the library's ReActIdle rig with
the config's joint map, the generated set), for the wrists, ankles, neck and knees: the bend (degrees between
the segment and its parent's T-pose direction: wrist = forearm -> hand tip against the forearm, ankle = ankle
-> toe against the shin's right angle, neck = neck -> head top against the pelvis frame's up, knee = shank against
the thigh) and the three Euler angles of y', as mean and sd over all frames of all files (resampled to 30 fps,
reference frames dropped, as the workflow loads them), then the same at rest (all BVH channels zero; for CMU
also its leading reference-pose frame), mean over files. Last, for the walks and jogs of each family with a toe
joint, the left ankle's flexion (Euler X) measured towards the mapped toe and towards the ball of the foot (the
toe joint, a landmark every such family places at the same anatomical point), at the source frame rate.
"""

import argparse
import tempfile
from collections import defaultdict
from pathlib import Path

import numpy as np
import yaml

from voxpose.io.bvh import read_bvh, write_bvh
from voxpose.motion import canon
from voxpose.motion.bvh_kinematics import forward_kinematics, rest_pose
from voxpose.motion.canonical_pose import canonical_pose, local_rotations
from voxpose.motion.generate import KINDS, default_motion
from voxpose.motion.joint_map import resolve_joint_map, skeleton_points
from voxpose.motion.load import load_motion
from voxpose.workflow_config import motion_settings

JOINTS = ("lwrist", "rwrist", "lankle", "rankle", "neck", "lknee", "rknee")
CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"
SHARED = Path(__file__).resolve().parents[2] / "shared" / "data"  # the shared data beside the checkout


def bends(rotations: np.ndarray) -> dict[str, np.ndarray]:
    """Per joint of ``JOINTS``: (F,) degrees between its segment and its parent's T-pose direction."""
    local = local_rotations(rotations)
    out = {}
    for name in JOINTS:
        j = canon.INDEX[name]
        t = canon.TPOSE_DIRECTIONS[j]
        cos = np.clip(local[:, j] @ t @ t, -1.0, 1.0)
        out[name] = np.degrees(np.arccos(cos))
    return out


def euler(angles: np.ndarray) -> dict[str, np.ndarray]:
    """Per joint of ``JOINTS``: (F, 3) its Euler angles of y'."""
    return {name: angles[:, 3 * canon.INDEX[name] : 3 * canon.INDEX[name] + 3] for name in JOINTS}


def rest_values(bvh, joint_map, frame=None):
    """Bends and Euler angles of the rest pose (all channels zero) or of ``frame`` of ``bvh``."""
    one = rest_pose(bvh) if frame is None else type(bvh)(bvh.joints, bvh.frame_time, bvh.motion[frame : frame + 1])
    jmap = resolve_joint_map(one, joint_map)
    joints, ends = skeleton_points(one, jmap, forward_kinematics(one))
    pose = canonical_pose(joints, ends)
    return bends(pose.rotations), euler(pose.angles)


BALLS = {"cmu": "LeftToeBase", "bandai": "Toes_L", "generated": "LeftToe"}


def ankle_flexion_to_ball(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Left ankle flexion (Euler X, degrees) towards the mapped toe and the toe joint, every frame but the first
    (CMU's reference frame)."""
    bvh = read_bvh(path)
    fk = forward_kinematics(bvh)
    joints, ends = skeleton_points(bvh, resolve_joint_map(bvh), fk)
    balls = ends.copy()
    balls[:, canon.ENDS.index("ltoe")] = fk[0][:, [j.name for j in bvh.joints].index(BALLS[family_of(path.stem)])]
    column = 3 * canon.INDEX["lankle"] + 1
    return tuple(canonical_pose(joints[1:], e[1:]).angles[:, column] for e in (ends, balls))


def family_of(name: str) -> str:
    for family in ("cmu", "bandai", "reactidle"):
        if f"_{family}" in name:
            return family
    return "generated"


def settings(name: str) -> dict:
    """The default config's loading settings for motion ``name`` (its ``motions.overrides`` applied)."""
    return motion_settings(name, yaml.safe_load(CONFIG.read_text())["motions"])


def generated_files(n: int, folder: Path) -> list[Path]:
    paths = []
    for i in range(n):
        kind = KINDS[i % len(KINDS)]
        path = folder / f"{kind}_gen_{i:02d}.bvh"
        write_bvh(default_motion(kind, i // len(KINDS), n_frames=150, seed=1), path)
        paths.append(path)
    return paths


def measure(paths):
    frames = defaultdict(lambda: defaultdict(list))  # family -> key -> arrays
    rest = defaultdict(lambda: defaultdict(list))
    for path in paths:
        family = family_of(path.stem)
        cfg = settings(path.stem)
        motion = load_motion(path, **cfg)
        b = bends(motion.rotations)
        e = euler(motion.angles)
        for name in JOINTS:
            frames[family][name, "bend"].append(b[name])
            frames[family][name, "euler"].append(e[name])
        bvh = read_bvh(path)
        poses = {"rest": None}
        if motion.source["dropped_frames"]:
            poses["ref frame 0"] = 0
        for label, frame in poses.items():
            rb, re = rest_values(bvh, cfg.get("joint_map"), frame)
            for name in JOINTS:
                rest[family, label][name, "bend"].append(rb[name])
                rest[family, label][name, "euler"].append(re[name])
    return frames, rest


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bvh", type=Path, default=SHARED / "bvh")
    parser.add_argument("--library", type=Path, default=SHARED / "bvh-library")
    parser.add_argument("--generated", type=int, default=10, help="generated motions (150 frames each)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        paths = sorted(args.bvh.glob("*.bvh")) + sorted(args.library.glob("*.bvh"))
        paths += generated_files(args.generated, Path(tmp))
        frames, rest = measure(paths)
        report(frames, rest, paths)


def report(frames, rest, paths):
    print("all frames: bend mean (sd) | Euler angles mean (sd), degrees")
    for family, table in frames.items():
        n = sum(len(a) for a in table[JOINTS[0], "bend"])
        print(f"\n{family} ({len(table[JOINTS[0], 'bend'])} files, {n} frames)")
        for name in JOINTS:
            b = np.concatenate(table[name, "bend"])
            e = np.concatenate(table[name, "euler"])
            eul = "  ".join(f"{m:6.1f} ({s:4.1f})" for m, s in zip(e.mean(0), e.std(0), strict=True))
            print(f"  {name:7s} bend {b.mean():5.1f} ({b.std():4.1f}) | {eul}")
    print("\nrest: bend mean over files [min-max] | Euler angles mean, degrees")
    for (family, label), table in rest.items():
        print(f"\n{family}, {label} ({len(table[JOINTS[0], 'bend'])} files)")
        for name in JOINTS:
            b = np.concatenate(table[name, "bend"])
            e = np.concatenate(table[name, "euler"])
            eul = "  ".join(f"{m:6.1f}" for m in e.mean(0))
            print(f"  {name:7s} bend {b.mean():5.1f} [{b.min():5.1f}-{b.max():5.1f}] | {eul}")
    print("\nleft ankle flexion (Euler X) in walks and jogs, towards the toe end | the ball (toe joint): mean (sd)")
    for family in BALLS:
        for kind in ("walk", "jog"):
            found = [p for p in paths if family_of(p.stem) == family and p.stem.startswith(kind + "_")]
            if found:
                toe, ball = (np.concatenate(a) for a in zip(*map(ankle_flexion_to_ball, found), strict=True))
                means = f"{toe.mean():6.1f} ({toe.std():4.1f}) | {ball.mean():6.1f} ({ball.std():4.1f})"
                print(f"  {family:9s} {kind:4s} {means}")


if __name__ == "__main__":
    main()
