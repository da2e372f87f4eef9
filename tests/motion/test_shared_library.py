"""The shared BVH library (../shared/data/bvh-library): Bandai files as they are, ReActIdle files through the
shipped override entry (a Blender rig whose wrists are its forearms' End Sites). Skipped when absent."""

import numpy as np
import pytest
import yaml

from tests.helpers import ROOT
from voxpose import workflow_config as wc
from voxpose.io.bvh import read_bvh
from voxpose.motion import canon
from voxpose.motion.bvh_kinematics import forward_kinematics
from voxpose.motion.load import load_motion, resample, source_frame_rate
from voxpose.motion.reference_pose import reference_poses

MOTIONS = yaml.safe_load((ROOT / "config/config.yaml").read_text())["motions"]


def load(path):
    """``path`` loaded with the settings the workflow gives it (the shipped config's overrides)."""
    settings = wc.motion_settings(path.stem, MOTIONS)
    return load_motion(path, **{k: settings[k] for k in ("fps", "unit_scale", "joint_map", "drop_reference_frame")})


def test_library_bandai_files_load_as_they_are(shared_library_dir):
    files = sorted(shared_library_dir.glob("*_bandai*.bvh"))
    assert len(files) == 39
    for path in files:
        m = load(path)
        assert m.source["skeleton"] == "bandai" and m.source["dropped_frames"] == 0, path.name
        assert 1.4 <= m.height <= 2.1 and np.all(np.isfinite(m.angles)), path.name


@pytest.fixture(scope="module")
def reactidle(shared_library_dir):
    return {p.stem: (read_bvh(p), load(p)) for p in sorted(shared_library_dir.glob("idle_reactidle_*.bvh"))}


def test_reactidle_files_load_through_the_shipped_override(reactidle):
    assert len(reactidle) == 4
    for name, (bvh, m) in reactidle.items():
        assert m.source["skeleton"] == "config" and m.source["unit_from"] == "given", name
        assert m.source["dropped_frames"] == 0, name  # they start standing, arms down (below)
        assert 1.25 <= m.height <= 1.45, name  # small rigs in metres (000: hips 0.68 m up, 1.32 m tall)
        # the canonical wrists are the forearms' End Sites, resampled from 24 to 30 fps
        positions, _, sites = forward_kinematics(bvh)
        index = {j.name: i for i, j in enumerate(bvh.joints)}
        for side in "LR":
            wrist = resample(sites[index[f"forearm.{side}"]], source_frame_rate(bvh.frame_time), 30.0)
            assert np.allclose(m.positions[:, canon.INDEX[f"{side.lower()}wrist"]], wrist, atol=1e-12), name
        assert np.all(np.isfinite(m.angles)), name


def test_reactidle_first_frames_are_standing_not_a_reference_pose(reactidle):
    for name, (_, m) in reactidle.items():
        assert not reference_poses(m.positions[:10]).any(), name
        p = m.positions[0]
        down = p[canon.INDEX["root"]] - p[canon.INDEX["neck"]]
        for side in "lr":
            arm = p[canon.INDEX[f"{side}elbow"]] - p[canon.INDEX[f"{side}shoulder"]]
            cos = arm @ down / np.linalg.norm(arm) / np.linalg.norm(down)
            assert np.degrees(np.arccos(cos)) < 20.0, name  # the arms hang (10-13 degrees)
